#!/usr/bin/env python3
"""Convert the sensor_msgs/JointState messages of a ROS bag to momentlmi's CSV.

momentlmi reads ROS 2 bags in MCAP directly (`--data run.mcap`). This script is
for the rest: ROS 1 bags (`.bag`) and ROS 2's SQLite storage (a `.db3` file or
its bag directory). It needs only the pure-Python `rosbags` package (no ROS):

    pip install rosbags
    python examples/convert_rosbag.py run.bag run.csv [--topic /joint_states]
    momentlmi identify --robot arm.urdf --data run.csv

The CSV has `t` (each message's header stamp, s; the log time when the stamp
is unset), and per joint `q_<joint>`, plus `qd_<joint>` and `tau_<joint>` when
the messages carry velocity and effort. It has no q̈, so momentlmi reads it as a
raw log and prepares it (docs/inputs.md). Joints are the union of the names of
the messages; a message that lacks one of them is an error.
"""
import argparse
import csv
import sys
from pathlib import Path

from rosbags.highlevel import AnyReader

JOINT_STATE = "sensor_msgs/msg/JointState"


def pick_topic(reader, topic):
    conns = [c for c in reader.connections if c.msgtype == JOINT_STATE]
    names = sorted({c.topic for c in conns})
    if topic is None:
        if len(names) != 1:
            sys.exit(f"error: JointState topics {names}: name one with --topic")
        topic = names[0]
    chosen = [c for c in conns if c.topic == topic]
    if not chosen:
        sys.exit(f"error: no JointState messages on {topic}; JointState topics: {names}")
    return chosen


def rows(reader, conns):
    for conn, log_time, raw in reader.messages(connections=conns):
        m = reader.deserialize(raw, conn.msgtype)
        s = m.header.stamp
        t = s.sec + 1e-9 * s.nanosec if (s.sec or s.nanosec) else 1e-9 * log_time
        yield t, list(m.name), list(m.position), list(m.velocity), list(m.effort)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bag", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--topic")
    a = ap.parse_args()
    with AnyReader([a.bag]) as reader:
        data = list(rows(reader, pick_topic(reader, a.topic)))
    if not data:
        sys.exit("error: no messages")
    joints = list(dict.fromkeys(n for d in data for n in d[1]))
    has_v = all(len(d[3]) == len(d[1]) for d in data)
    has_e = all(len(d[4]) == len(d[1]) for d in data)
    header = ["t"] + [f"q_{j}" for j in joints]
    header += [f"qd_{j}" for j in joints] if has_v else []
    header += [f"tau_{j}" for j in joints] if has_e else []
    tmp = a.out.with_suffix(a.out.suffix + ".part")
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for k, (t, names, q, v, e) in enumerate(data):
            at = {n: i for i, n in enumerate(names)}
            missing = [j for j in joints if j not in at]
            if missing:
                sys.exit(f"error: message {k + 1} lacks joint(s) {missing}")
            row = [t] + [q[at[j]] for j in joints]
            row += [v[at[j]] for j in joints] if has_v else []
            row += [e[at[j]] for j in joints] if has_e else []
            w.writerow(row)
    tmp.replace(a.out)  # written whole or not at all
    print(f"{a.out}: {len(data)} messages, joints {', '.join(joints)}")


if __name__ == "__main__":
    main()
