"""Experiment design from Python: `excite` gives the command line's design
with its samples inside the limits, and `identify(bounds=…)` the parameters'
ranges beside the identifiability report."""

import json

import numpy as np
import pytest

import momentlmi as m
from conftest import read_csv


@pytest.fixture(scope="module")
def leg():
    return m.Robot.builtin("cheetah3-leg")


def test_excite_matches_the_command_line_and_keeps_the_limits(leg, cli, tmp_path):
    r = m.excite(leg, seconds=2, seeds=2, pool=5, rate_hz=200)
    s = r["samples"]
    assert s["t"].shape == (400,) and s["q"].shape == (400, 3) and s["qdd"].shape == (400, 3)
    for j, lim in enumerate(r["limits"]):
        lo, hi = lim["position"]
        assert lo <= s["q"][:, j].min() and s["q"][:, j].max() <= hi
        assert np.abs(s["qd"][:, j]).max() <= lim["velocity"]
        assert np.abs(s["qdd"][:, j]).max() <= lim["acceleration"]
    assert r["pool"]["designed"] <= r["pool"]["bound"] + 1e-6 * abs(r["pool"]["bound"])
    out = tmp_path / "ex.csv"
    text = cli("excite", "--robot", "cheetah3-leg", "--seconds", 2, "--seeds", 2, "--pool", 5,
               "--rate", 200, "--out", out, "--json")
    theirs = json.loads(text.stdout)
    assert theirs["value"] == pytest.approx(r["value"], rel=1e-12)
    t, q, qd, qdd, _ = read_csv(out, leg.joint_names)
    assert np.allclose(q, s["q"], atol=1e-9) and np.allclose(qdd, s["qdd"], atol=1e-6)
    with pytest.raises(ValueError, match="criterion"):
        m.excite(leg, criterion="x")
    with pytest.raises(m.IdentifyError, match="seconds"):
        m.excite(leg, seconds=-1)


def test_identify_reports_identifiability_and_bounds(leg):
    sim = m.simulate(leg, seconds=2, seed=1)
    r = m.identify(leg, sim, constraints="consistent", bounds="auto")
    ident = r["identifiability"]
    assert ident["rank"] == len(ident["base_parameters"]) < ident["columns"] == 66
    assert "abad.m" in ident["unidentifiable"]
    ranges = r["bounds"]["ranges"]
    assert len(ranges) == 66
    for p in ranges:
        if p["min"] is not None and p["max"] is not None:
            assert p["min"] <= p["estimate"] * (1 + 1e-6) + 1e-9 and p["estimate"] <= p["max"] * (1 + 1e-6) + 1e-9
    with pytest.raises(ValueError, match="bounds"):
        m.identify(leg, sim, bounds=-1.0)
