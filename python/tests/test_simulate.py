"""Simulation from Python gives the command line's samples for the same
arguments; bad arguments are errors."""

import numpy as np
import pytest

import momentlmi as m
from conftest import read_csv


def test_simulate_equals_the_command_line(cli, tmp_path):
    leg = m.Robot.builtin("cheetah3-leg")
    d = m.simulate(leg, 0.5, effects=["backlash"], seed=7)
    out = tmp_path / "s.csv"
    cli("simulate", "--robot", "cheetah3-leg", "--seconds", 0.5, "--effects", "backlash", "--seed", 7, "--out", out)
    t, q, qd, qdd, tau = read_csv(out, leg.joint_names)
    assert d["joints"] == leg.joint_names and d["q"].shape == (len(t), 3)
    for name, col in zip(("t", "q", "qd", "qdd", "tau"), (t, q, qd, qdd, tau)):
        assert np.array_equal(d[name], col), name
    # another seed, other noise
    assert not np.array_equal(m.simulate(leg, 0.5, effects=["backlash"], seed=8)["tau"], d["tau"])


def test_bad_simulations_are_errors():
    leg = m.Robot.builtin("cheetah3-leg")
    with pytest.raises(m.MomentlmiError, match="wobble"):
        m.simulate(leg, 1.0, effects=["wobble"])
    with pytest.raises(m.MomentlmiError):
        m.simulate(leg, -1.0)
