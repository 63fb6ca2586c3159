#!/usr/bin/env python3
"""Convert a LeRobot dataset's episodes to momentlmi's CSV, one file per episode.

LeRobot datasets (v2 and v3 layouts) keep frames in Parquet files under `data/`
(columns `timestamp`, `episode_index`, and list columns such as
`observation.state`) and the joints' names in `meta/info.json`. Needs `pyarrow`:

    pip install pyarrow
    python examples/convert_lerobot.py path/to/dataset out/ [--deg]
    momentlmi identify --robot arm.urdf --data out/episode_000000.csv --data out/episode_000001.csv

Each CSV has `t` (the frame's timestamp, s) and per joint `q_<joint>` from
`--q` (default `observation.state`), `qd_<joint>` from `--qd` and `tau_<joint>`
from `--tau` (defaults `observation.velocity`, `observation.effort`, when the
dataset has them). Identification needs torques: a dataset without efforts
serves `predict` only. `--deg` converts positions and velocities from degrees
(SO-100/101 arms record degrees). Joint names must be the URDF's: rename them
with `--rename old=new` (repeatable). Given together, each episode is its own
segment: no filter crosses from one to the next.
"""
import argparse
import csv
import json
import math
import sys
from pathlib import Path

import pyarrow.parquet as pq


def joint_names(info, column):
    feat = info.get("features", {}).get(column)
    if feat is None:
        sys.exit(f"error: meta/info.json has no feature '{column}'")
    names = feat.get("names")
    if isinstance(names, dict):  # {"motors": [...]} in some datasets
        names = next(iter(names.values()))
    if not names:
        names = [f"joint{k}" for k in range(feat["shape"][0])]
    return list(names)


def episodes(root, columns):
    files = sorted((root / "data").rglob("*.parquet"))
    if not files:
        sys.exit(f"error: no Parquet files under {root / 'data'}")
    out = {}
    for f in files:
        t = pq.read_table(f, columns=["timestamp", "episode_index"] + columns)
        cols = {c: t.column(c).to_pylist() for c in t.column_names}
        for k, e in enumerate(cols["episode_index"]):
            out.setdefault(e, []).append([cols[c][k] for c in ["timestamp"] + columns])
    return out


def write_episode(path, header, frames, scales):
    tmp = path.with_suffix(".csv.part")
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for t, *vals in sorted(frames, key=lambda r: r[0]):
            row = [t]
            for v, s in zip(vals, scales):
                row += [x * s for x in v]
            w.writerow(row)
    tmp.replace(path)  # written whole or not at all


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dataset", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--q", default="observation.state")
    ap.add_argument("--qd", default="observation.velocity")
    ap.add_argument("--tau", default="observation.effort")
    ap.add_argument("--deg", action="store_true")
    ap.add_argument("--rename", action="append", default=[])
    a = ap.parse_args()
    info = json.loads((a.dataset / "meta" / "info.json").read_text())
    feats = info.get("features", {})
    rename = dict(r.split("=", 1) for r in a.rename)
    joints = [rename.get(j, j) for j in joint_names(info, a.q)]
    chosen = [(a.q, "q", True)] + [(c, p, False) for c, p in [(a.qd, "qd"), (a.tau, "tau")] if c in feats]
    header = ["t"] + [f"{p}_{j}" for _, p, _ in chosen for j in joints]
    scales = [math.pi / 180 if a.deg and p != "tau" else 1.0 for _, p, _ in chosen]
    if not any(p == "tau" for _, p, _ in chosen):
        print(f"warning: no '{a.tau}' feature: the CSVs have no torques (predict only)", file=sys.stderr)
    a.out.mkdir(parents=True, exist_ok=True)
    for e, frames in sorted(episodes(a.dataset, [c for c, _, _ in chosen]).items()):
        path = a.out / f"episode_{e:06d}.csv"
        write_episode(path, header, frames, scales)
        print(f"{path}: {len(frames)} frames")


if __name__ == "__main__":
    main()
