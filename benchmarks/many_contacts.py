"""min_force (sigma_L1, eq. 13) on grasps of m = 4 to 16 soft fingers: "zc-ie" against "zc-ie-newton".

A call of W_L1's support map evaluates all m contact ellipsoids, so an IE step costs O(m); a Newton
step of "zc-ie-newton" evaluates only the few pieces of the exit face (at most 6 in R^6). This
script measures where that pays. The grasps: m contacts at random points of the unit sphere with
inward normals (mu = 0.5, mu_s = 0.05), random wrenches as in benchmarks/grasp_sets.py; the truth
is the minimum certified by "ie" at eps = 1e-12 (the paper's procedure, no Newton).

    python -m benchmarks.many_contacts [--wrenches 300] [--out benchmarks/results/many_contacts.md]
"""
import argparse
import time

import numpy as np

import graspforce as gf
from benchmarks.grasp_sets import random_wrenches

REPEATS = 3
METHODS = ("zc-ie", "zc-ie-newton")


def sphere_grasp(m, seed):
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(m, 3))
    p /= np.linalg.norm(p, axis=1, keepdims=True)
    return gf.Grasp(gf.Contact(q, -q, 0.5, 0.05) for q in p)


def timed(call):
    best = np.inf
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        out = call()
        best = min(best, time.perf_counter() - t0)
    return best, out


def run(n_wrenches=300, sizes=(4, 8, 12, 16), seed=0, log=print):
    lines = ["| contacts | method | median us | mean us | median iters | median support calls "
             "| max rel error | feasible |", "|---|---|---|---|---|---|---|---|"]
    for m in sizes:
        grasp = sphere_grasp(m, seed + m)
        W = grasp.wrench_set("L1")
        wrenches = random_wrenches(n_wrenches, seed=seed)
        truth = [gf.ray_shoot(W, -w, method="ie", eps=1e-12) for w in wrenches]
        for method in METHODS:
            grasp.min_force(wrenches[0], method=method)
            times, iters, calls, errs, feas = [], [], [], [], 0
            for w, tr in zip(wrenches, truth):
                dt, res = timed(lambda: grasp.min_force(w, method=method))
                times.append(dt)
                shot = res.shot
                iters.append(shot.iterations)
                calls.append(shot.support_calls)
                if res.feasible:
                    feas += 1
                    errs.append(abs(res.sigma - 1.0 / tr.t) * tr.t)
                elif tr.hit:
                    errs.append(np.inf)
            row = (f"| {m} | {method} | {1e6 * np.median(times):.1f} | {1e6 * np.mean(times):.1f} "
                   f"| {np.median(iters):g} | {np.median(calls):g} | "
                   f"{max(errs) if errs else 0:.1e} | {feas}/{n_wrenches} |")
            log(row)
            lines.append(row)
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--wrenches", type=int, default=300)
    ap.add_argument("--out", default="benchmarks/results/many_contacts.md")
    args = ap.parse_args()
    lines = run(args.wrenches)
    with open(args.out, "w") as f:
        f.write("## min_force sigma_L1 on m-finger sphere grasps: zc-ie vs zc-ie-newton\n\n"
                f"{args.wrenches} random wrenches per grasp, eps = 1e-9, least of {REPEATS} "
                "timed passes per call, medians. Command: `python -m benchmarks.many_contacts`.\n\n")
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
