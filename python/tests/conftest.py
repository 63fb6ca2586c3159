"""Shared helpers: the command line (for comparisons) and simulated leg data."""

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


def cli_binary():
    """The `momentlmi` command: $MOMENTLMI_BIN, else the workspace's release build."""
    b = os.environ.get("MOMENTLMI_BIN") or str(ROOT / "target" / "release" / "momentlmi")
    return b if os.path.isfile(b) else shutil.which("momentlmi")


@pytest.fixture(scope="session")
def cli():
    b = cli_binary()
    if b is None:
        pytest.skip("the momentlmi command is not built (cargo build --release -p momentlmi-cli; or set MOMENTLMI_BIN)")

    def run(*args, ok=(0,)):
        r = subprocess.run([b, *map(str, args)], capture_output=True, text=True)
        assert r.returncode in ok, r.stderr
        return r

    return run


@pytest.fixture(scope="session")
def leg_csv(tmp_path_factory, cli):
    """Two seconds of the simulated leg at 1 kHz (a prepared CSV: t, q, qd, qdd, tau)."""
    out = tmp_path_factory.mktemp("leg") / "leg.csv"
    cli("simulate", "--robot", "cheetah3-leg", "--seconds", 2, "--out", out)
    return out


def read_csv(path, joints):
    """The CSV's columns as arrays: t (N,), q, qd, qdd, tau (N, n) (None: not in the file)."""
    data = np.genfromtxt(path, delimiter=",", names=True)
    have = data.dtype.names
    col = lambda p: np.column_stack([data[f"{p}_{j}"] for j in joints]) if f"{p}_{joints[0]}" in have else None
    return data["t"], col("q"), col("qd"), col("qdd"), col("tau")


def json_differences(mine, theirs, path="", rel=1e-6, abs_=1e-9, skip=()):
    """Where two JSON values differ, field by field: numbers by more than `rel` relative
    or `abs_` absolute, anything else at all; `skip` the paths (regular expressions, as
    `/bodies[0]/params[3]`) not compared."""
    import re

    if any(re.fullmatch(s, path) for s in skip):
        return []
    if isinstance(mine, dict) and isinstance(theirs, dict):
        if set(mine) != set(theirs):
            return [(path, "keys", sorted(set(mine) ^ set(theirs)))]
        return [d for k in mine for d in json_differences(mine[k], theirs[k], f"{path}/{k}", rel, abs_, skip)]
    if isinstance(mine, list) and isinstance(theirs, list):
        if len(mine) != len(theirs):
            return [(path, "length", len(mine), len(theirs))]
        return [d for k, (a, b) in enumerate(zip(mine, theirs))
                for d in json_differences(a, b, f"{path}[{k}]", rel, abs_, skip)]
    numbers = (int, float)
    if isinstance(mine, numbers) and isinstance(theirs, numbers) and not isinstance(mine, bool) and not isinstance(theirs, bool):
        close = abs(mine - theirs) <= max(abs_, rel * max(abs(mine), abs(theirs)))
        return [] if close else [(path, mine, theirs)]
    return [] if mine == theirs else [(path, mine, theirs)]


#: What a report of the same identification may differ in between the command line
#: and Python: the times, and the data's names (a file's path; "data" for arrays).
NOT_COMPARED = (r"/(total|solve|reduce)_time_s", r"/timings/.*", r"/data_preparation/(training|validation)\[\d+\]/path")
