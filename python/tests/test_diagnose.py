"""The diagnosis of arrays is the command line's report of the same file."""

import json

import pytest

import momentlmi as m
from conftest import read_csv


def test_diagnose_equals_diagnose_json(cli, tmp_path):
    leg = m.Robot.builtin("cheetah3-leg")
    log = tmp_path / "backlash.csv"
    cli("simulate", "--robot", "cheetah3-leg", "--seconds", 5, "--effects", "backlash", "--seed", 3, "--out", log)
    t, q, qd, qdd, tau = read_csv(log, leg.joint_names)
    mine = m.diagnose(leg, dict(t=t, q=q, qd=qd, qdd=qdd, tau=tau))
    theirs = json.loads(cli("diagnose", "--robot", "cheetah3-leg", "--data", log, "--json").stdout)
    assert json.dumps(mine, sort_keys=True) == json.dumps(theirs, sort_keys=True)
    assert "backlash" in mine["accepted"], mine["accepted"]


def test_bad_diagnoses_are_errors(tmp_path):
    leg = m.Robot.builtin("cheetah3-leg")
    d = m.simulate(leg, 0.5)
    with pytest.raises(ValueError, match="repeats: 1 segments"):
        m.diagnose(leg, d, repeats=[d])
    with pytest.raises(m.MomentlmiError, match="nominal: .*missing.json"):
        m.diagnose(leg, d, nominal=tmp_path / "missing.json")


def test_nominal_data_as_the_command_line_takes_it(cli, tmp_path):
    leg = m.Robot.builtin("cheetah3-leg")
    logs = {}
    for name, seed in [("run", 5), ("own", 6)]:
        logs[name] = tmp_path / f"{name}.csv"
        cli("simulate", "--robot", "cheetah3-leg", "--seconds", 4, "--effects", "payload", "--seed", seed, "--out", logs[name])
    arrays = {k: dict(zip(["t", "q", "qd", "qdd", "tau"], read_csv(p, leg.joint_names))) for k, p in logs.items()}
    mine = m.diagnose(leg, arrays["run"], nominal="true", nominal_data=arrays["own"])
    theirs = json.loads(
        cli("diagnose", "--robot", "cheetah3-leg", "--nominal", "true", "--data", logs["run"],
            "--nominal-data", logs["own"], "--json").stdout
    )
    assert json.dumps(mine, sort_keys=True) == json.dumps(theirs, sort_keys=True)
    assert any("refit with the friction law" in w["message"] for w in mine["warnings"]), mine["warnings"]
