#!/usr/bin/env python3
"""SDPLIB: momentlmi against CVXPY + Clarabel, measured in one run.

A measurement tool, not a dependency of the crate. For each SDPA file it
alternates, `--rounds` times, one `momentlmi sdpa FILE --json` (its reported
setup_time_s + solve_time_s: compile, Clarabel's setup, the solve and, with
the verified decomposition, the check) and one CVXPY solve of the same
problem with Clarabel (the wall time of `Problem.solve`, which includes
CVXPY's compilation to Clarabel's form, and Clarabel's own `solve_time` from
`solver_stats`, which counts Clarabel's setup and solve), and
prints the medians as a Markdown table. Alternating keeps the two sides
under the same machine load and speed (the machine's speed drifts).

Set-up (a scratch virtualenv; versions of the table in docs/benchmarks.md):

    python3 -m venv /tmp/cvx && /tmp/cvx/bin/pip install cvxpy clarabel==0.11.1
    cargo build --release
    /tmp/cvx/bin/python benches/reference/sdplib_cvxpy.py ../shared/sdplib/*.dat-s

Both sides use Clarabel's default settings for tolerances (1e-8) and its
chordal decomposition on; momentlmi's default also checks a decomposed
answer against the original problem (docs/inputs.md, `--decomposition`).
"""

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import time

import cvxpy as cp
import numpy as np
import scipy.sparse as sp


def read_sdpa(path):
    """(c, blocks, entries) of an SDPA sparse file; entries are
    (matrix, block, i, j, value) with 0-based block, i, j."""
    lines = []
    with open(path) as f:
        for line in f:
            s = line.strip()
            if not s or s[0] in '"*':
                continue
            lines.append(s)
    numbers = lambda s: [x for x in re.split(r"[\s,(){}]+", s) if x]
    m = int(numbers(lines[0])[0])
    nblocks = int(numbers(lines[1])[0])
    blocks = [int(float(x)) for x in numbers(lines[2])[:nblocks]]
    rest = lines[3:]
    c = []
    while len(c) < m:
        c += [float(x) for x in numbers(rest.pop(0))]
    entries = []
    for s in rest:
        t = numbers(s)
        if len(t) >= 5:
            entries.append((int(t[0]), int(t[1]) - 1, int(t[2]) - 1, int(t[3]) - 1, float(t[4])))
    return np.array(c[:m]), blocks, entries


def cvxpy_problem(c, blocks, entries):
    """min cᵀx s.t. Σ xᵢ Fᵢ − F₀ ⪰ 0 per block (≥ 0 for a diagonal block)."""
    m = len(c)
    x = cp.Variable(m)
    per_block = [[] for _ in blocks]
    for e in entries:
        per_block[e[1]].append(e)
    cons = []
    for size, es in zip(blocks, per_block):
        n = abs(size)
        rows, cols, vals = [], [], []
        f0 = np.zeros(n * n if size > 0 else n)
        for mat, _, i, j, v in es:
            pairs = [(i, j)] if (i == j or size < 0) else [(i, j), (j, i)]
            for a, b in pairs:
                r = a * n + b if size > 0 else a
                if mat == 0:
                    f0[r] += v
                else:
                    rows.append(r)
                    cols.append(mat - 1)
                    vals.append(v)
        A = sp.csr_matrix((vals, (rows, cols)), shape=(len(f0), m))
        expr = A @ x - f0
        if size > 0:
            X = cp.reshape(expr, (n, n), order="C")
            cons.append(0.5 * (X + X.T) >> 0)
        else:
            cons.append(expr >= 0)
    return cp.Problem(cp.Minimize(c @ x), cons)


def run_cvxpy(path):
    prob = cvxpy_problem(*read_sdpa(path))
    t0 = time.perf_counter()
    prob.solve(solver=cp.CLARABEL)
    wall = time.perf_counter() - t0
    return {
        "status": prob.status,
        "objective": prob.value,
        "wall_s": wall,
        "clarabel_s": prob.solver_stats.solve_time,
    }


def run_ours(binary, path, extra):
    out = subprocess.run(
        [binary, "sdpa", path, "--json", *extra], capture_output=True, text=True
    )
    if out.returncode not in (0, 1):
        raise RuntimeError(f"{path}: momentlmi exited {out.returncode}: {out.stderr.strip()}")
    v = json.loads(out.stdout)
    v["time_s"] = v["setup_time_s"] + v["solve_time_s"]
    return v


def fmt(x):
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "—"
    return f"{x:.8g}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--binary", default=os.path.join("target", "release", "momentlmi"))
    ap.add_argument("--extra", default="", help="more momentlmi flags, e.g. '--max-memory-gib 10'")
    a = ap.parse_args()
    print(f"cvxpy {cp.__version__}, clarabel {__import__('clarabel').__version__}, "
          f"{a.rounds} rounds, {time.strftime('%Y-%m-%d %H:%M')}", file=sys.stderr)
    print("| problem | momentlmi objective | decomposition | momentlmi compile+setup+solve [s] "
          "| CVXPY objective | CVXPY status | CVXPY solve() [s] | of it Clarabel setup+solve [s] | ratio |")
    print("|---|---|---|---|---|---|---|---|---|")
    for path in a.files:
        ours, theirs = [], []
        for _ in range(a.rounds):
            ours.append(run_ours(a.binary, path, a.extra.split()))
            theirs.append(run_cvxpy(path))
        o, t = ours[-1], theirs[-1]
        ot = statistics.median(r["time_s"] for r in ours)
        tw = statistics.median(r["wall_s"] for r in theirs)
        tc = statistics.median(r["clarabel_s"] for r in theirs)
        name = os.path.basename(path).removesuffix(".dat-s")
        print(f"| {name} | {fmt(o['primal_objective'])} ({o['status']}) | {o['decomposition']} | {ot:.3g} "
              f"| {fmt(t['objective'])} | {t['status']} | {tw:.3g} | {tc:.3g} | {ot / tw:.2f} |",
              flush=True)


if __name__ == "__main__":
    main()
