#!/usr/bin/env python3
"""The exported models checked by MuJoCo itself (run by .ci/run in a
virtualenv with mujoco and numpy; docs/export.md).

For the built-in leg (three geared rotors), the Panda (fixed and locked
joints, STL meshes) and the KUKA LWR4+ (a real robot's URDF):
1. `momentlmi export --params true --urdf-out --mjcf-out`;
2. inverse dynamics: MuJoCo's `mj_inverse` on the written MJCF, with
   constraints (Coulomb `frictionloss`, limits, contacts) and damping off,
   equals `momentlmi predict --mujoco-view` (rigid bodies + armature) to
   1e-6 N·m on simulated motions; damping and frictionloss equal the
   exported sidecar's viscous and Coulomb friction;
3. round trip: `predict` on the written URDF + sidecar equals `predict` on
   the original robot to 1e-9 N·m, and `check` calls every body of the
   written URDF consistent;
4. forward: MuJoCo's `mj_step` from a recorded state under the recorded
   torques (the Panda without friction: the MJCF is then the whole model)
   stays within 1e-4 rad of the recorded motion for 0.2 s (each step's
   torque the mean of the samples at its ends; measured 2e-6 rad).
5. a floating base (Solo12, robots/solo12): the exported MJCF's free joint
   under `mj_inverse` equals `momentlmi predict` (base wrench and joint
   torques) to 1e-6, MuJoCo's free-joint conventions converted (qpos
   w x y z; linear velocity and acceleration in world axes, force in world
   axes; angular ones in the base's); the URDF round trip as in 3.

Usage: mujoco_check.py [path of the momentlmi binary]"""
import csv
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import mujoco
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "target/release/momentlmi"
ROBOTS = {
    "leg": ["--robot", "cheetah3-leg"],
    "panda": ["--robot", str(ROOT / "robots/panda/panda.urdf")],
    "kuka": ["--robot", str(ROOT / "robots/kuka-lwr4/kuka_lwr4.urdf")],
}


def run(*args, ok=(0,)):
    r = subprocess.run([str(BIN), *map(str, args)], capture_output=True, text=True)
    if r.returncode not in ok:
        sys.exit(f"momentlmi {' '.join(map(str, args))}: exit {r.returncode}\n{r.stderr}")
    return r


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array(rows[1:], dtype=float)


def columns(header, values, prefix, names):
    return values[:, [header.index(f"{prefix}_{n}") for n in names]]


def joint_names(m):
    return [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, i) for i in range(m.njnt)]


def inverse(xml, data, pred):
    """max |qfrc_inverse − predicted| over the samples (N·m)."""
    m = mujoco.MjModel.from_xml_path(str(xml))
    m.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    m.dof_damping[:] = 0
    d = mujoco.MjData(m)
    names = joint_names(m)
    h, a = read_csv(data)
    hp, p = read_csv(pred)
    q, qd, qdd = (columns(h, a, x, names) for x in ("q", "qd", "qdd"))
    tau = columns(hp, p, "tau", names)
    worst = 0.0
    for k in range(len(a)):
        d.qpos[:], d.qvel[:], d.qacc[:] = q[k], qd[k], qdd[k]
        mujoco.mj_inverse(m, d)
        worst = max(worst, float(np.abs(d.qfrc_inverse - tau[k]).max()))
    return worst


def friction_matches(xml, sidecar):
    """The MJCF's damping and frictionloss are the sidecar's viscous and Coulomb friction."""
    m = mujoco.MjModel.from_xml_path(str(xml))
    joints = {j["name"]: j for j in tomllib.loads(Path(sidecar).read_text()).get("joint", [])}
    for i, n in enumerate(joint_names(m)):
        j = joints[n]
        assert m.dof_damping[i] == j["viscous"] and m.dof_frictionloss[i] == j["coulomb"], n


def forward(xml, data, start=500, steps=200):
    """Largest |q_MuJoCo − q_recorded| (rad) over `steps` steps of 1 ms from
    sample `start`, the recorded torques applied, friction off."""
    m = mujoco.MjModel.from_xml_path(str(xml))
    m.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT | mujoco.mjtDisableBit.mjDSBL_LIMIT
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    m.dof_damping[:] = 0
    m.dof_frictionloss[:] = 0
    d = mujoco.MjData(m)
    names = joint_names(m)
    h, a = read_csv(data)
    q, qd, tau = (columns(h, a, x, names) for x in ("q", "qd", "tau"))
    d.qpos[:], d.qvel[:] = q[start], qd[start]
    worst = 0.0
    for k in range(start, start + steps):
        d.ctrl[:] = 0.5 * (tau[k] + tau[k + 1])  # the torque over the step, to O(dt²)
        mujoco.mj_step(m, d)
        worst = max(worst, float(np.abs(d.qpos - q[k + 1]).max()))
    return worst


def floating_inverse(xml, data, pred):
    """max |qfrc_inverse − predicted| (N, N·m) of a free-flyer's MJCF:
    momentlmi's base twist, its derivative and the base force are in base
    axes, MuJoCo's free joint has the linear ones in world axes."""
    m = mujoco.MjModel.from_xml_path(str(xml))
    m.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    m.dof_damping[:] = 0
    d = mujoco.MjData(m)
    assert m.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    names = joint_names(m)[1:]
    h, a = read_csv(data)
    hp, p = read_csv(pred)
    base = lambda hh, aa, cols: columns(hh, aa, "base", cols)
    pos, quat = base(h, a, ["x", "y", "z"]), base(h, a, ["qw", "qx", "qy", "qz"])
    v, w = base(h, a, ["vx", "vy", "vz"]), base(h, a, ["wx", "wy", "wz"])
    dv, dw = base(h, a, ["dvx", "dvy", "dvz"]), base(h, a, ["dwx", "dwy", "dwz"])
    q, qd, qdd = (columns(h, a, x, names) for x in ("q", "qd", "qdd"))
    force = base(hp, p, ["force_x", "force_y", "force_z"])
    moment = base(hp, p, ["moment_x", "moment_y", "moment_z"])
    tau = columns(hp, p, "tau", names)
    worst = 0.0
    for k in range(len(a)):
        r = np.zeros(9)
        mujoco.mju_quat2Mat(r, quat[k] / np.linalg.norm(quat[k]))
        r = r.reshape(3, 3)
        d.qpos[:] = np.concatenate([pos[k], quat[k], q[k]])
        d.qvel[:] = np.concatenate([r @ v[k], w[k], qd[k]])
        d.qacc[:] = np.concatenate([r @ (dv[k] + np.cross(w[k], v[k])), dw[k], qdd[k]])
        mujoco.mj_inverse(m, d)
        ours = np.concatenate([r @ force[k], moment[k], tau[k]])
        worst = max(worst, float(np.abs(d.qfrc_inverse - ours).max()))
    return worst


def floating(tmp):
    """Solo12 with its free-flying base: mj_inverse, and the URDF round trip."""
    robot = ["--robot", str(ROOT / "robots/solo12/solo12.urdf")]
    data, pred = tmp / "solo.csv", tmp / "solo_pred.csv"
    urdf, side, xml = tmp / "solo.urdf", tmp / "solo.toml", tmp / "solo.xml"
    run("simulate", *robot, "--seconds", 2, "--out", data)
    run("export", *robot, "--params", "true", "--urdf-out", urdf, "--mjcf-out", xml)
    run("predict", *robot, "--params", "true", "--data", data, "--out", pred)
    worst = floating_inverse(xml, data, pred)
    print(f"solo12: max |mj_inverse - predict| (free joint) = {worst:.2e}")
    assert worst <= 1e-6, worst
    round_trip("solo12", (urdf, side), data, pred, tmp / "solo_back.csv")


def round_trip(name, written, data, orig, back):
    """`predict` on the written URDF and sidecar equals `orig` (the original
    robot's prediction) to 1e-9."""
    urdf, side = written
    run("predict", "--robot", urdf, "--sidecar", side, "--params", "true", "--data", data, "--out", back)
    (h1, a1), (h2, a2) = read_csv(orig), read_csv(back)
    assert h1 == h2, (h1, h2)
    gap = float(np.abs(a1 - a2).max())
    print(f"{name}: URDF round trip, max difference {gap:.2e}")
    assert gap <= 1e-9, gap


def main():
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for name, robot in ROBOTS.items():
            data, pred = tmp / f"{name}.csv", tmp / f"{name}_pred.csv"
            urdf, side, xml = tmp / f"{name}.urdf", tmp / f"{name}.toml", tmp / f"{name}.xml"
            run("simulate", *robot, "--seconds", 2, "--noise", 0, "--out", data)
            run("export", *robot, "--params", "true", "--urdf-out", urdf, "--mjcf-out", xml)
            run("predict", *robot, "--params", "true", "--mujoco-view", "--data", data, "--out", pred)
            worst = inverse(xml, data, pred)
            print(f"{name}: max |mj_inverse - predict --mujoco-view| = {worst:.2e} N·m")
            assert worst <= 1e-6, worst
            friction_matches(xml, side)
            # round trip through the written URDF and sidecar
            orig = tmp / f"{name}_orig.csv"
            run("predict", *robot, "--params", "true", "--data", data, "--out", orig)
            round_trip(name, (urdf, side), data, orig, tmp / f"{name}_back.csv")
            run("check", urdf, "--package-path", ROOT / "robots/panda")
            if name == "panda":
                drift = forward(xml, data)
                print(f"{name}: mj_step under the recorded torques, 0.2 s: max |dq| = {drift:.2e} rad")
                assert drift <= 1e-4, drift
        floating(tmp)
    print("mujoco: ok")


if __name__ == "__main__":
    main()
