"""min_force on families of grasps, each family with its own median, p90 and iterations, against
Clarabel (the exact SOCP, built once, `update(b=...)` per wrench) in the same run.

    python -m benchmarks.families                      # 12 grasps x 60 loads a family, zc-ie
    python -m benchmarks.families --grasps 4 --loads 20 --method zc-ie-newton

Families (metres, newtons; each grasp drawn from a seeded generator):
- ingot: the paper's four soft fingers (benchmarks/grasp_sets.py), forces N(0, 10 N), torques
  N(0, 0.5 N m);
- sphere-3, sphere-4, sphere-5: 3 to 5 soft fingers spread over a 5 cm sphere (a regular layout
  turned at random, each finger jittered by up to 15 degrees), normals to the centre, mu in
  [0.3, 1.0], mu_spin in [0.005, 0.02] m; forces N(0, 5 N), torques N(0, 0.1 N m);
- pinch: two point contacts facing each other across a 2-8 cm object (normals tilted up to 5
  degrees), mu in [0.3, 1.0], holding its weight (0.1-1 kg, centre of mass on the line between
  the contacts: no pinch resists a torque about that line, and no load here has one);
- feet: a humanoid's eight foot-corner point contacts (two 22 x 12 cm soles 20 cm apart, ground
  normals tilted up to 5 degrees), mu in [0.5, 1.0], its weight (60-100 kg) at a centre of mass 0.9
  m up over the support polygon.
The pinch and the feet are not force-closure: their loads are the weight plus a random
disturbance d scaled to a fraction of alpha*, the largest scale the contacts resist (found by
bisection on Clarabel's tight answers): half of them at 0.2 alpha* (small), half at 0.95-0.999
alpha* (near the limit). The force-closure families resist every load, and sigma scales with the
load, so their loads are random directions.

Clarabel is timed without the record built from its solution (`Prepared.solve_raw`: the
update and the solve alone; the record would add ~15 %).

Every call is timed alone (perf_counter_ns, garbage collector off) after an untimed warm-up pass
(which builds the grasp's start table, as any second call does), in three passes: "median" is the
median over calls of each call's least, "single" the median of the first timed pass alone.
Accuracy: every feasible sigma against Clarabel with tight tolerances (relative), and the number of
loads whose feasibility differs. Writes benchmarks/results/families.md.
"""
import argparse
import math
import os
import sys

import numpy as np

import graspforce as gf
from benchmarks.grasp_sets import ingot_grasp, random_wrenches
from benchmarks.ray_shoot import _cpu_name, _timed_passes, core_description

HERE = os.path.dirname(os.path.abspath(__file__))
GRAVITY = np.array([0.0, 0.0, -9.81])
LAYOUTS = {                                 # unit directions of the fingers before the turn
    3: [(math.cos(a), math.sin(a), 0.0) for a in np.deg2rad([0.0, 120.0, 240.0])],
    4: [(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)],
    5: [(0, 0, 1), (0, 0, -1)] + [(math.cos(a), math.sin(a), 0.0)
                                  for a in np.deg2rad([0.0, 120.0, 240.0])],
}


def rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def tilted(v, rng, degrees):
    """v turned by up to `degrees` about a random axis normal to it."""
    axis = np.cross(v, rng.normal(size=3))
    axis /= np.linalg.norm(axis)
    a = np.deg2rad(rng.uniform(0.0, degrees))
    return v * math.cos(a) + np.cross(axis, v) * math.sin(a) + axis * (axis @ v) * (1 - math.cos(a))


def weight_wrench(mass, com):
    """The weight of `mass` at `com` as a wrench about the origin (force, torque)."""
    f = mass * GRAVITY
    return np.concatenate((f, np.cross(com, f)))


def sphere(m):
    def make(rng, k):
        turn = rotation(rng)
        contacts = []
        for d in LAYOUTS[m]:
            x = tilted(turn @ (np.asarray(d, float) / np.linalg.norm(d)), rng, 15.0)
            contacts.append(gf.Contact(0.05 * x, -x, rng.uniform(0.3, 1.0),
                                       rng.uniform(0.005, 0.02)))
        loads = np.hstack([rng.normal(0.0, 5.0, (k, 3)), rng.normal(0.0, 0.1, (k, 3))])
        return gf.Grasp(contacts), loads
    return make


def ingot(rng, k):
    return ingot_grasp(), random_wrenches(k, int(rng.integers(2**31)))


def pinch(rng, k):
    axis = rotation(rng)[:, 0]
    half = rng.uniform(0.01, 0.04)
    mu = rng.uniform(0.3, 1.0)
    grasp = gf.Grasp([gf.Contact(half * axis, tilted(-axis, rng, 5.0), mu),
                      gf.Contact(-half * axis, tilted(axis, rng, 5.0), mu)])
    base = weight_wrench(rng.uniform(0.1, 1.0), rng.uniform(-half, half) * axis)
    scale = np.concatenate((np.full(3, 2.0), np.full(3, 0.02)))
    return grasp, limit_loads(grasp, base, scale, rng, k, blind=axis)


def feet(rng, k):
    contacts = []
    mu = rng.uniform(0.5, 1.0)
    for y in (0.1, -0.1):
        for dx in (0.11, -0.11):
            for dy in (0.06, -0.06):
                contacts.append(gf.Contact([dx, y + dy, 0.0],
                                           tilted(np.array([0.0, 0.0, 1.0]), rng, 5.0), mu))
    com = np.array([rng.uniform(-0.08, 0.08), rng.uniform(-0.12, 0.12), 0.9])
    base = weight_wrench(rng.uniform(60.0, 100.0), com)
    scale = np.concatenate((np.full(3, 100.0), np.full(3, 30.0)))
    grasp = gf.Grasp(contacts)
    return grasp, limit_loads(grasp, base, scale, rng, k)


FAMILIES = {"ingot": ingot, "sphere-3": sphere(3), "sphere-4": sphere(4), "sphere-5": sphere(5),
            "pinch": pinch, "feet": feet}


def limit_loads(grasp, base, scale, rng, k, blind=None):
    """k loads base + s alpha* d (d random, scaled per component by `scale`): s = 0.2 for the
    first half, s in [0.95, 0.999] for the rest; alpha* by bisection on Clarabel's tight answers.
    `blind`: an axis through the origin about which the contacts make no torque (a pinch's);
    d's torque about it is removed."""
    from graspforce.grasping.baselines import clarabel_socp
    truth = clarabel_socp.Prepared(grasp, "L1", "normal", tight=True)

    def holds(w):
        return truth.solve(w).status == "optimal"

    if not holds(base):
        raise ValueError("the family's base load is not resisted")
    loads = []
    while len(loads) < k:
        d = rng.normal(size=6) * scale
        if blind is not None:
            d[3:] -= (d[3:] @ blind) * blind
        lo, hi = 0.0, 1.0
        while holds(base + hi * d) and hi < 1e6:
            lo, hi = hi, 2.0 * hi
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if holds(base + mid * d) else (lo, mid)
        s = 0.2 if len(loads) < k // 2 else rng.uniform(0.95, 0.999)
        loads.append(base + s * lo * d)
    return np.array(loads)


def run_family(name, grasps, loads, method, eps, log):
    from graspforce.grasping.baselines import clarabel_socp
    rng = np.random.default_rng(sum(map(ord, name)))
    row = {"family": name}
    cases = [FAMILIES[name](rng, loads) for _ in range(grasps)]
    row["contacts"] = len(cases[0][0])
    for norm in ("L1", "Linf"):
        ours_t, ours_1, iters, base_t, rel, disagree, feasible, statuses = [], [], [], [], [], 0, 0, {}
        for grasp, ws in cases:
            times, res = _timed_passes(
                lambda w: grasp.min_force(w, norm, method=method, eps=eps), ws)
            t, t1 = times.min(axis=0), times[0]
            prepared = clarabel_socp.Prepared(grasp, norm, "normal")
            bt = _timed_passes(prepared.solve_raw, ws)[0].min(axis=0)
            tight = clarabel_socp.Prepared(grasp, norm, "normal", tight=True)
            for r, w in zip(res, ws):
                truth = tight.solve(w)
                statuses[r.status] = statuses.get(r.status, 0) + 1
                disagree += r.feasible != (truth.status == "optimal")
                if r.feasible and truth.status == "optimal":
                    rel.append(abs(r.sigma - truth.sigma) / truth.sigma)
                feasible += r.feasible
            ours_t.append(t)
            ours_1.append(t1)
            base_t.append(bt)
            iters += [r.iterations for r in res]
        ours_t, ours_1, base_t = (np.concatenate(x) / 1e3 for x in (ours_t, ours_1, base_t))
        row[norm] = dict(median=np.median(ours_t), single=np.median(ours_1),
                         p90=np.percentile(ours_t, 90), iters=np.median(iters),
                         iters90=np.percentile(iters, 90), clarabel=np.median(base_t),
                         ratio=np.median(base_t) / np.median(ours_t), max_rel=max(rel, default=0.0),
                         disagree=disagree, feasible=feasible, n=len(ours_t), statuses=statuses)
        log(f"{name} {norm}: {row[norm]['median']:.1f} us (p90 {row[norm]['p90']:.1f}), "
            f"{row[norm]['iters']:g} iterations, {row[norm]['ratio']:.1f}x Clarabel")
    return row


def report(rows, grasps, loads, method, eps):
    lines = [f"## min_force on grasp families ({method}, eps = {eps:g}, {grasps} grasps x {loads} "
             "loads a family)\n",
             "Times in us: median of each call's least of three passes, the first pass's median "
             "(single), p90 of the least; iterations median / p90; Clarabel (updated SOCP, its "
             "solve alone) median and its ratio to ours; max rel sigma against Clarabel with tight tolerances; loads "
             "whose feasibility differs from it.\n"]
    for norm in ("L1", "Linf"):
        lines += [f"### sigma_{norm}\n",
                  "| family | contacts | feasible | median | single | p90 | iters | Clarabel "
                  "| ratio | max rel sigma | disagree | statuses |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for row in rows:
            r = row[norm]
            lines.append(
                f"| {row['family']} | {row['contacts']} | {r['feasible']}/{r['n']} | "
                f"{r['median']:.1f} | {r['single']:.1f} | {r['p90']:.1f} | {r['iters']:g} / "
                f"{r['iters90']:g} | {r['clarabel']:.1f} | {r['ratio']:.1f}x | "
                f"{r['max_rel']:.1e} | {r['disagree']} | "
                + ", ".join(f"{k} {v}" for k, v in sorted(r["statuses"].items())) + " |")
        lines.append("")
    import clarabel
    lines.append(f"Command: `python -m benchmarks.families --grasps {grasps} --loads {loads} "
                 f"--method {method}`. Environment: numpy {np.__version__}, "
                 f"{core_description()}, clarabel {clarabel.__version__}, {_cpu_name()}.")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grasps", type=int, default=12)
    ap.add_argument("--loads", type=int, default=60)
    ap.add_argument("--method", default="zc-ie")
    ap.add_argument("--eps", type=float, default=1e-9)
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--out", default=os.path.join(HERE, "results", "families.md"))
    args = ap.parse_args(argv)
    log = lambda s: print(s, file=sys.stderr)  # noqa: E731
    rows = [run_family(f, args.grasps, args.loads, args.method, args.eps, log)
            for f in args.families.split(",")]
    text = report(rows, args.grasps, args.loads, args.method, args.eps)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    print(text)


if __name__ == "__main__":
    main()
