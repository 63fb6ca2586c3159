"""The paper's experiment on the Cheetah 3 leg from Python: simulate training and
held-out data, identify at each constraint level, compare on the held-out data.
Run from anywhere:

    python python/examples/leg.py [--plot fig4.png]

With --plot (and Matplotlib installed) the paper's Fig. 4 is drawn into that PNG:
the held-out torques measured and predicted by the model identified at the
ellipsoid level, joint by joint (`momentlmi demo` draws it as fig4_validation.svg).
"""

import argparse

import numpy as np

import momentlmi as m

ap = argparse.ArgumentParser()
ap.add_argument("--plot", help="a PNG file for the figure (needs matplotlib)")
a = ap.parse_args()

leg = m.Robot.builtin("cheetah3-leg")
train = m.simulate(leg, 10.0, seed=1)  # 10,000 samples at 1 kHz, σ = 0.3 N·m
held_out = m.simulate(leg, 5.0, seed=2)

levels = ["none", "semi", "consistent", "ellipsoid"]
rms = {}
print(f"{'level':<11} {'held-out RMS per joint (N·m)':<32} consistent bodies")
for level in levels:
    r = m.identify(leg, train, validate=held_out, constraints=level)
    rms[level] = r["validation_rms"]
    ok = sum(b["consistent"] for b in r["bodies"])
    print(f"{level:<11} {str(np.round(rms[level], 3)):<32} {ok}/{len(r['bodies'])}")

if a.plot:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tau = leg.predict(r, held_out["q"], held_out["qd"], held_out["qdd"])  # r: the ellipsoid level's
    fig, axes = plt.subplots(leg.dof, 1, figsize=(7, 6), sharex=True)
    for j, ax in enumerate(axes):
        ax.plot(held_out["t"], held_out["tau"][:, j], lw=0.6, color="0.6", label="measured")
        ax.plot(held_out["t"], tau[:, j], lw=0.9, color="C0", label="predicted (ellipsoid)")
        ax.set_ylabel(f"{leg.joint_names[j]} (N·m)")
    axes[0].legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time (s)")
    fig.suptitle("Held-out torques (Fig. 4)")
    fig.tight_layout()
    fig.savefig(a.plot, dpi=120)
    print("wrote", a.plot)
