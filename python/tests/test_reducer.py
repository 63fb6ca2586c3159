"""The fleet path: parts reduced apart and merged equal one reduction of
the whole; the bytes round-trip and are checked; the solve equals the
command line's identification of the same file."""

import numpy as np
import pytest

import momentlmi as m
from conftest import read_csv


@pytest.fixture(scope="module")
def leg():
    return m.Robot.builtin("cheetah3-leg")


@pytest.fixture(scope="module")
def data(leg, leg_csv):
    return read_csv(leg_csv, leg.joint_names)


def test_four_merged_parts_equal_the_whole(leg, data):
    _, q, qd, qdd, tau = data
    whole = m.Reducer(leg).update(q, qd, qdd, tau)
    cuts = [0, 300, 301, 1200, len(q)]
    parts = [m.Reducer(leg).update(*(x[a:b] for x in (q, qd, qdd, tau))) for a, b in zip(cuts, cuts[1:])]
    merged = parts[0]
    for p in parts[1:]:
        merged.merge(m.Reducer.from_bytes(leg, p.to_bytes()))  # as if from another machine
    assert merged.samples == whole.samples == len(q)
    g, w = merged.gram(), whole.gram()
    assert np.abs(g - w).max() <= 1e-10 * np.abs(w).max()
    # the sums differ in their last bits (another order of addition); the
    # interior-point solve then agrees to its own tolerance
    a, b = merged.solve(), whole.solve()
    pa = np.array([bd["params"] for bd in a["bodies"]])
    pb = np.array([bd["params"] for bd in b["bodies"]])
    assert np.abs(pa - pb).max() <= 1e-6 * np.abs(pb).max()


def test_the_solve_equals_the_command_lines(leg, data, leg_csv, cli):
    import json

    _, q, qd, qdd, tau = data
    mine = m.Reducer(leg).update(q, qd, qdd, tau).solve("ellipsoid", 1e-6)
    theirs = json.loads(cli("identify", "--robot", "cheetah3-leg", "--data", leg_csv,
                            "--constraints", "ellipsoid", "--weight", "1e-6", "--json").stdout)
    assert mine["training_samples"] == theirs["training_samples"] == len(q)
    assert [b["name"] for b in mine["bodies"]] == [b["name"] for b in theirs["bodies"]]
    # the command line sums the file's blocks in another order: the solves
    # agree to the interior-point method's tolerance (the directions the
    # data do not excite are held by the prior's small weight alone)
    pa = np.array([b["params"] for b in mine["bodies"]])
    pb = np.array([b["params"] for b in theirs["bodies"]])
    assert np.abs(pa - pb).max() <= 1e-6 * np.abs(pb).max()
    assert np.allclose(mine["training_rms"], theirs["training_rms"], rtol=1e-9)
    assert mine["identifiability"]["rank"] == theirs["identifiability"]["rank"] and mine["status"] == theirs["status"] == "solved"
    # the same base parameters, in the same order, and the same unseen directions
    # (canonical: a pivoted QR chose 5 of 38 otherwise, by rounding; issue 58)
    named = lambda r: [b["combination"] for b in r["identifiability"]["base_parameters"]]
    assert named(mine) == named(theirs) and len(named(mine)) == 38
    assert mine["identifiability"]["directions"] == theirs["identifiability"]["directions"]


def test_bytes_are_checked(leg, data):
    _, q, qd, qdd, tau = data
    b = m.Reducer(leg).update(q[:50], qd[:50], qdd[:50], tau[:50]).to_bytes()
    with pytest.raises(m.IdentifyError, match="cut short"):
        m.Reducer.from_bytes(leg, b[:-5])
    with pytest.raises(m.IdentifyError, match="no MLMIRED mark"):
        m.Reducer.from_bytes(leg, b"PK" + b[2:])
    bumped = bytearray(b)
    bumped[8] = 9
    with pytest.raises(m.IdentifyError, match="format version 9"):
        m.Reducer.from_bytes(leg, bytes(bumped))
    with pytest.raises(m.IdentifyError, match="no samples yet"):
        m.Reducer(leg).to_bytes()


def test_bad_samples_are_value_errors(leg):
    r = m.Reducer(leg)
    z = np.zeros((3, 3))
    with pytest.raises(ValueError, match=r"tau: shape \(3, 2\)"):
        r.update(z, z, z, np.zeros((3, 2)))
    with pytest.raises(ValueError, match=r"qd|v: value inf"):
        r.update(z, np.full((3, 3), np.inf), z, z)
    with pytest.raises(ValueError, match="constraints: 'tight'"):
        r.update(z, z, z, z).solve("tight")
    assert r.samples == 3


def test_the_dask_example_merges_what_one_reducer_sums(tmp_path):
    """python/examples/fleet_dask.py on a small fleet (4 logs of 1 s, 2 workers), with
    only what `pip install` gives and Dask: no command line (none on the PATH, no
    MOMENTLMI_BIN, run from elsewhere than the repository)."""
    pytest.importorskip("dask.distributed", reason="Dask is not installed: the fleet example is not run")
    import os
    import subprocess
    import sys
    from pathlib import Path

    example = Path(__file__).resolve().parents[1] / "examples" / "fleet_dask.py"
    env = {k: v for k, v in os.environ.items() if k != "MOMENTLMI_BIN"}
    env["PATH"] = os.pathsep.join([os.path.dirname(sys.executable), "/usr/bin", "/bin"])
    r = subprocess.run([sys.executable, str(example), "--files", "4", "--seconds", "1", "--workers", "2"],
                       capture_output=True, text=True, env=env, timeout=300, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "4 files, 4000 samples; merged sums equal one reducer's" in r.stdout
    assert "status solved" in r.stdout and "| 2 Dask workers |" in r.stdout


def test_sums_that_overflow_or_merge_into_themselves_are_errors(leg):
    z = np.zeros((1, 3))
    big = np.array([[1.3e154, 0.0, 0.0]])  # each part finite, their sum not
    r = m.Reducer(leg).update(z, z, z, big)
    with pytest.raises(m.IdentifyError, match="not finite"):
        r.update(z, z, z, big)
    with pytest.raises(ValueError, match="into itself"):
        r.merge(r)
