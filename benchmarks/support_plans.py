"""One support call of the compiled kernel, by the program's plan against the general passes.

A program whose plan is not GENERAL (graspforce.geometry._kernel: the soft fingers' wrench sets,
bare or lifted; sums of posed 3-D bodies) is evaluated by a loop of its own; the same program with
its plan entry set to GENERAL runs the four passes every other program runs. Both are timed here in
one process, round by round (least of ROUNDS), inside a compiled loop over random unit directions
(graspforce._core.timing.support_loop), after checking that they return the same value, point
and witnesses. Sets: the ingot grasp's W_L1 (R^6) and W_Linf's lift (R^9, what min_force shoots
for Linf); a two-point-contact pinch's W_L1 in its wrenches' span (R^5, an affine image of a hull
of ellipses: what min_force shoots for it); the growth protocol's
Delta = R_A(A_0) - R_B(B_0) (an ellipsoid and a truncated cone, leaves the plan evaluates in
registers), the same for a box and a polytope (leaves it evaluates by the passes' leaf code), and,
as a program that keeps the passes, a capsule's Delta (a sum under each pose).

    python -m benchmarks.support_plans
"""
import numpy as np

import graspforce as gf
from benchmarks.families import FAMILIES
from benchmarks.grasp_sets import ingot_grasp
from benchmarks.growth_sets import protocol_pairs
from graspforce.geometry import _kernel as K
from graspforce._core import timing
from graspforce.grasping.wrench_space import lift_rows, lift_summand

ROUNDS = 7
DIRECTIONS = 1000
REPS = 100


def _loop(ints, floats, U, reps, ws):
    """ns per support call over `reps` sweeps of U's rows, from a compiled loop."""
    ns, _ = timing.support_loop(ints, floats, U, np.empty(U.shape[1]), np.empty(ws), 1, reps)
    return ns[0]


def sets():
    """{name: convex set} timed here."""
    grasp = ingot_grasp()
    W = grasp.contact_sets()
    pair = protocol_pairs(1)[0]
    poses = ((pair["R_e"], pair["p_e"]), (pair["R_c"], pair["p_c"]))
    vertices = np.random.default_rng(0).normal(size=(20, 3))
    deltas = {}
    for name, A, B in (
            ("ellipsoid, cone", gf.Ellipsoid(np.zeros(3), np.diag(pair["axes"])),
             gf.TruncatedCone(pair["rb"], pair["rt"], pair["h"])),
            ("box, polytope", gf.Box([0.3, 0.5, 0.7]), gf.Polytope(vertices - vertices.mean(0))),
            ("capsule, cone", gf.Capsule(0.3, 1.0),
             gf.TruncatedCone(pair["rb"], pair["rt"], pair["h"]))):
        growth = gf.GrowthDistance(A, B, warm_start=False)
        growth(*poses)                                                  # writes the poses
        deltas[f"growth Delta ({name})"] = growth.delta
    pinch, loads = FAMILIES["pinch"](np.random.default_rng(0), 1)
    return {"ingot W_L1": gf.hull(*W),
            "ingot W_Linf lift": gf.hull(*[lift_summand(W_i, e)
                                           for W_i, e in zip(W, lift_rows(len(W)))]),
            "pinch W_L1 in its span": pinch.min_force(loads[0]).shot.convex_set,
            **deltas}


def _general(ints):
    copy = ints.copy()
    copy[-1] = K.GENERAL
    return copy


def _same_answers(A, U):
    """Largest difference between the plan's and the passes' value, point and witness."""
    ints, floats = A.program
    worst = 0.0
    for u in U:
        out = []
        for program in (ints, _general(ints)):
            point, wit = np.empty(A.dim), np.empty(A.witness_size)
            h = K.support(program, floats, u, point, wit)
            out.append(np.concatenate(([h], point, wit)))
        worst = max(worst, np.abs(out[0] - out[1]).max())
    return worst


def main():
    rows = []
    for name, A in sets().items():
        ints, floats = A.program
        U = np.random.default_rng(0).normal(size=(DIRECTIONS, A.dim))
        U /= np.linalg.norm(U, axis=1, keepdims=True)
        general = _general(ints)
        best = {"plan": np.inf, "general": np.inf}
        for program in (ints, general):
            _loop(program, floats, U, 1, A.witness_size)
        for _ in range(ROUNDS):
            for key, program in (("plan", ints), ("general", general)):
                best[key] = min(best[key], _loop(program, floats, U, REPS, A.witness_size))
        plan = {K.GENERAL: "GENERAL", K.ELLIPSOID_HULL: "ELLIPSOID_HULL",
                K.ELLIPSE_HULL: "ELLIPSE_HULL", K.POSED_SUM: "POSED_SUM",
                K.PROJECTED_ELLIPSOID_HULL: "PROJECTED_ELLIPSOID_HULL",
                K.PROJECTED_ELLIPSE_HULL: "PROJECTED_ELLIPSE_HULL"}[int(ints[-1])]
        rows.append((name, plan, best["plan"], best["general"], _same_answers(A, U[:200])))
    print("| set | plan | plan's loop (ns) | four passes (ns) | passes / plan | max difference |")
    print("|---|---|---|---|---|---|")
    for name, plan, ns_plan, ns_general, diff in rows:
        print(f"| {name} | {plan} | {ns_plan:.1f} | {ns_general:.1f} | "
              f"{ns_general / ns_plan:.2f} | {diff:.1e} |")


if __name__ == "__main__":
    main()
