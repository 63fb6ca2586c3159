#!/usr/bin/env python3
"""Tests of the converter scripts (run by .ci/run in a virtualenv with rosbags
and pyarrow): each writes a log the way its tool does (a ROS 1 bag, a ROS 2
SQLite bag, a LeRobot dataset), converts it and compares the CSV with what
was written."""
import csv
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
NAMES = ["j2", "gripper", "j1"]  # the publisher's order; the CSV keeps it


def motion(n):
    t = 1.7e9 + 0.005 * np.arange(n) + 0.001 * np.sin(np.arange(n))
    q = np.stack([np.sin(t - 1.7e9), 0.01 + 0 * t, np.cos(t - 1.7e9)], 1)
    return t, q, 2 * q, 3 * q


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array(rows[1:], dtype=float)


def check(path, t, q, qd, tau, names):
    header, v = read_csv(path)
    want = ["t"] + [f"{p}_{j}" for p in ("q", "qd", "tau") for j in names]
    assert header == want, header
    assert np.allclose(v[:, 0], t, atol=2e-9, rtol=0), abs(v[:, 0] - t).max()
    k = len(names)
    for i, x in enumerate((q, qd, tau)):
        assert np.allclose(v[:, 1 + i * k : 1 + (i + 1) * k], x, atol=1e-6), i


def bags(d):
    from rosbags.rosbag1 import Writer as W1
    from rosbags.rosbag2 import Writer as W2
    from rosbags.typesys import Stores, get_typestore

    t, q, qd, tau = motion(300)
    for name, store, writer in [
        ("run.bag", Stores.ROS1_NOETIC, lambda p: W1(p)),
        ("run_ros2", Stores.ROS2_HUMBLE, lambda p: W2(p, version=8)),
    ]:
        ts = get_typestore(store)
        T = ts.types
        js = "sensor_msgs/msg/JointState"
        with writer(d / name) as w:
            c = w.add_connection("/joint_states", js, typestore=ts)
            for k in range(len(t)):
                sec = int(t[k])
                ns = int(round((t[k] - sec) * 1e9))
                hk = dict(stamp=T["builtin_interfaces/msg/Time"](sec=sec, nanosec=ns), frame_id="")
                if "seq" in T["std_msgs/msg/Header"].__dataclass_fields__:
                    hk["seq"] = k
                m = T[js](header=T["std_msgs/msg/Header"](**hk), name=NAMES,
                          position=q[k], velocity=qd[k], effort=tau[k])
                raw = ts.serialize_ros1(m, js) if name.endswith(".bag") else ts.serialize_cdr(m, js)
                w.write(c, int(t[k] * 1e9), raw)
        out = d / (name.split(".")[0] + ".csv")
        subprocess.run([sys.executable, HERE / "convert_rosbag.py", d / name, out], check=True)
        check(out, t, q, qd, tau, NAMES)
    r = subprocess.run([sys.executable, HERE / "convert_rosbag.py", d / "run.bag", d / "x.csv",
                        "--topic", "/nope"], capture_output=True, text=True)
    assert r.returncode != 0 and "/nope" in r.stderr and not (d / "x.csv").exists(), r.stderr


def lerobot(d):
    import pyarrow as pa
    import pyarrow.parquet as pq

    root = d / "lerobot"
    (root / "meta").mkdir(parents=True)
    (root / "data" / "chunk-000").mkdir(parents=True)
    feats = {f"observation.{k}": {"dtype": "float32", "shape": [3], "names": {"motors": NAMES}}
             for k in ("state", "velocity", "effort")}
    (root / "meta" / "info.json").write_text(json.dumps({"fps": 200, "features": feats}))
    t, q, qd, tau = motion(200)
    t = t - t[0]
    # two episodes in one file (v3 layout), the second's frames out of order
    ep = np.repeat([0, 1], 100)
    order = np.r_[0:100, 199:99:-1]
    table = pa.table({
        "timestamp": t[order] - np.where(ep == 1, t[100], 0),
        "episode_index": ep,
        "observation.state": [list(r) for r in q[order]],
        "observation.velocity": [list(r) for r in qd[order]],
        "observation.effort": [list(r) for r in tau[order]],
    })
    pq.write_table(table, root / "data" / "chunk-000" / "file-000.parquet")
    out = d / "episodes"
    subprocess.run([sys.executable, HERE / "convert_lerobot.py", root, out, "--deg",
                    "--rename", "j1=joint_1"], check=True)
    names = ["j2", "gripper", "joint_1"]
    r = np.pi / 180
    check(out / "episode_000000.csv", t[:100], r * q[:100], r * qd[:100], tau[:100], names)
    check(out / "episode_000001.csv", t[100:] - t[100], r * q[100:], r * qd[100:], tau[100:], names)


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as d:
        bags(Path(d))
        lerobot(Path(d))
    print("converters: ok")
