"""Reference numbers for the free-flyer dynamics test (tests/free_flyer.rs).

A developer's script, run once; the crate and its tests never run it:

    python3 -m venv /tmp/pin && /tmp/pin/bin/pip install pin==4.1.0
    /tmp/pin/bin/python tools/reference/solo12_free_flyer.py > tests/data/solo12_free_flyer.json

It loads robots/solo12/solo12.urdf with Pinocchio's free-flyer root and writes,
for a few seeded random states, the generalized force (RNEA), the mass matrix
(CRBA), the joint torque regressor and the generalized force of two contact
wrenches (J_cᵀ w_c, one LOCAL, one LOCAL_WORLD_ALIGNED). Pinocchio's
conventions are momentlmi's (src/dynamics/free_flyer.rs): q = [p, quat (x, y,
z, w), joints], v = [v_lin, ω] in the base frame, force first. The regressor's
columns are converted from Pinocchio's parameter order (m, h, Ixx, Ixy, Iyy,
Ixz, Iyz, Izz) to the paper's (m, h, Ixx, Ixy, Ixz, Iyy, Iyz, Izz).
"""

import json
import os

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
URDF = os.path.join(HERE, "..", "..", "robots", "solo12", "solo12.urdf")
CONTACTS = [("FL_FOOT", "local"), ("HR_FOOT", "world_aligned")]


def paper_order(y):
    out = y.copy()
    for b in range(y.shape[1] // 10):
        out[:, 10 * b + 6], out[:, 10 * b + 7] = y[:, 10 * b + 7], y[:, 10 * b + 6]
    return out


def case(model, data, rng):
    q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
    q[:3] = rng.uniform(-1, 1, 3)
    v = rng.uniform(-2, 2, model.nv)
    a = rng.uniform(-5, 5, model.nv)
    tau = pin.rnea(model, data, q, v, a)
    m = pin.crba(model, data, q)
    m = np.triu(m) + np.triu(m, 1).T
    y = paper_order(pin.computeJointTorqueRegressor(model, data, q, v, a))
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    contacts, gen = [], np.zeros(model.nv)
    for name, frame in CONTACTS:
        ref = pin.LOCAL if frame == "local" else pin.LOCAL_WORLD_ALIGNED
        j = pin.getFrameJacobian(model, data, model.getFrameId(name), ref)
        w = rng.uniform(-20, 20, 6)
        gen += j.T @ w
        contacts.append({"frame": name, "expressed": frame, "wrench": w.tolist()})
    return {
        "q": q.tolist(),
        "v": v.tolist(),
        "a": a.tolist(),
        "tau": tau.tolist(),
        "mass_matrix": m.tolist(),
        "regressor": y.tolist(),
        "contacts": contacts,
        "contact_force": gen.tolist(),
    }


def main():
    model = pin.buildModelFromUrdf(URDF, pin.JointModelFreeFlyer())
    data = model.createData()
    rng = np.random.default_rng(40)
    np.random.seed(40)
    names = list(model.names)[2:]
    print(
        json.dumps(
            {
                "source": f"Pinocchio {pin.__version__}, tools/reference/solo12_free_flyer.py",
                "joints": names,
                "cases": [case(model, data, rng) for _ in range(3)],
            }
        )
    )


main()
