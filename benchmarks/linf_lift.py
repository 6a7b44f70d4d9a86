"""min sigma_Linf (eq. 13) shot at W_Linf's lift against the sum itself
(graspforce.grasping.wrench_space).

For norm "Linf", IE and ZC-IE shoot the ray (0, r) at the lift C = CH(U_i {e_i - c} x CH({0} U W_i))
in R^(m + 5) on grasps of up to LIFT_MAX_CONTACTS contacts, instead of r at the sum
W_Linf = sum_i CH({0} U W_i) in R^6. This script times both on the same grasp objects, call by
call and alternating (the machine's speed drifts too much for two runs one after the other), and
reports medians of the per-call times, the per-call ratio and the iterations: on the ingot grasp
of table 5 (1000 wrenches), and on m soft fingers at random points of a sphere (the grasps of
benchmarks/many_contacts.py, 200 wrenches), where the lift's larger IE steps stop paying
(graspforce.grasping.wrench_space.LIFT_MAX_CONTACTS; the row for 8 contacts forces the lift).

    python -m benchmarks.linf_lift [--out benchmarks/results/linf_lift.md]
"""
import argparse
import time

import numpy as np

from benchmarks.grasp_sets import ingot_grasp, random_wrenches
from benchmarks.many_contacts import sphere_grasp

PASSES = 3


def shooting(grasp, magnitude, method, lifted):
    """The grasp, its min_force with `method` shooting at W_Linf's lift or at W_Linf itself
    whatever the number of contacts."""
    space = grasp._space("Linf", magnitude)
    space._by_method[(method, False)] = space._target(lifted, space.length)
    return grasp


def compare(make_grasp, wrenches, magnitude="normal", method="zc-ie"):
    """(median us lift, median us sum, median per-call ratio, median iterations lift, sum,
    max |sigma_lift / sigma_sum - 1|, feasible answers) over PASSES passes."""
    lift = shooting(make_grasp(), magnitude, method, True)
    plain = shooting(make_grasp(), magnitude, method, False)
    dim = lift._space("Linf", magnitude).target(method).set.dim
    for grasp in (lift, plain):
        # the first two calls compile and build the start table
        for w in wrenches[:2]:
            grasp.min_force(w, norm="Linf", magnitude=magnitude, method=method)
    times = {"lift": [], "sum": []}
    iters = {"lift": [], "sum": []}
    err, feasible = 0.0, 0
    for _ in range(PASSES):
        for w in wrenches:
            t0 = time.perf_counter()
            a = plain.min_force(w, norm="Linf", magnitude=magnitude, method=method)
            t1 = time.perf_counter()
            b = lift.min_force(w, norm="Linf", magnitude=magnitude, method=method)
            t2 = time.perf_counter()
            times["sum"].append(t1 - t0)
            times["lift"].append(t2 - t1)
            iters["sum"].append(a.iterations)
            iters["lift"].append(b.iterations)
            if a.status != b.status:
                raise AssertionError(f"lift {b.status}, sum {a.status} for w = {list(w)}")
            if a.feasible:
                feasible += 1
                err = max(err, abs(b.sigma / a.sigma - 1))
    ratio = np.median(np.array(times["lift"]) / np.array(times["sum"]))
    return (dim, np.median(times["lift"]) * 1e6, np.median(times["sum"]) * 1e6, ratio,
            np.median(iters["lift"]), np.median(iters["sum"]), err, feasible // PASSES)


def run(log=print):
    lines = ["| grasp | magnitude | method | lift dim | lift median us | sum median us | "
             "per-call ratio lift/sum | lift iters | sum iters | max rel sigma diff | feasible |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]

    def row(name, make, wrenches, magnitude, method):
        d, tl, ts, ratio, il, is_, err, feas = compare(make, wrenches, magnitude, method)
        lines.append(f"| {name} | {magnitude} | {method} | {d} | {tl:.1f} | {ts:.1f} | "
                     f"{ratio:.3f} | {il:.0f} | {is_:.0f} | {err:.1e} | {feas} |")
        log(lines[-1])

    ingot_wrenches = random_wrenches(1000, seed=0)
    for magnitude in ("normal", "full"):
        for method in ("zc-ie", "ie"):
            row("ingot (4 soft)", ingot_grasp, ingot_wrenches, magnitude, method)
    sphere_wrenches = random_wrenches(200, seed=0)
    for m in (2, 4, 6, 8):
        row(f"sphere, {m} soft", lambda m=m: sphere_grasp(m, m), sphere_wrenches, "normal",
            "zc-ie")
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=None)
    args = parser.parse_args(argv)
    lines = run()
    if args.out:
        with open(args.out, "w") as f:
            f.write("\n".join(["## min sigma_Linf: W_Linf's lift against the sum "
                               "(`python -m benchmarks.linf_lift`)", ""] + lines) + "\n")


if __name__ == "__main__":
    main()
