"""A real robot from Python: the KUKA LWR4+'s published runs (robots/kuka-lwr4,
NumPy archives read with numpy.load) identified on runs 1 and 2, held out on run 3,
then diagnosed. Run from the repository's root:

    python python/examples/kuka_lwr4.py
"""

import numpy as np

import momentlmi as m

KUKA = "robots/kuka-lwr4"
robot = m.Robot.from_urdf(f"{KUKA}/kuka_lwr4.urdf", sidecar=f"{KUKA}/kuka_lwr4.toml")


def run(k):
    """One run as recorded: time, joint positions and the torque sensors' readings
    (raw: filtered and differentiated as the command line does)."""
    z = np.load(f"{KUKA}/data/measurements_{k}.npz")
    return dict(t=z["times"], q=z["positions"], tau=z["torques"])


# the options docs/real-robot.md recommends for an arm with torque sensors and harmonic drives
r = m.identify(robot, [run(1), run(2)], validate=run(3), constraints="ellipsoid",
               friction="viscous,coulomb,offset,load,stribeck", regularizer="entropic", weight=1e-2)
print("held-out RMS per joint (N·m):", np.round(r["validation_rms"], 3), "mean", round(float(np.mean(r["validation_rms"])), 3))
print("every body physically consistent:", r["all_bodies_consistent"])

dg = m.diagnose(robot, run(3))
print("where the nominal model departs from run 3:")
for line in dg["summary"]:
    print("  " + line)
