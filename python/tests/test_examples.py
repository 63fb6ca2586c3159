"""The examples of python/examples run from the repository's root and print
what they promise."""

import subprocess
import sys

import pytest

from conftest import ROOT


def run(name, *args):
    r = subprocess.run([sys.executable, str(ROOT / "python" / "examples" / name), *args],
                       capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_the_leg_example_identifies_at_every_level():
    out = run("leg.py")
    for level in ("none", "semi", "consistent", "ellipsoid"):
        assert f"\n{level} " in out
    assert "ellipsoid   [0.3" in out and "6/6" in out


def test_the_leg_example_draws_fig_4(tmp_path):
    pytest.importorskip("matplotlib", reason="Matplotlib is not installed: the figure is not drawn")
    png = tmp_path / "fig4.png"
    assert "wrote" in run("leg.py", "--plot", str(png))
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000


def test_the_urdf_example_checks_the_panda(tmp_path):
    out = run("check_urdf.py", "robots/panda/panda.urdf", "--repair", str(tmp_path / "p.urdf"))
    assert out.count(" kg ") == 13 and "wrote" in out


def test_the_kuka_example_reads_the_real_runs():
    out = run("kuka_lwr4.py")
    assert "mean 0.3" in out and "every body physically consistent: True" in out
    assert out.count("lwr_") >= 7
