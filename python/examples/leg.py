"""The paper's experiment on the Cheetah 3 leg from Python: simulate training and
held-out data, identify at each constraint level, compare on the held-out data
(the bars of the paper's Fig. 4; `momentlmi demo` draws the paper's figures
themselves). Run from anywhere:

    python python/examples/leg.py [--plot leg_levels.png]

With --plot (and Matplotlib installed) the held-out RMS per joint and level is
drawn into that PNG.
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

    x = np.arange(leg.dof)
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for k, level in enumerate(levels):
        ax.bar(x + (k - 1.5) * 0.2, rms[level], width=0.2, label=level)
    ax.set_xticks(x, leg.joint_names)
    ax.set_ylabel("held-out torque RMS (N·m)")
    ax.legend(title="constraints")
    fig.tight_layout()
    fig.savefig(a.plot, dpi=120)
    print("wrote", a.plot)
