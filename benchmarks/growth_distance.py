"""Growth distance: the paper's tables 1 and 2 and fig. 8 (section 4.2), with a Clarabel baseline.

Run from the repository root:

    python -m benchmarks.growth_distance            # 3000 pairs per case, all pairs of 100 shapes
    python -m benchmarks.growth_distance --quick    # 300 pairs per case, 30 shapes
    python -m benchmarks.growth_distance --plots    # also fig. 8 (needs the `plots` extra)

Pairs (benchmarks/growth_sets.py): an ellipsoid touching a truncated cone through its side, a base
rim or a base face, at random sizes and poses (truth 1), and the same shrunk or enlarged by 2 about
their reference points (truth 2, 0.5). For each pair `gf.GrowthDistance(E, C, method, eps,
warm_start=False)` is built once (Delta compiled), called once untimed, then timed on its own
calls (time.perf_counter_ns, garbage collector off) in REPEATS = 3 passes over all pairs, keeping
each query's least (the machine's speed drifts over seconds); Clarabel's too, each pair's least of
REPEATS builds and solves. "random": every pair among random ellipsoids and truncated cones (no
truth; the methods are compared with each other and with Clarabel).
Baseline: Clarabel on the convex program min sigma s.t. a point lies in A(sigma) and B(sigma)
(the truncated cone as the convex hull of its two scaled disks), built and solved per pair.
Warm start: iterations and time of one GrowthDistance following a moving pair, cold and warm.
"""
import argparse
import gc
import json
import os
import sys
import time

import numpy as np
import scipy.sparse as sp

from benchmarks.growth_sets import SCALES, protocol_pairs, random_shapes, scaled_shapes
from benchmarks.ray_shoot import PAPER_TABLES, REPEATS, _cpu_name, _timed_pass, core_description

METHODS = ("gjk", "ie", "zc", "bi-gjk", "zc-ie-paper", "zc-ie", "zc-ie-newton")
HERE = os.path.dirname(os.path.abspath(__file__))


def make_shape(kind, data):
    import graspforce as gf
    if kind == "ellipsoid":
        return gf.Ellipsoid(np.zeros(3), np.diag(data))
    return gf.TruncatedCone(*data)


def timed_query(solver, pose_a, pose_b):
    """(ns, result): the least of REPEATS timings of one query (the machine's speed drifts),
    after an untimed warm-up call."""
    solver(pose_a, pose_b)                       # warm-up: first call, cold caches
    gc_on = gc.isenabled()
    gc.disable()
    try:
        dt = None
        for _ in range(REPEATS):
            t0 = time.perf_counter_ns()
            res = solver(pose_a, pose_b)
            elapsed = time.perf_counter_ns() - t0
            dt = elapsed if dt is None else min(dt, elapsed)
    finally:
        if gc_on:
            gc.enable()
    return dt, res


def least_of(timed_call, *args):
    """(value, ns) of a call that times itself, its least time over REPEATS calls, as ours."""
    runs = [timed_call(*args) for _ in range(REPEATS)]
    return runs[0][0], min(dt for _, dt in runs)


def clarabel_growth(kind_a, data_a, R_a, p_a, kind_b, data_b, R_b, p_b):
    """(sigma, seconds) from Clarabel: min sigma s.t. p_A + R_A x = p_B + R_B y, x in sigma A_0,
    y in sigma B_0; an ellipsoid {diag(axes) u : ||u|| <= sigma}, a truncated cone
    {q_1 + q_2 : q_1 in mu_1 D_bottom, q_2 in mu_2 D_top, mu_1 + mu_2 = sigma}."""
    import clarabel
    cols = {"sigma": 0}
    blocks = []
    n = 1
    for side, kind in (("a", kind_a), ("b", kind_b)):
        size = 3 if kind == "ellipsoid" else 6          # u (3) or mu1, x1, y1, mu2, x2, y2
        cols[side] = n
        n += size
        blocks.append(size)
    A_rows, b_rows, cones = [], [], []
    eq = np.zeros((3, n))
    extra_eq = []
    for sign, side, kind, data, R in ((1.0, "a", kind_a, data_a, R_a),
                                      (-1.0, "b", kind_b, data_b, R_b)):
        c = cols[side]
        if kind == "ellipsoid":
            eq[:, c:c + 3] = sign * R @ np.diag(data)
            block = np.zeros((4, n))
            block[0, 0], block[1:, c:c + 3] = -1.0, -np.eye(3)
            A_rows.append(block)
            b_rows.append(np.zeros(4))
            cones.append(clarabel.SecondOrderConeT(4))
        else:
            rb, rt, h = data
            # q = (x1 + x2, y1 + y2, (mu2 - mu1) h / 2)
            M = np.zeros((3, 6))
            M[0, 1] = M[0, 4] = 1.0
            M[1, 2] = M[1, 5] = 1.0
            M[2, 0], M[2, 3] = -0.5 * h, 0.5 * h
            eq[:, c:c + 6] = sign * R @ M
            for mu, radius in ((0, rb), (3, rt)):
                block = np.zeros((3, n))
                block[0, c + mu] = -radius
                block[1, c + mu + 1] = block[2, c + mu + 2] = -1.0
                A_rows.append(block)
                b_rows.append(np.zeros(3))
                cones.append(clarabel.SecondOrderConeT(3))
            row = np.zeros((1, n))
            row[0, c], row[0, c + 3], row[0, 0] = 1.0, 1.0, -1.0
            extra_eq.append(row)
    A = np.vstack([eq] + extra_eq + A_rows)
    b = np.concatenate([p_b - p_a, np.zeros(len(extra_eq))] + b_rows)
    cones = [clarabel.ZeroConeT(3 + len(extra_eq))] + cones
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    q = np.zeros(n)
    q[0] = 1.0
    t0 = time.perf_counter_ns()
    sol = clarabel.DefaultSolver(sp.csc_matrix((n, n)), q, sp.csc_matrix(A), b, cones,
                                 settings).solve()
    return sol.x[0], time.perf_counter_ns() - t0


def _query(query):
    solver, pose_a, pose_b = query
    return solver(pose_a, pose_b)


def protocol_rows(pairs, eps, methods, log):
    import graspforce as gf
    rows = {}
    for case, (scale, truth) in SCALES.items():
        shapes = [scaled_shapes(p, scale) for p in pairs]
        for method in methods:
            queries = [(gf.GrowthDistance(make_shape("ellipsoid", axes), make_shape("cone", cone),
                                          method, eps, warm_start=False),
                        (p["R_e"], p["p_e"]), (p["R_c"], p["p_c"]))
                       for p, (axes, cone) in zip(pairs, shapes)]
            times, results = _timed_pass(_query, queries)
            errors = [abs(res.sigma - truth) for res in results]
            iters = [res.iterations for res in results]
            rows[(case, method)] = {"median_us": np.median(times) / 1e3,
                                    "mean_us": np.mean(times) / 1e3,
                                    "mean_err": np.mean(errors), "max_err": np.max(errors),
                                    "mean_iters": np.mean(iters)}
            log(f"{case} {method}: median {rows[(case, method)]['median_us']:.1f} us, "
                f"max error {rows[(case, method)]['max_err']:.1e}")
        times, errors = [], []
        for p, (axes, cone) in zip(pairs, shapes):
            sigma, dt = least_of(clarabel_growth, "ellipsoid", axes, p["R_e"], p["p_e"], "cone",
                                 cone, p["R_c"], p["p_c"])
            times.append(dt)
            errors.append(abs(sigma - truth))
        rows[(case, "clarabel")] = {"median_us": np.median(times) / 1e3,
                                    "mean_us": np.mean(times) / 1e3, "mean_err": np.mean(errors),
                                    "max_err": np.max(errors), "mean_iters": float("nan")}
    return rows


def random_rows(shapes, eps, methods, log):
    import graspforce as gf
    objects = [make_shape(kind, data) for kind, data, _, _ in shapes]
    pairs = [(i, j) for i in range(len(shapes)) for j in range(i + 1, len(shapes))]
    rows, sigmas = {}, {}
    for method in methods:
        queries = [(gf.GrowthDistance(objects[i], objects[j], method, eps, warm_start=False),
                    shapes[i][2:], shapes[j][2:]) for i, j in pairs]
        times, results = _timed_pass(_query, queries)
        iters = [res.iterations for res in results]
        values = [res.sigma for res in results]
        sigmas[method] = np.array(values)
        rows[method] = {"median_us": np.median(times) / 1e3, "mean_us": np.mean(times) / 1e3,
                        "mean_iters": np.mean(iters)}
        log(f"random {method}: median {rows[method]['median_us']:.1f} us")
    times, values = [], []
    for i, j in pairs:
        (ka, da, Ra, pa), (kb, db, Rb, pb) = shapes[i], shapes[j]
        sigma, dt = least_of(clarabel_growth, ka, da, Ra, pa, kb, db, Rb, pb)
        times.append(dt)
        values.append(sigma)
    clar = np.array(values)
    rows["clarabel"] = {"median_us": np.median(times) / 1e3, "mean_us": np.mean(times) / 1e3,
                        "mean_iters": float("nan")}
    for method in methods:
        rows[method]["max_rel_vs_clarabel"] = np.max(np.abs(sigmas[method] / clar - 1))
    return rows, len(pairs)


def warm_start_rows(eps, steps=(400, 4000)):
    """A truncated cone circling and tumbling around an ellipsoid, once around in `steps` poses
    (about 0.02 and 0.002 rad of normal change per call): one GrowthDistance, cold and warm
    (time coherence)."""
    from scipy.spatial.transform import Rotation

    import graspforce as gf
    A = gf.Ellipsoid(np.zeros(3), np.diag([0.3, 0.2, 0.15]))
    B = gf.TruncatedCone(0.2, 0.1, 0.4)
    out = {}
    for n in steps:
        poses = []
        for k in range(n):
            th = 2 * np.pi * k / n
            pose_b = (Rotation.from_rotvec([th, 0.5 * th, 0.2]).as_matrix(),
                      np.array([0.8 * np.cos(th), 0.6 * np.sin(th), 0.1 * np.sin(3 * th)]))
            poses.append(((Rotation.from_rotvec([0, 0, 0.3 * th]).as_matrix(), np.zeros(3)),
                          pose_b))
        for warm in (False, True):
            solver = gf.GrowthDistance(A, B, "zc-ie", eps, warm_start=warm)
            for pa, pb in poses[:10]:
                solver(pa, pb)
            times, iters = [], []
            for pa, pb in poses:
                t0 = time.perf_counter_ns()
                res = solver(pa, pb)
                times.append(time.perf_counter_ns() - t0)
                iters.append(res.iterations)
            out[(n, "warm" if warm else "cold")] = {"median_us": np.median(times) / 1e3,
                                                    "mean_iters": np.mean(iters)}
    return out


def time_split(pairs, eps, method="zc-ie"):
    """Where a query's time goes (contact case): the whole Python call, the core's query called
    from Python (graspforce._core.growth_query: the checks of its seven array arguments, then the
    pose checks, the rotations written in place and the shooter), the same query in a compiled
    loop without Python (graspforce._core.timing.growth_loop), and the support calls alone (mean
    calls per query times one call's cost, from a compiled loop). Each is the least of REPEATS
    timings after a warm-up call or pass."""
    from graspforce._core import growth_query, timing

    import graspforce as gf

    full, from_python, compiled, calls, per_call = [], [], [], [], []
    U = np.random.default_rng(0).normal(size=(2000, 3))
    for p in pairs[:500]:
        axes, cone = scaled_shapes(p, 1.0)
        g = gf.GrowthDistance(make_shape("ellipsoid", axes), make_shape("cone", cone), method,
                              eps, warm_start=False)
        pa, pb = (p["R_e"], p["p_e"]), (p["R_c"], p["p_c"])
        dt, res = timed_query(g, pa, pb)
        full.append(dt)
        calls.append(res.support_calls)
        packed = np.empty(g._size)
        args = (g._ints, g._floats, *pa, *pb, packed)
        growth_query(*args)
        best = None
        for _ in range(REPEATS):
            t0 = time.perf_counter_ns()
            growth_query(*args)
            elapsed = time.perf_counter_ns() - t0
            best = elapsed if best is None else min(best, elapsed)
        from_python.append(best)
        # the loop takes (k, 3, 3) rotations and (k, 3) translations: here k = 1
        poses = [np.ascontiguousarray(x[None], dtype=float) for x in (*pa, *pb)]
        ns, _ = timing.growth_loop(g._ints, g._floats, *poses, packed, REPEATS + 1)
        compiled.append(ns[1:].min())
        point, wit = np.empty(3), np.empty(g.delta.witness_size)
        ns, _ = timing.support_loop(g._ints, g._floats, U, point, wit, REPEATS + 1)
        per_call.append(ns[1:].min())
    return {"full_us": np.median(full) / 1e3, "from_python_us": np.median(from_python) / 1e3,
            "compiled_us": np.median(compiled) / 1e3, "calls": np.mean(calls),
            "support_us": np.mean(calls) * np.median(per_call) / 1e3,
            "per_call_ns": np.median(per_call)}


def tolerance_sweep(pairs, methods, tolerances):
    """Fig. 8: mean absolute error and median time per method against eps (all three cases)."""
    out = {}
    for eps in tolerances:
        rows = protocol_rows(pairs, eps, methods, log=lambda s: None)
        for method in methods:
            err = np.mean([rows[(c, method)]["mean_err"] for c in SCALES])
            us = np.median([rows[(c, method)]["median_us"] for c in SCALES])
            out[(eps, method)] = (err, us)
    return out


def plot_sweep(sweep, methods, tolerances, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for method in methods:
        ax1.loglog(tolerances, [max(sweep[(e, method)][0], 1e-17) for e in tolerances], "o-",
                   label=method)
        ax2.semilogx(tolerances, [sweep[(e, method)][1] for e in tolerances], "o-", label=method)
    ax1.set(xlabel="eps (relative)", ylabel="mean absolute error of g(A, B)",
            title="(a) error vs tolerance")
    ax2.set(xlabel="eps (relative)", ylabel="median time per query [us]",
            title="(b) time vs tolerance")
    for ax in (ax1, ax2):
        ax.invert_xaxis()
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def run(n_pairs=3000, n_shapes=100, eps=1e-9, seed=0, methods=METHODS, plots=False,
        out_path=None, log=print):
    import clarabel
    pairs = protocol_pairs(n_pairs, seed)
    prot = protocol_rows(pairs, eps, methods, log)
    rand, n_random = random_rows(random_shapes(n_shapes, seed + 1), eps, methods, log)
    warm = warm_start_rows(eps)
    split = time_split(pairs, eps)
    with open(PAPER_TABLES) as f:
        paper = json.load(f)
    p1, p2 = paper["table1_growth_abs_error"], paper["table2_growth_time_ms_and_iterations"]
    index = {m: i for i, m in enumerate(paper["methods"])}
    lines = [(f"## Growth distance: ellipsoid vs truncated cone ({n_pairs} pairs per case, "
              f"eps = {eps:g} relative, seed {seed})\n"),
             ("Every query timed alone from Python on a GrowthDistance built for the pair "
              "(warm start off); sigma is the midpoint of the certified bracket. Paper: eps = "
              "1e-5 absolute, MATLAB, Intel i7 2.67 GHz, means.\n"),
             ("| case | method | median us | mean us | mean iters | mean abs error | max abs error "
              "| paper mean abs error | paper ms | paper iters |"),
             "|---|---|---|---|---|---|---|---|---|---|"]
    for case in SCALES:
        for method in list(methods) + ["clarabel"]:
            r = prot[(case, method)]
            i = index.get(method if method != "clarabel" else "active-set")
            ms, it = p2[case][i] if i is not None else ("", "")
            paper_err = f"{p1[case][i]:.1e}" if i is not None else ""
            lines.append(f"| {case} | {method} | {r['median_us']:.1f} | {r['mean_us']:.1f} | "
                         f"{r['mean_iters']:.1f} | {r['mean_err']:.1e} | {r['max_err']:.1e} | "
                         f"{paper_err} | {ms} | {it} |")
    lines += ["", (f"### All pairs among {n_shapes} random ellipsoids and truncated cones "
               f"({n_random} pairs)\n"),
              ("| method | median us | mean us | mean iters | max rel vs clarabel | paper ms "
               "| paper iters |"), "|---|---|---|---|---|---|---|"]
    for method in list(methods) + ["clarabel"]:
        r = rand[method]
        i = index.get(method if method != "clarabel" else "active-set")
        ms, it = p2["random"][i] if i is not None else ("", "")
        rel = f"{r['max_rel_vs_clarabel']:.1e}" if "max_rel_vs_clarabel" in r else ""
        lines.append(f"| {method} | {r['median_us']:.1f} | {r['mean_us']:.1f} | "
                     f"{r['mean_iters']:.1f} | {rel} | {ms} | {it} |")
    lines += ["", ("### Warm start on a moving pair (zc-ie, a tumbling cone circling an "
               "ellipsoid once in N poses)\n"), "| N poses | start | median us | mean iters |",
              "|---|---|---|---|"]
    for (n, k), r in warm.items():
        lines.append(f"| {n} | {k} | {r['median_us']:.1f} | {r['mean_iters']:.1f} |")
    lines += ["", "### Where a zc-ie query's time goes (contact case, 500 pairs, medians)\n",
              ("| whole Python call us | core query from Python us | core query in a "
               "compiled loop us | support calls per query | one support call ns "
               "| support calls alone us |"),
              "|---|---|---|---|---|---|",
              (f"| {split['full_us']:.1f} | {split['from_python_us']:.1f} | "
               f"{split['compiled_us']:.1f} | {split['calls']:.1f} | {split['per_call_ns']:.0f} | "
               f"{split['support_us']:.1f} |")]
    if plots:
        tolerances = [1e-3, 1e-5, 1e-7, 1e-9, 1e-11]
        sweep = tolerance_sweep(pairs[:300], methods, tolerances)
        path = os.path.join(HERE, "growth_distance_fig8.png")
        plot_sweep(sweep, methods, tolerances, path)
        lines += ["", f"Fig. 8 (300 pairs per case): `{os.path.relpath(path, HERE)}`\n",
                  "| eps | " + " | ".join(f"{m} err / us" for m in methods) + " |",
                  "|---|" + "---|" * len(methods)]
        for e in tolerances:
            lines.append(f"| {e:g} | " + " | ".join(
                f"{sweep[(e, m)][0]:.1e} / {sweep[(e, m)][1]:.1f}" for m in methods) + " |")
    lines += ["", (f"Environment: numpy {np.__version__}, {core_description()}, clarabel "
               f"{clarabel.__version__}, {_cpu_name()}.")]
    text = "\n".join(lines) + "\n"
    if out_path:
        os.makedirs(os.path.dirname(out_path), exist_ok=True)
        with open(out_path, "w") as f:
            f.write(text)
    return text


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="300 pairs per case, 30 shapes")
    ap.add_argument("--eps", type=float, default=1e-9)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--plots", action="store_true", help="fig. 8 as a PNG (needs matplotlib)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "growth_distance.md"))
    args = ap.parse_args(argv)
    n_pairs, n_shapes = (300, 30) if args.quick else (3000, 100)
    methods = tuple(m.strip() for m in args.methods.split(",") if m.strip())
    text = run(n_pairs, n_shapes, args.eps, args.seed, methods, args.plots, args.out,
               log=lambda s: print(s, file=sys.stderr))
    print(text)
    print(f"written to {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
