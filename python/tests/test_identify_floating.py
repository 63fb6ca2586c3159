"""A floating-base robot (Solo12, the repository's) identified from Python as the
command line identifies it: from the files, from their columns in a DataFrame, or
from Python's own simulation of the same log, the same report to 1e-9; the options a floating base does not take are refused by
name, and the functions for a fixed base refuse a floating one."""

import json
import pickle

import numpy as np
import pandas as pd
import pytest

import momentlmi as m
from conftest import ROOT, json_differences

URDF = ROOT / "robots" / "solo12" / "solo12.urdf"
SIDECAR = ROOT / "robots" / "solo12" / "solo12.toml"


@pytest.fixture(scope="module")
def solo():
    return m.Robot.from_urdf(URDF, sidecar=SIDECAR)


@pytest.fixture(scope="module")
def logs(tmp_path_factory, cli):
    """20 s on the harness to fit, 5 s held out (the command line's simulator)."""
    d = tmp_path_factory.mktemp("solo")
    for name, seconds, seed in (("train", 20, 1), ("val", 5, 2)):
        cli("simulate", "--robot", URDF, "--seconds", seconds, "--seed", seed, "--out", d / f"{name}.csv")
    return d / "train.csv", d / "val.csv"


def cli_json(cli, train, val, *options):
    r = cli("identify", "--robot", URDF, "--data", train, "--validate", val, *options, "--json", ok=(0, 1))
    return json.loads(r.stdout)


def test_the_sidecar_or_the_flag_makes_the_root_free():
    assert m.Robot.from_urdf(URDF, sidecar=SIDECAR).floating_base
    assert m.Robot.from_urdf(URDF, floating_base=True).floating_base
    assert not m.Robot.from_urdf(URDF).floating_base
    with pytest.raises(TypeError, match="floating_base"):
        m.Robot.from_urdf(URDF, floating_base="yes")


@pytest.mark.parametrize("rows, constraints", [("base", "consistent"), ("all", "ellipsoid")])
def test_files_give_the_command_lines_report(solo, logs, cli, rows, constraints):
    train, val = logs
    mine = m.identify(solo, str(train), validate=val, rows=rows, constraints=constraints)
    theirs = cli_json(cli, train, val, "--rows", rows, "--constraints", constraints)
    assert theirs["floating_base"] and theirs["rows"] == rows
    assert json_differences(dict(mine), theirs, rel=1e-9, abs_=1e-12) == []


def test_columns_give_what_their_file_gives(solo, logs, cli):
    train, val = logs
    frame = pd.read_csv(train)
    mine = m.identify(solo, frame, validate=val, rows="base", constraints="consistent")
    as_dict = m.identify(solo, {c: frame[c].to_numpy() for c in frame.columns}, validate=val,
                         rows="base", constraints="consistent")
    theirs = cli_json(cli, train, val, "--rows", "base", "--constraints", "consistent")
    assert json_differences(dict(mine), theirs, rel=1e-9, abs_=1e-12) == []
    assert json_differences(dict(as_dict), theirs, rel=1e-9, abs_=1e-12) == []


def test_a_floating_robot_pickles_as_itself(solo):
    again = pickle.loads(pickle.dumps(solo))
    assert again.floating_base and again.body_names == solo.body_names


def test_options_and_logs_a_floating_base_does_not_take_are_named(solo, logs):
    train, _ = logs
    for option in ({"cutoff_hz": 5.0}, {"bounds": "auto"}, {"weight": "auto"}, {"friction": "auto"},
                   {"velocity": "file"}):
        with pytest.raises(ValueError, match=f"{next(iter(option))}.*not available for a floating base"):
            m.identify(solo, str(train), **option)
    with pytest.raises(ValueError, match="rows: 'wheels'"):
        m.identify(solo, str(train), rows="wheels")
    frame = pd.read_csv(train)
    with pytest.raises(ValueError, match="force_base_link_x"):
        m.identify(solo, frame.drop(columns=["force_base_link_x"]))
    with pytest.raises(ValueError, match="column 'base_x' has shape"):
        m.identify(solo, {"t": frame["t"].to_numpy(), "base_x": np.zeros((len(frame), 2))})
    with pytest.raises(TypeError, match="DataFrame or a dict of columns"):
        m.identify(solo, 3)
    with pytest.raises(ValueError, match="rows is for a floating base"):
        m.identify("cheetah3-leg", {"t": [0.0]}, rows="base")
    with pytest.raises(ValueError, match=r"a fixed-base log \(joints, q"):
        m.identify(solo, {"t": [0.0, 0.1], "q": np.zeros((2, 12)), "joints": solo.joint_names})


def test_simulate_gives_the_command_lines_log_as_columns(solo, logs, cli):
    train, val = logs
    columns = m.simulate(solo, 20, seed=1)
    assert list(columns) == pd.read_csv(train, nrows=1).columns.tolist()
    mine = m.identify(solo, columns, validate=val, rows="base", constraints="consistent")
    theirs = cli_json(cli, train, val, "--rows", "base", "--constraints", "consistent")
    assert json_differences(dict(mine), theirs, rel=1e-9, abs_=1e-12) == []
    with pytest.raises(ValueError, match="effects: .*'ripple'.*joint_friction"):
        m.simulate(solo, 1.0, effects="ripple")
    with pytest.raises(ValueError, match="params: a floating base"):
        m.simulate(solo, 1.0, effects="payload", params={"payload_mass": 1.0})


def test_the_fixed_base_functions_refuse_a_floating_base(solo):
    z = np.zeros((2, solo.dof))
    calls = (lambda: solo.rnea(z, z, z), lambda: m.Reducer(solo), lambda: m.excite(solo),
             lambda: m.diagnose(solo, "x.csv"))  # (the refusal before the data are read)
    for call in calls:
        with pytest.raises(ValueError, match="solo.*has a floating base"):
            call()
