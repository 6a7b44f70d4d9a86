"""Minimal contact forces on the ingot grasp (paper section 5.2, table 5): graspforce against the
solvers users would use instead, on the same wrenches, in the same run.

Run from the repository root:

    python -m benchmarks.min_force              # 1000 random wrenches, eps = 1e-9, sigma_L1 and sigma_Linf
    python -m benchmarks.min_force --quick      # 100 wrenches
    python -m benchmarks.min_force --eps 1e-5   # the paper's tolerance (absolute there, relative here)
    python -m benchmarks.min_force --magnitude full   # the objectives of eq. (15)

Ours: `grasp.min_force(w, norm, magnitude, method, eps)` for the five methods (every call from
Python, forces read off the final simplex included). Baselines (graspforce.grasping.baselines):
- Clarabel SOCP on the exact cones, at its fastest: built once, `solver.update(b=...)` per wrench;
- the same SOCP built and solved per call (how it is usually called);
- a linearized friction pyramid (8 faces) solved through qpsolvers with OSQP and with Clarabel, as
  users usually call them (normal magnitude only).
Each call is timed on its own with time.perf_counter_ns after an untimed warm-up pass (garbage
collector off), in three passes; a call's time is its least (benchmarks.ray_shoot.REPEATS). Accuracy: every sigma against the prepared SOCP solved with tight tolerances
(relative), plus checks that need no solver: our bracket (sigma / sigma_lower - 1 <= eps), the
equilibrium residual |sum_i G_i f_i + w_ext| / |w_ext|, and the forces' distance outside their cones.
"""
import argparse
import json
import os
import sys

import numpy as np

from benchmarks.grasp_sets import MU, MU_S, cone_outside, ingot_grasp, random_wrenches
from benchmarks.ray_shoot import PAPER_NAMES, PAPER_TABLES, _cpu_name, _timed_pass, core_description

METHODS = ("gjk", "ie", "zc", "bi-gjk", "zc-ie-paper", "zc-ie", "zc-ie-newton")
HERE = os.path.dirname(os.path.abspath(__file__))


def cone_violation(contact, f, scale):
    """How far the local force f lies outside F_i (eq. 12), relative to `scale` (the solution's
    largest normal force: an unused contact's f_1 ~ 0 would make a relative measure meaningless)."""
    return max(cone_outside(contact, f), 0.0) / scale


def summarize(name, times, results, wrenches, grasp, reference, eps=None):
    """One table row: timing, statuses, accuracy against the reference sigmas, self-checks."""
    sigma = np.array([r.sigma for r in results])
    feasible = np.array([r.feasible for r in results])
    ref_feasible = np.isfinite(reference)
    both = feasible & ref_feasible
    rel = np.abs(sigma[both] - reference[both]) / reference[both]
    status = {}
    for r in results:
        status[r.status] = status.get(r.status, 0) + 1
    residual = max((np.linalg.norm(r.resultant + w) / np.linalg.norm(w)
                    for r, w in zip(results, wrenches) if r.feasible), default=0.0)
    outside = max((cone_violation(c, f, max(r.forces[:, 0].max(), 1e-300)) for r in results
                   if r.feasible for c, f in zip(grasp.contacts, r.forces)), default=0.0)
    row = dict(
        name=name, median_us=np.median(times) / 1e3, mean_us=np.mean(times) / 1e3,
        iters=np.median([r.iterations for r in results]),
        mean_iters=np.mean([r.iterations for r in results]),
        status=status, disagree=int(np.sum(feasible != ref_feasible)),
        max_rel=rel.max(initial=0.0), med_rel=np.median(rel) if rel.size else float("nan"),
        residual=residual, outside=outside)
    if eps is not None:
        gap = np.array([r.sigma / r.sigma_lower - 1.0 for r in results if r.status == "optimal"])
        row["max_gap"] = gap.max(initial=0.0)
    return row


def run_objective(grasp, wrenches, norm, magnitude, eps, methods, log):
    from graspforce.grasping.baselines import clarabel_socp, pyramid

    prepared = clarabel_socp.Prepared(grasp, norm, magnitude)
    reference_solver = clarabel_socp.Prepared(grasp, norm, magnitude, tight=True)
    reference = np.array([reference_solver.solve(w).sigma for w in wrenches])
    rows = []
    for method in methods:
        times, res = _timed_pass(
            lambda w: grasp.min_force(w, norm, magnitude, method=method, eps=eps), wrenches)
        rows.append(summarize(method, times, res, wrenches, grasp, reference, eps))
        log(f"{norm}/{magnitude} {method}: median {rows[-1]['median_us']:.1f} us")
    baselines = [("clarabel SOCP (update)", prepared.solve),
                 ("clarabel SOCP (build)",
                  lambda w: clarabel_socp.min_force(grasp, w, norm, magnitude))]
    if magnitude == "normal":
        for solver in ("osqp", "clarabel"):
            baselines.append((f"{solver} pyramid (qpsolvers)",
                              lambda w, s=solver: pyramid.min_force(grasp, w, norm, magnitude,
                                                                    solver=s)))
    for name, fn in baselines:
        times, res = _timed_pass(fn, wrenches)
        rows.append(summarize(name, times, res, wrenches, grasp, reference))
        log(f"{norm}/{magnitude} {name}: median {rows[-1]['median_us']:.1f} us")
    return rows


def table(rows, norm, magnitude, eps, n, seed):
    ours = {r["name"]: r for r in rows}
    lines = [f"### min sigma_{norm}, magnitude {magnitude!r} ({n} wrenches, seed {seed}, "
             f"eps = {eps:g} relative)\n",
             "| solver | median us | mean us | zc-ie faster by | median iters | mean iters "
             "| max rel sigma vs SOCP | median rel | feasibility disagreements | max certified gap "
             "| max equilibrium residual | max cone violation | statuses |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    base = ours.get("zc-ie", rows[0])["median_us"]
    for r in rows:
        gap = f"{r['max_gap']:.1e}" if "max_gap" in r else ""
        lines.append(
            f"| {r['name']} | {r['median_us']:.1f} | {r['mean_us']:.1f} | "
            f"{r['median_us'] / base:.3g} | {r['iters']:g} | {r['mean_iters']:.1f} | "
            f"{r['max_rel']:.1e} | {r['med_rel']:.1e} | {r['disagree']} | {gap} | "
            f"{r['residual']:.1e} | {r['outside']:.1e} | "
            + ", ".join(f"{k}: {v}" for k, v in sorted(r["status"].items())) + " |")
    return lines


def paper_table(all_rows):
    with open(PAPER_TABLES) as f:
        paper = json.load(f)
    p5 = paper["table5_force_opt_time_ms_and_iterations"]
    lines = ["Paper table 5 (eps = 1e-5 absolute, MATLAB, Intel i7 2.67 GHz, means) next to this "
             "run (means):\n",
             "| method | paper L1 ms | paper L1 iters | our L1 us | our L1 iters | paper Linf ms "
             "| paper Linf iters | our Linf us | our Linf iters |",
             "|---|---|---|---|---|---|---|---|---|"]
    ours = {norm: {r["name"]: r for r in rows} for (norm, _), rows in all_rows.items()}
    names = {**PAPER_NAMES, "active-set": "clarabel SOCP (update)"}
    for i, m in enumerate(paper["methods"]):
        name = names.get(m, m)
        cells = [name if m != "active-set" else "active-set (paper) / clarabel SOCP update (ours)"]
        for norm, key in (("L1", "min_sigma_L1"), ("Linf", "min_sigma_Linf")):
            ms, it = p5[key][i]
            r = ours.get(norm, {}).get(name)
            cells += [str(ms), str(it), f"{r['mean_us']:.1f}" if r else "n/a",
                      f"{r['mean_iters']:.1f}" if r and m != "active-set" else ""]
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def run(n=1000, eps=1e-9, seed=0, magnitude="normal", methods=METHODS, out_path=None, log=print):
    import clarabel
    import osqp
    import qpsolvers

    grasp = ingot_grasp()
    wrenches = random_wrenches(n, seed)
    all_rows = {}
    lines = [f"## Minimal contact forces on the ingot grasp (4 soft fingers, mu {MU}, "
             f"mu_s {MU_S} m)\n",
             "`zc-ie faster by` = the row's median / zc-ie's median. Accuracy columns: max rel "
             "sigma vs SOCP is against Clarabel with tight tolerances; the certified gap is "
             "sigma / sigma_lower - 1 (ours, <= eps by contract); the equilibrium residual is "
             "|sum_i G_i f_i + w_ext| / |w_ext|; the cone violation is how far a returned force "
             "lies outside its exact cone, relative to the solution's largest normal force (an "
             "inscribed pyramid's exact forces would show 0).\n"]
    for norm in ("L1", "Linf"):
        rows = run_objective(grasp, wrenches, norm, magnitude, eps, methods, log)
        all_rows[(norm, magnitude)] = rows
        lines += table(rows, norm, magnitude, eps, n, seed) + [""]
    lines += paper_table(all_rows) + [""]
    lines.append(f"Environment: numpy {np.__version__}, {core_description()}, clarabel "
                 f"{clarabel.__version__}, osqp {osqp.__version__}, qpsolvers "
                 f"{qpsolvers.__version__}, {_cpu_name()}.")
    text = "\n".join(lines) + "\n"
    if out_path:
        os.makedirs(os.path.dirname(out_path), exist_ok=True)
        with open(out_path, "w") as f:
            f.write(text)
    return text, all_rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="100 wrenches instead of 1000")
    ap.add_argument("--n", type=int, default=None)
    ap.add_argument("--eps", type=float, default=1e-9)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--magnitude", default="normal", choices=("normal", "full"))
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    n = args.n if args.n is not None else (100 if args.quick else 1000)
    out = args.out or os.path.join(HERE, "results", f"min_force_{args.magnitude}.md")
    methods = tuple(m.strip() for m in args.methods.split(",") if m.strip())
    text, _ = run(n, args.eps, args.seed, args.magnitude, methods, out,
                  log=lambda s: print(s, file=sys.stderr))
    print(text)
    print(f"written to {out}", file=sys.stderr)


if __name__ == "__main__":
    main()
