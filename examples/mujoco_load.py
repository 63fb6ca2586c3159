#!/usr/bin/env python3
"""Loads a model `momentlmi export --mjcf-out` wrote into MuJoCo, prints what
its joints hold, and steps it for one second under zero joint torque
(docs/export.md). Needs `pip install mujoco`.

Usage: mujoco_load.py MODEL.xml"""
import sys

import mujoco

model = mujoco.MjModel.from_xml_path(sys.argv[1])
data = mujoco.MjData(model)
for i in range(model.njnt):
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, i)
    dof = model.jnt_dofadr[i]
    print(f"{name:<16} armature {model.dof_armature[dof]:.4g}  damping "
          f"{model.dof_damping[dof]:.4g}  frictionloss {model.dof_frictionloss[dof]:.4g}")
data.ctrl[:] = 0.0  # joint torques (N·m): the robot falls under gravity
while data.time < 1.0:
    mujoco.mj_step(model, data)
print("q after 1 s:", " ".join(f"{x:.3f}" for x in data.qpos))
