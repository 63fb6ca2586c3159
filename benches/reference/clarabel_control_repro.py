#!/usr/bin/env python3
"""Clarabel's chordal decomposition ending "optimal" at a wrong optimum.

A reproducer for Clarabel 0.11.1 (docs/benchmarks.md, "A reproducer: the
control family"); a measurement tool, not part of the crate. Random instances
of SDPLIB's control-problem structure

    maximise λ  s.t.  [ AᵀP + PA − Cᵀ diag(d) C   PB      ] − λ I ⪰ 0,   P ⪰ I
                      [ BᵀP                       diag(d) ]

are solved through CVXPY with Clarabel, decomposition off and on, and the
seeds whose two "optimal" values differ by more than 1e-4 (relative) are
printed. Variants (third argument, comma-separated): noC (no Cᵀ diag(d) C),
first (P ⪰ I before the big block), diagPI (diag(P) ≥ 1 instead of P ⪰ I),
trace (tr P = n instead), soc (a second-order cone on P's first column
instead). A fourth argument is a JSON dict of Clarabel settings for the
decomposed solve, e.g. '{"equilibrate_enable": false}'.

    python3 -m venv /tmp/cvx && /tmp/cvx/bin/pip install cvxpy clarabel==0.11.1
    /tmp/cvx/bin/python benches/reference/clarabel_control_repro.py 5 40
"""

import json
import sys

import cvxpy as cp
import numpy as np


def control(n, rng, variant, scale=50.0):
    A, B, C = (rng.uniform(-1, 1, (n, n)) * scale for _ in range(3))
    P = cp.Variable((n, n), symmetric=True)
    d = cp.Variable(n)
    lam = cp.Variable()
    top = A.T @ P + P @ A
    if "noC" not in variant:
        top = top - C.T @ cp.diag(d) @ C
    M = cp.bmat([[top, P @ B], [B.T @ P, cp.diag(d)]]) - lam * np.eye(2 * n)
    big = 0.5 * (M + M.T) >> 0
    second = {
        "diagPI": cp.diag(P) >= 1,
        "trace": cp.trace(P) == n,
        "soc": cp.SOC(P[0, 0], P[1:, 0]),
    }
    other = next((c for k, c in second.items() if k in variant), P - np.eye(n) >> 0)
    cons = [other, big] if "first" in variant else [big, other]
    return cp.Problem(cp.Maximize(lam), cons)


def main():
    n, count = int(sys.argv[1]), int(sys.argv[2])
    variant = sys.argv[3].split(",") if len(sys.argv) > 3 else []
    opts = json.loads(sys.argv[4]) if len(sys.argv) > 4 else {}
    bad = 0
    for seed in range(count):
        p = control(n, np.random.default_rng(seed), variant)
        # settings are passed explicitly both times: CVXPY may reuse a cached
        # Clarabel solver and its settings between solves of one problem
        p.solve(solver=cp.CLARABEL, chordal_decomposition_enable=False)
        v0, s0 = p.value, p.status
        p.solve(solver=cp.CLARABEL, chordal_decomposition_enable=True, **opts)
        v1, s1 = p.value, p.status
        if s0 == s1 == "optimal" and abs(v1 - v0) > 1e-4 * (1 + abs(v0)):
            bad += 1
            print(f"seed {seed}: off {v0:.8f}, decomposed {v1:.8f} ({s1})", flush=True)
    print(f"n = {n} {','.join(variant)}: {bad} of {count} wrong")


if __name__ == "__main__":
    main()
