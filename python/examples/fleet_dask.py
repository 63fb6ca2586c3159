"""Fleet-scale identification on Dask: many logs reduced in parallel by the workers
of a cluster, their sums merged, one SDP solved.

    python python/examples/fleet_dask.py [--files 8] [--seconds 10] [--workers 2]
        [--data DIR]

It needs what `pip install ./python` installs and Dask (`pip install
"dask[distributed]"`, the package's `fleet` extra); not the command line. Without
--data, the logs are simulated first by `momentlmi.simulate` (one robot, a run per
seed) and written as the command line's prepared CSV. Each Dask task reads one CSV log (NumPy), reduces it with
`momentlmi.Reducer` and returns its sums as bytes (`to_bytes`: 73 kB for the
leg, whatever the log's length); the client merges them (`from_bytes`, `merge`) and
solves once. The example checks that the merged sums equal one reducer's over every
file (to 1e-10) and prints the throughput in samples per second.

A LocalCluster stands for a real one: with `Client("scheduler-address:8786")` the
same code runs on many machines, each reading the files it can reach.
"""

import argparse
import os
import sys
import tempfile
import time

import numpy as np

import momentlmi

ROBOT = "cheetah3-leg"


def read_log(path, joints):
    """A prepared CSV log's q, qd, qdd and tau, each (N, n)."""
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    col = lambda p: data[:, [header.index(f"{p}_{j}") for j in joints]]
    return col("q"), col("qd"), col("qdd"), col("tau")


def reduce_file(path):
    """One task: a log reduced to its sums (bytes) and its sample count."""
    robot = momentlmi.Robot.builtin(ROBOT)
    r = momentlmi.Reducer(robot).update(*read_log(path, robot.joint_names))
    return r.to_bytes(), r.samples


def simulate(folder, files, seconds):
    """`files` runs of the robot (seeds 1, 2, …) written as prepared CSV logs (t, then
    q_, qd_, qdd_, tau_<joint>), as `momentlmi simulate --out` writes them."""
    robot = momentlmi.Robot.builtin(ROBOT)
    header = ["t"] + [f"{p}_{j}" for p in ("q", "qd", "qdd", "tau") for j in robot.joint_names]
    paths = []
    for k in range(files):
        d = momentlmi.simulate(robot, seconds, seed=k + 1)
        out = os.path.join(folder, f"run_{k:03d}.csv")
        rows = np.column_stack([d["t"], d["q"], d["qd"], d["qdd"], d["tau"]])
        np.savetxt(out, rows, delimiter=",", header=",".join(header), comments="", fmt="%.17g")
        paths.append(out)
    return paths


def fleet(paths, workers):
    """The sums of every file, reduced by `workers` Dask worker processes; the time it took."""
    from dask.distributed import Client, LocalCluster

    robot = momentlmi.Robot.builtin(ROBOT)
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
        client.submit(reduce_file, paths[0]).result()  # the workers warm (imports, robot)
        t0 = time.perf_counter()
        futures = client.map(reduce_file, paths, pure=False)
        total = momentlmi.Reducer(robot)
        for data, _ in client.gather(futures):
            total.merge(momentlmi.Reducer.from_bytes(robot, data))
        return total, time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--files", type=int, default=8)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--workers", type=int, nargs="+", default=[2])
    ap.add_argument("--data", help="a folder of prepared CSV logs (default: simulated)")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        if a.data:
            paths = sorted(os.path.join(a.data, f) for f in os.listdir(a.data) if f.endswith(".csv"))
        else:
            paths = simulate(tmp, a.files, a.seconds)
        robot = momentlmi.Robot.builtin(ROBOT)
        t0 = time.perf_counter()
        one = momentlmi.Reducer(robot)
        for p in paths:
            one.update(*read_log(p, robot.joint_names))
        single_s = time.perf_counter() - t0
        rows = [("1 (this process, no Dask)", one.samples / single_s)]
        for w in a.workers:
            total, seconds = fleet(paths, w)
            g, ref = total.gram(), one.gram()
            err = np.abs(g - ref).max() / np.abs(ref).max()
            if total.samples != one.samples or not err <= 1e-10:
                sys.exit(f"error: the merged sums differ from one reducer's: {err:.1e} ({total.samples} samples)")
            rows.append((f"{w} Dask worker{'s' if w > 1 else ''}", total.samples / seconds))
        result = total.solve("ellipsoid", 1e-6)
        print(f"{len(paths)} files, {one.samples} samples; merged sums equal one reducer's (max rel. difference {err:.1e})")
        print(f"identified: status {result['status']}, training RMS {np.round(result['training_rms'], 4).tolist()} N·m")
        print("| reducing with | samples/s |\n|---|---|")
        for name, rate in rows:
            print(f"| {name} | {rate:,.0f} |")


if __name__ == "__main__":
    main()
