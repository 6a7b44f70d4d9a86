"""A grasp or a pair of shapes made per query (a REST request, a batch over many grasps): the whole
cost of building the objects and their first answer, and the fixed cost around a compiled call.

    python -m benchmarks.fresh                        # 2000 queries a case
    python -m benchmarks.fresh --n 500 --before /tmp/base    # interleaved with another checkout

Cases, each query timed on its own (perf_counter_ns, garbage collector off), median and p90:
- (a) `gf.Grasp([gf.Contact(p, n, 0.6, 0.01) for 4 contacts]).min_force(w)`, zc-ie, L1: four soft
  fingers at the corners of a regular tetrahedron on a 5 cm sphere, turned at random for every
  query, normals to the centre; w: forces N(0, 5 N), torques N(0, 0.1 N m) (the issue's sphere
  grasp, made fresh). Beside it, the compiled call alone on an equal grasp's first shot
  (`graspforce._core.shoot_and_read_forces` with no start table, as a first min_force calls it)
  and the median iterations: the part of the query that is the answer itself.
- (b) the same with norm "Linf" (W_Linf's lift in R^9).
- (c) `gf.growth_distance(gf.Ellipsoid(0, diag(axes)), pose_a, gf.TruncatedCone(rb, rt, h),
  pose_b)` on shapes made for the query (axes 2-10 cm, radii 0-5 cm, heights 4-16 cm, random
  rotations, centres 5-40 cm apart); beside it the same query on a GrowthDistance made once
  (no warm start), the compiled `growth_query` alone, and `gf.growth_distance` called again on
  the same two shapes (which it sets up again: it keeps only composite sets).
- (d) min_force (zc-ie, L1) on one reused grasp of (a), 1000 wrenches, after a pass that builds
  its start table; the compiled call alone with the grasp's own capsule (`min_force_compiled`:
  the shot, its forces and the record); the fixed cost is the difference of the medians. The
  same for a reused GrowthDistance, and for queries whose compiled call returns at once (a zero
  wrench, coincident reference points).
With --before, every query of (a)-(c) is also run by the other checkout (its Python package, with
its own compiled core from its build folder, as benchmarks/ab.py loads it), alternately, on the
same inputs.

Writes benchmarks/results/fresh.md.
"""
import argparse
import gc
import math
import time
from pathlib import Path

import numpy as np

import graspforce as gf
from graspforce import _core
from graspforce.geometry._start_table import NO_TABLE

OUT = Path(__file__).resolve().parent / "results" / "fresh.md"
RADIUS, MU, MU_S = 0.05, 0.6, 0.01
TETRAHEDRON = np.array([[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0],
                        [-1.0, -1.0, 1.0]]) / math.sqrt(3.0)


def rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def finger_points(rng):
    """[(p, n)] of four spread soft fingers on the sphere, turned at random."""
    d = TETRAHEDRON @ rotation(rng).T
    return [(RADIUS * x, -x) for x in d]


def wrench(rng):
    return np.concatenate((rng.normal(0.0, 5.0, 3), rng.normal(0.0, 0.1, 3)))


def shape_pair(rng):
    axes = rng.uniform(0.02, 0.1, 3)
    rb, rt, h = rng.uniform(0.0, 0.05), rng.uniform(0.01, 0.05), rng.uniform(0.04, 0.16)
    d = rng.normal(size=3)
    pose_a = (rotation(rng), np.zeros(3))
    pose_b = (rotation(rng), d / np.linalg.norm(d) * rng.uniform(0.05, 0.4))
    return axes, (rb, rt, h), pose_a, pose_b


def timed(f):
    t0 = time.perf_counter_ns()
    f()
    return time.perf_counter_ns() - t0


def stats(ns):
    us = np.asarray(ns) / 1e3
    return float(np.median(us)), float(np.percentile(us, 90))


def fresh_grasp_query(gf_, points, w, norm):
    return lambda: gf_.Grasp([gf_.Contact(p, n, MU, MU_S) for p, n in points]).min_force(
        w, norm=norm)


def fresh_growth_query(gf_, case):
    axes, (rb, rt, h), pose_a, pose_b = case
    return lambda: gf_.growth_distance(gf_.Ellipsoid(np.zeros(3), np.diag(axes)), pose_a,
                                       gf_.TruncatedCone(rb, rt, h), pose_b)


def compiled_first_shot(points, w, norm):
    """ns of the compiled call of a first min_force on a grasp equal to the query's, and the
    call's iterations."""
    grasp = gf.Grasp([gf.Contact(p, n, MU, MU_S) for p, n in points])
    _, code, shoot, args, _, size, _, _, _ = grasp._call(norm, "normal", "zc-ie")
    packed = np.empty(size)
    t0 = time.perf_counter_ns()
    head = shoot(w, code, 1e-9, 10000, packed, NO_TABLE, *args)
    return time.perf_counter_ns() - t0, head[4]


def run_fresh(n, rng, versions, norm):
    """{version: [ns]} of fresh grasp queries, the versions alternating on each query, and the
    compiled first shots' ns and iterations."""
    times = {name: [] for name in versions}
    compiled, iterations = [], []
    for i in range(n):
        points, w = finger_points(rng), wrench(rng)
        order = list(versions.items())
        if i % 2:
            order.reverse()
        for name, gf_ in order:
            times[name].append(timed(fresh_grasp_query(gf_, points, w, norm)))
        ns, iters = compiled_first_shot(points, w, norm)
        compiled.append(ns)
        iterations.append(iters)
    return times, compiled, iterations


def run_growth(n, rng, versions):
    """{version: [ns]} of fresh growth queries, and this checkout's ns of the same query on a
    GrowthDistance made once, of its compiled call alone, and of gf.growth_distance called again
    on the same two shapes."""
    times = {name: [] for name in versions}
    reused, compiled, again = [], [], []
    for i in range(n):
        case = shape_pair(rng)
        order = list(versions.items())
        if i % 2:
            order.reverse()
        for name, gf_ in order:
            times[name].append(timed(fresh_growth_query(gf_, case)))
        axes, (rb, rt, h), pose_a, pose_b = case
        A, B = gf.Ellipsoid(np.zeros(3), np.diag(axes)), gf.TruncatedCone(rb, rt, h)
        solver = gf.GrowthDistance(A, B, warm_start=False)
        solver(pose_a, pose_b)
        reused.append(timed(lambda: solver(pose_a, pose_b)))
        packed = np.empty(solver._size)
        args = (solver._ints, solver._floats, pose_a[0], pose_a[1], pose_b[0], pose_b[1], packed)
        compiled.append(timed(lambda: _core.growth_query(*args)))
        again.append(timed(lambda: gf.growth_distance(A, pose_a, B, pose_b)))
    return times, reused, compiled, again


def run_reused(n, rng):
    """min_force on one reused grasp and its compiled call alone, per wrench, alternating."""
    grasp = gf.Grasp([gf.Contact(p, n_, MU, MU_S) for p, n_ in finger_points(rng)])
    wrenches = [wrench(rng) for _ in range(n)]
    # the start table is built at the second shot, the compiled call's capsule at the third
    for w in wrenches[:3]:
        grasp.min_force(w)
    call = grasp._compiled["L1", "normal", "zc-ie"]
    whole, compiled = [], []
    for i, w in enumerate(wrenches):
        # in turns first: the second call on a wrench finds the first's data in the caches
        if i % 2:
            whole.append(timed(lambda: grasp.min_force(w)))
        compiled.append(timed(lambda: _core.min_force_compiled(call, w)))
        if not i % 2:
            whole.append(timed(lambda: grasp.min_force(w)))
    return whole, compiled


def run_trivial(n, rng):
    """{call: (whole ns, compiled ns)} of queries whose compiled call returns at once: min_force
    of a zero wrench on a reused grasp, and growth distance at coincident reference points on a
    reused GrowthDistance; the two alternate, whole and compiled in turns first."""
    grasp = gf.Grasp([gf.Contact(p, n_, MU, MU_S) for p, n_ in finger_points(rng)])
    zero = np.zeros(6)
    for _ in range(3):
        grasp.min_force(zero)
    call = grasp._compiled["L1", "normal", "zc-ie"]
    axes, (rb, rt, h), pose_a, _ = shape_pair(rng)
    solver = gf.GrowthDistance(gf.Ellipsoid(np.zeros(3), np.diag(axes)),
                               gf.TruncatedCone(rb, rt, h), warm_start=False)
    solver(pose_a, pose_a)
    calls = {
        "min_force of a zero wrench, reused grasp": (
            lambda: grasp.min_force(zero),
            lambda: _core.min_force_compiled(call, zero)),
        "growth distance at coincident reference points, reused GrowthDistance": (
            lambda: solver(pose_a, pose_a),
            lambda: _core.growth_query(solver._ints, solver._floats, *pose_a, *pose_a,
                                       np.empty(solver._size)))}
    out = {name: ([], []) for name in calls}
    for i in range(n):
        for name, (whole, compiled) in calls.items():
            order = ((0, whole), (1, compiled)) if i % 2 else ((1, compiled), (0, whole))
            for k, f in order:
                out[name][k].append(timed(f))
    return out


def load_before(checkout):
    from benchmarks.ab import load
    return load(checkout, "gf_before")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--before", help="another checkout, run alternately on the same inputs")
    parser.add_argument("--out", default=str(OUT))
    args = parser.parse_args()
    versions = {"this": gf}
    if args.before:
        versions = {"before": load_before(args.before), "this": gf}
    rng = np.random.default_rng(args.seed)
    # warm-up: a structure's first grasp makes its template (graspforce.grasping.wrench_space), a
    # leaf pair's first Delta its own (graspforce.growth.growth); both once per process
    run_fresh(20, rng, versions, "L1")
    run_fresh(20, rng, versions, "Linf")
    run_growth(20, rng, versions)
    gc.disable()
    l1 = run_fresh(args.n, rng, versions, "L1")
    linf = run_fresh(args.n, rng, versions, "Linf")
    growth = run_growth(args.n, rng, versions)
    reused = run_reused(min(args.n, 1000), rng)
    trivial = run_trivial(min(args.n, 1000), rng)
    gc.enable()

    lines = ["# A grasp or a pair of shapes made per query", "",
             f"`python -m benchmarks.fresh --n {args.n}"
             + (f" --before {args.before}`" if args.before else "`")
             + f"; {args.n} queries a case, each timed on its own; us.", ""]
    head = "| case | " + " | ".join(f"{name} median | {name} p90" for name in versions)
    lines += [head + " | goal |", "|---" * (2 * len(versions) + 2) + "|"]

    def row(label, times, goal=""):
        cells = " | ".join(f"{m:.1f} | {p:.1f}" for m, p in (stats(times[v]) for v in versions))
        return f"| {label} | {cells} | {goal} |"

    lines.append(row("(a) fresh Grasp (4 soft) + first min_force, zc-ie L1", l1[0], "<= 30"))
    lines.append(row("(b) the same, Linf", linf[0]))
    lines.append(row("(c) fresh ellipsoid + truncated cone + first growth distance", growth[0],
                     "<= 15"))
    lines += ["", "Of which the answer itself (this checkout; the compiled call on an equal "
              "object, as the first query calls it):", "",
              "| case | median | p90 | median iterations |", "|---|---|---|---|"]
    for label, (_, compiled, iters) in (("(a) first shot, L1", l1), ("(b) first shot, Linf",
                                                                    linf)):
        m, p = stats(compiled)
        lines.append(f"| {label} | {m:.1f} | {p:.1f} | {np.median(iters):.0f} |")
    m, p = stats(growth[1])
    lines.append(f"| (c) the same query on a GrowthDistance made once | {m:.1f} | {p:.1f} | |")
    m, p = stats(growth[2])
    lines.append(f"| (c) its compiled growth_query alone | {m:.1f} | {p:.1f} | |")
    m, p = stats(growth[3])
    lines.append(f"| (c) gf.growth_distance again on the same two shapes (set up per call) | "
                 f"{m:.1f} | {p:.1f} | |")
    whole, compiled = reused
    mw, pw = stats(whole)
    mc, pc = stats(compiled)
    mg = stats(growth[1])[0]
    mq = stats(growth[2])[0]
    lines += ["", "(d) The fixed cost around a compiled call, on reused objects:", "",
              "| call | whole median | p90 | compiled median | p90 | fixed cost (median "
              "difference) |", "|---|---|---|---|---|---|",
              f"| min_force zc-ie L1, reused grasp (start table) | {mw:.2f} | {pw:.2f} | "
              f"{mc:.2f} | {pc:.2f} | {mw - mc:.2f} |",
              f"| growth distance, reused GrowthDistance | {mg:.2f} | | {mq:.2f} | | "
              f"{mg - mq:.2f} |"]
    for name, (whole, compiled) in trivial.items():
        (mw, pw), (mc, pc) = stats(whole), stats(compiled)
        lines.append(f"| {name} | {mw:.2f} | {pw:.2f} | {mc:.2f} | {pc:.2f} | {mw - mc:.2f} |")
    text = "\n".join(lines) + "\n"
    print(text)
    Path(args.out).write_text(text)


if __name__ == "__main__":
    main()
