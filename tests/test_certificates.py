"""Every answer certifies itself, whatever the input: min_force says "optimal" only with forces in
their cones that resist w_ext to 1e-9 (relative) and a supporting hyperplane that bounds the
minimum from below to eps, "infeasible" only with a separating direction, and anything else
"max_iter" with an honest lower bound; a ray shot says "hit" only with t_upper / t - 1 <= eps and
weights that reproduce t r.

Nothing here trusts graspforce's own flags: every certificate is recomputed from the returned
forces, normal and points with the grasp maps of grasp_cases.plain and the closed-form supports
of truth.py, and feasibility is decided independently, with a margin, by the SOCPs of
truth.resist_margin.
"""
import collections
import math
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import graspforce as gf
import truth as T
from grasp_cases import plain, random_grasp, random_wrench
from test_grasp_forces import edge_of_cone_cases, wrench_normal

METHODS = list(gf.METHODS)
OBJECTIVES = [("L1", "normal"), ("Linf", "normal"), ("L1", "full"), ("Linf", "full")]
EPS = 1e-9                  # min_force's default eps
# the bound on the equilibrium residual of an "optimal" answer, relative to ||w_ext||
RESIDUAL = 1e-9
# forces are nonnegative combinations of unit forces on their cones' boundaries, each to a few
# ulps: outside the cone by at most this much, relative to f_1
CONE_TOL = 1e-12
# |margin| of -w_ext / ||w_ext|| from the boundary of the cone of wrenches the contacts resist
# (truth.resist_margin): beyond MARGIN every answer's verdict is truth's; between WRONG_MARGIN and
# MARGIN an answer may be "max_iter" (no verdict: near a curved face of that cone ZC's steps from
# the origin stop gaining at h_W(n) ~1e-11, and neither the polish of its normal nor the walk
# from outside separates a set that holds the origin, W_Linf's lift of full magnitude; seen up to
# 4e-5), never the wrong verdict; below WRONG_MARGIN (the SOCPs' own accuracy is ~1e-8) the ray
# grazes W and feasibility is not compared, only the certificates
MARGIN = 1e-4
WRONG_MARGIN = 1e-7


# --- certificates, recomputed from what the answer returns ----------------------------------------
def grasp_size(P, norm, magnitude):
    """A bound on the size of W: its support along the axes (for rounding tolerances)."""
    return max(T.grasp_support(P, e, norm, magnitude) for e in np.vstack((np.eye(6), -np.eye(6))))


def rounding(P, res, n, h):
    """The relative rounding of a bound n.r / h_W(n): both supports are rounded to ~1e-16 of W's
    size, which is large relative to h where n is nearly orthogonal to W's points."""
    return 1e-12 + 1e-14 * grasp_size(P, res.norm, res.magnitude) * np.linalg.norm(n) / h


def check_optimal(grasp, P, w, res, ctx):
    """The certificate of an "optimal" answer: forces in their cones, in equilibrium with w_ext to
    RESIDUAL, sigma their objective, and the answer's normal (re-evaluated with truth's support)
    bounding the minimum from below within eps of sigma; its shot a certified hit."""
    assert res.feasible and math.isfinite(res.sigma), ctx
    forces = np.asarray(res.forces)
    for c, f in zip(grasp.contacts, forces):
        assert T.cone_excess(c, f) <= CONE_TOL, (ctx, "cone", c.kind, f)
    wrenches = np.array([G @ f for (G, _, _), f in zip(P, forces)])
    resultant = wrenches.sum(axis=0)
    assert np.linalg.norm(resultant + w) <= RESIDUAL * np.linalg.norm(w), \
        (ctx, "residual", np.linalg.norm(resultant + w) / np.linalg.norm(w))
    sigma = T.contact_objective(forces, P, res.norm, res.magnitude)
    assert res.sigma == pytest.approx(sigma, rel=1e-14), (ctx, res.sigma, sigma)
    # the bracket [sigma_lower, sigma] within eps, either way (the forces resist w_ext only to
    # RESIDUAL, so sigma may fall a little below a bound on the minimum for w_ext itself)
    assert res.sigma_lower <= res.sigma * (1 + EPS), (ctx, "bracket", res.sigma_lower, res.sigma)
    assert res.sigma / res.sigma_lower - 1 <= EPS + 1e-15, (ctx, res.sigma, res.sigma_lower)
    # weak duality: for any n with n.r > 0, n.r / h_W(n) bounds the minimum for r from below.
    # For the wrench these forces resist exactly (their resultant), sigma may not lie below it;
    # for -w_ext it is the answer's sigma_lower, recomputed with truth's support, within eps of
    # sigma either way (the forces resist w_ext only to RESIDUAL)
    n = wrench_normal(res)
    h = T.grasp_support(P, n, res.norm, res.magnitude)
    assert n @ resultant > 0 and n @ (-w) > 0, ctx
    # a normal nearly orthogonal to r bounds nothing to eps: n.r, a sum of 6 products, is
    # rounded by up to 6 ulps of ||n|| ||r|| in the units the shot is made in, (force,
    # torque / L) (Grasp.length), where n's torque part is L times the one returned
    units = np.r_[1.0, 1.0, 1.0, np.full(3, grasp.length)]
    dot_rounding = (6 * np.finfo(float).eps * np.linalg.norm(n * units)
                    * np.linalg.norm(w / units) / (n @ (-w)))
    assert dot_rounding <= EPS, (ctx, "normal", n)
    lower_own = (n @ resultant) / h
    assert lower_own <= res.sigma * (1 + rounding(P, res, n, h)), \
        (ctx, "weak duality", lower_own, res.sigma)
    lower = (n @ (-w)) / h
    assert lower <= res.sigma * (1 + EPS), (ctx, "lower", lower, res.sigma)
    assert res.sigma / lower - 1 <= EPS * (1 + 1e-6) + rounding(P, res, n, h), \
        (ctx, "gap", lower, res.sigma)
    check_hit(res.shot, ctx)


def check_hit(shot, ctx):
    """A RayShot's "hit": t_upper / t - 1 <= eps and weights >= 0, summing to 1, that reproduce
    t r to 1e-9 (relative) with its vertices."""
    assert shot.hit and shot.status == "hit", ctx
    t, t_up = float(shot.t), float(shot.t_upper)
    assert 0.0 < t <= t_up and t_up / t - 1 <= EPS * (1 + 1e-6), (ctx, t, t_up)
    weights, vertices = np.asarray(shot.weights), np.asarray(shot.vertices)
    assert np.all(weights >= 0.0) and abs(weights.sum() - 1.0) <= 1e-12, (ctx, weights)
    point = t * np.asarray(shot.r)
    assert np.linalg.norm(weights @ vertices - point) <= 1e-9 * np.linalg.norm(point), ctx


def check_infeasible(P, w, res, ctx):
    """The certificate of "infeasible": a direction n with n.r > 0 in which W does not extend (to
    rounding: 1e-11 of the length of W's points, which in R^6 is at most sqrt(6) times its
    largest extent along an axis); no forces."""
    assert not res.feasible and res.sigma == math.inf, ctx
    assert not np.asarray(res.forces).any(), ctx
    n = wrench_normal(res)
    assert n @ (-w) > 0, ctx
    h = T.grasp_support(P, n, res.norm, res.magnitude)
    size = math.sqrt(6.0) * grasp_size(P, res.norm, res.magnitude)
    assert h <= 1e-11 * size * np.linalg.norm(n), (ctx, h)


def check_open(P, w, res, ctx):
    """A "max_iter" answer claims only its lower bound: sigma_lower at most what its normal
    proves (re-evaluated with truth's support)."""
    assert res.status == "max_iter", ctx
    if res.sigma_lower > 0.0:
        n = wrench_normal(res)
        r = -np.asarray(w, dtype=float)
        assert n @ r > 0, ctx
        h = T.grasp_support(P, n, res.norm, res.magnitude)
        if h <= 0.0:
            return                          # n separates: any lower bound holds
        lower = (n @ r) / h
        assert res.sigma_lower <= lower * (1 + rounding(P, res, n, h)), \
            (ctx, res.sigma_lower, lower)


def check_answer(grasp, P, w, res, margin, ctx):
    """The answer's own certificate; with |margin| >= MARGIN, its verdict is truth's. Returns the
    status."""
    if res.status == "optimal":
        check_optimal(grasp, P, w, res, ctx)
    elif res.status == "infeasible":
        check_infeasible(P, w, res, ctx)
    else:
        check_open(P, w, res, ctx)
    truth = "optimal" if margin > 0 else "infeasible"
    if abs(margin) >= MARGIN:
        assert res.status == truth, (ctx, res.status, margin)
    elif abs(margin) >= WRONG_MARGIN:
        assert res.status in (truth, "max_iter"), (ctx, res.status, margin)
    return res.status


# --- the random problems --------------------------------------------------------------------------
LOADS = ("random", "near", "edge")


def random_problem(rng):
    """(grasp, w_ext, load kind): 2 to 8 point and soft contacts (two and three most often, which
    are rarely force-closure), and a load drawn at random (inside or outside of what they
    resist), near the boundary of that cone (a random wrench projected onto it, moved in or out
    by 1e-2 to 1e-12 of its size) or on the edge of the contacts' friction cones (every contact
    pushing along an edge, perturbed by 1e-15)."""
    m = int(rng.choice([2, 2, 2, 3, 3, 4, 5, 6, 7, 8]))
    grasp = random_grasp(rng, m, ("soft", "point"))
    kind = LOADS[int(rng.integers(len(LOADS)))]
    if kind == "random":
        return grasp, random_wrench(rng), kind
    if kind == "edge":
        w = np.zeros(6)
        for W_i in grasp.contact_sets():
            w -= rng.uniform(0.2, 1.0) * W_i.support(rng.normal(size=6))[1]
        return grasp, w * (1.0 + 1e-15 * rng.normal(size=6)), kind
    x = -random_wrench(rng)
    x /= np.linalg.norm(x)
    p, u = T.resist_projection(plain(grasp), x)
    if u is None:                          # x resisted (force closure): no boundary near it
        return grasp, -x, "random"
    step = 10.0 ** rng.choice([-2, -4, -6, -8, -12]) * rng.choice([-1.0, 1.0])
    return grasp, -(p + step * np.linalg.norm(p) * u), kind


def answers(grasp, P, w, margin, combos, label):
    statuses = []
    for method, (norm, magnitude) in combos:
        res = grasp.min_force(w, norm, magnitude, method=method)
        ctx = (label, method, norm, magnitude)
        statuses.append((method, norm, magnitude, check_answer(grasp, P, w, res, margin, ctx)))
    return statuses


PROBLEMS = 2000


def test_every_answer_certifies_itself():
    """PROBLEMS random grasps, one load each; every objective, the methods in turn (each set is
    shot once: no start tables here, which test_start_table.py and the tests below exercise).
    Seeded, deterministic."""
    rng = np.random.default_rng(20261127)
    began = time.perf_counter()
    count = collections.Counter()
    statuses = collections.Counter()
    by_combo = collections.Counter()
    for i in range(PROBLEMS):
        grasp, w, kind = random_problem(rng)
        P = plain(grasp)
        margin = T.resist_margin(P, w)
        count[kind + " load"] += 1
        band = ("resisted" if margin >= MARGIN else "not resisted" if margin <= -MARGIN
                else "no verdict required" if abs(margin) >= WRONG_MARGIN else "skipped")
        count[band] += 1
        # force closure, decided independently: a ball around 0 in the resisted cone, or a
        # wrench proven out of it (the load, or another one at random)
        other = random_wrench(rng)
        if T.resist_depth(P, np.zeros(6)) > 0.0:
            count["force-closure"] += 1
        elif margin <= -WRONG_MARGIN or T.resist_margin(P, other) <= -WRONG_MARGIN:
            count["not force-closure"] += 1
        combos = [(METHODS[(i + j) % len(METHODS)], objective)
                  for j, objective in enumerate(OBJECTIVES)]
        for method, norm, magnitude, status in answers(grasp, P, w, margin, combos, i):
            statuses[status] += 1
            by_combo[(method, norm, magnitude)] += 1
            if band == "no verdict required" and status == "max_iter":
                count["answers without the verdict, 1e-7 to 1e-4 from the boundary"] += 1
    elapsed = time.perf_counter() - began
    print(f"\n{PROBLEMS} grasps, {sum(statuses.values())} answers in {elapsed:.1f} s: "
          f"{dict(count)}; {dict(statuses)}")
    # the population asked for: at least a third not force-closure, loads resisted, not
    # resisted and near the boundary, every method with every objective
    assert count["not force-closure"] >= PROBLEMS / 3
    assert count["force-closure"] >= PROBLEMS / 10
    assert min(count["resisted"], count["not resisted"]) >= PROBLEMS / 10
    assert count["near load"] >= PROBLEMS / 5
    assert len(by_combo) == len(METHODS) * len(OBJECTIVES)
    assert min(by_combo.values()) >= PROBLEMS * len(OBJECTIVES) / len(by_combo) - 1
    # feasibility is compared on all but the problems within the margin of the boundary
    assert count["skipped"] + count["no verdict required"] <= PROBLEMS / 4


# A smaller companion driven by Hypothesis: every method and objective on each example. Examples
# it once failed on are kept as explicit cases: 4217156846, an L1 "optimal" whose normal was
# 2.6e-9 from orthogonal to r (the bound uncertain by ~1e-6), and
# 1001519568, a Linf full-magnitude "optimal" with sigma 6.7e-12 below sigma_lower; 1619936146
# and 1381803462, W_Linf's lift (full magnitude) 4e-5 and 1e-5 from the resisted cone, "max_iter"
# where the verdict was required within 1e-5.
@settings(max_examples=40, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1))
@example(seed=0)
@example(seed=4217156846)
@example(seed=1001519568)
@example(seed=1619936146)
@example(seed=1381803462)
def test_every_method_and_objective_certifies_itself(seed):
    rng = np.random.default_rng(seed)
    grasp, w, kind = random_problem(rng)
    P = plain(grasp)
    margin = T.resist_margin(P, w)
    answers(grasp, P, w, margin,
            [(method, objective) for method in METHODS for objective in OBJECTIVES],
            (seed, kind))


# --- regressions: grasps that cannot hold their load ----------------------------------------------
# Three point contacts that cannot hold a 7 N weight: every method but GJK-based answered
# "infeasible" after one iteration, as does the SOCP; GJK-based answered "optimal" with sigma
# 4.93e12 and an equilibrium residual of 0.28 (sigma 5.32e12 with sigma_lower 5.54e12 for the full
# magnitude): its walk down the ray reached t ~ 1e-13, where GJK took t r for a point of W (the
# origin, on W's boundary, is within its rounding floor).
THREE_POINT_CONTACTS_UNDER_A_WEIGHT = (
    ([0.03567522563517225, 0.1325304011021182, 0.03840047982950859],
     [-0.2503193285452432, -0.9299148197399706, -0.269441388403186], 0.40603910967496404, 0.0),
    ([-0.03906906108323974, -0.07221068714880793, 0.11649399520626091],
     [0.27413256575475736, 0.506674601184844, -0.8173935312362661], 0.7496771805803712, 0.0),
    ([-0.0641247247946329, 0.1271132053974002, -0.006471358061196922],
     [0.4499385152568079, -0.8919044423068908, 0.04540702899038129], 0.9404836817222624, 0.0),
    [0.0, 0.0, -6.998092187753288, 0.0, 0.0, 0.0])

# Two contacts (random grasps of grasp_cases, seeds 72, 90, 243, 354, 54, 231) that GJK-based
# called feasible, "optimal" with sigma up to 5e12 or forces whose resultant missed w_ext by up to
# 6% (and 0 for one Linf problem): the ray leaves W at the origin or misses W, by margins of
# 2e-3 to 0.66 (truth.resist_margin).
TWO_CONTACTS = [
    (([0.05083352758330275, -0.01051550539034034, 0.019128006473977735],
      [-0.9686849054057299, -0.21663681661803655, 0.12131794477609306], 0.6068978921322337, 0.0),
     ([-0.00865124206375277, -0.015000315898535378, 0.009213004076235551],
      [0.986865297809138, -0.160861570959521, 0.014847187225749618], 0.8103192045136653, 0.0),
     [-2.918178963179963, 2.6376471569443445, -6.4253499507001, 0.25162402954280827,
      0.22536332792732133, 0.0236272537118118]),
    (([0.09736399479660642, 0.004543817038827162, 0.02022627242738912],
      [-0.9801774792606965, 0.00705210475085639, -0.1979959013937658], 0.750800052601386, 0.0),
     ([-0.010320486618855193, 0.028835921983546148, -0.01969044210000674],
      [-0.10905524405108988, -0.9939756665131682, 0.010923741330711239], 0.6463496252279419,
      0.0),
     [3.038036886583322, -2.5217588153032366, -9.707882600483416, 0.12559769571754273,
      0.07565490326599693, -0.16901551862606043]),
    (([-0.004318764953796829, -0.09838410679586862, 0.08511015541522374],
      [-0.25081699996086415, -0.12421112191669735, -0.9600325149300034], 0.6893334795365835,
      0.0),
     ([-0.07470753869667798, -0.07370205697918594, -0.1043037276556637],
      [-0.07682117804220182, 0.07119714136834757, 0.9944996096857877], 0.5499339709426962, 0.0),
     [1.1849225663825498, -5.2849818202987775, 1.6936927261524668, 0.19917523337363197,
      0.1435107175682597, 0.02248349783714484]),
    (([0.018654323524384463, -0.020217182765435347, -0.06450528846318528],
      [-0.12909430907467395, 0.07859498100514227, 0.9885127658889055], 0.8828836244556137, 0.0),
     ([0.015488606089773795, -0.046075464416293496, 0.05742714554380071],
      [0.5125439064658066, 0.8569610947178113, -0.054003945085716], 0.9170978540889851, 0.0),
     [-1.9753008694868996, -7.547909458338062, 1.2886818574664178, 0.08654764077444142,
      -0.1133710517969429, -0.22687294022094437]),
    (([-0.039622456951769115, 0.03067421667534028, 0.0060085982835449275],
      [-0.0039398723589903605, -0.9916916729806468, 0.12857722639192715], 0.815255765059304,
      0.0),
     ([-0.03985353216277862, -0.037979276888892445, 0.040369667772965835],
      [0.14806007464976076, 0.9889206575336085, 0.010683978566193604], 0.2888841307110722, 0.0),
     [1.2497401023453774, -1.7057499684551303, 4.092129881067667, 0.47910058684966955,
      0.412704834987375, 0.1025544444637177]),
    (([0.007367705189935774, -0.03387763486232716, -0.03159344313895085],
      [0.04535225994059805, 0.7950299528315015, 0.604872339108858], 0.9270550115329568,
      0.031280509770123546),
     ([0.0018323187942958772, 0.03329184556060602, 0.014825348539272197],
      [-0.013533915215228655, -0.9996351896062831, -0.023373507219872563], 0.5045329315439906,
      0.030405912447481503),
     [8.976520506678224, -2.264099008967736, -9.769400881218761, 0.00212156072598723,
      0.3372035070631181, -0.2685508698069981]),
]


def grasp_of(case):
    *contacts, w = case
    return gf.Grasp([gf.Contact(p, n, mu, mu_s) for p, n, mu, mu_s in contacts]), np.array(w)


def check_cannot_hold(grasp, w, method, label):
    """Every objective infeasible, certified; the ray shot at W itself a certified miss (never a
    hit: it leaves W at the origin or misses it)."""
    P = plain(grasp)
    for norm, magnitude in OBJECTIVES:
        ctx = (label, method, norm, magnitude)
        assert T.min_force_socp(P, w, norm, magnitude)[0] == "infeasible", ctx
        check_infeasible(P, w, grasp.min_force(w, norm, magnitude, method=method), ctx)
        shot = gf.ray_shoot(grasp.wrench_set(norm, magnitude), -w, method=method)
        assert shot.status == "miss" and shot.t == 0.0, (ctx, shot)
        n = np.asarray(shot.normal)
        h = T.grasp_support(P, n, norm, magnitude)
        assert n @ (-w) > 0 and h <= 1e-11 * math.sqrt(6.0) * grasp_size(P, norm, magnitude), \
            (ctx, h)


@pytest.mark.parametrize("method", METHODS)
def test_three_point_contacts_cannot_hold_a_weight(method):
    grasp, w = grasp_of(THREE_POINT_CONTACTS_UNDER_A_WEIGHT)
    check_cannot_hold(grasp, w, method, "three point contacts under a weight")


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("case", range(len(TWO_CONTACTS)))
def test_two_contacts_that_cannot_hold_their_load(case, method):
    grasp, w = grasp_of(TWO_CONTACTS[case])
    assert T.resist_margin(plain(grasp), w) <= -1e-3       # clearly infeasible
    check_cannot_hold(grasp, w, method, case)


# --- the two-point-contact corner -----------------------------------------------------------------
def two_point_contact_cases():
    """The edge-of-cone cases of test_grasp_forces.py with two point contacts: w = -(lam_1 s_1 +
    lam_2 s_2), s_i on the edges of the friction cones, whose minimum is sum(lam) (L1) or
    max(lam) (Linf) exactly, at a corner of W."""
    cases = [c for c in edge_of_cone_cases(60, weights_first=False) if c[4]]
    cases += [c for c in edge_of_cone_cases(40, weights_first=True) if c[4]]
    return [(grasp, lams, w) for _, grasp, lams, w, _ in cases]


@pytest.mark.parametrize("method", METHODS)
def test_two_point_contact_corners_certify_when_perturbed(method):
    # Perturbed by 1e-15 (relative), the ray passes within rounding of the corner of W where
    # z_W(r) lies: ZC's cone from b_k idles there, GJK's simplex one step above it loses rank,
    # and 0.3-1% of the L1 shots (depending on the CPU) ended "max_iter" with an open bracket
    # (12% of the shots of the methods that shoot W_Linf itself). Now every shot is certified: at
    # least 1000 for L1 and 250 for Linf, each "optimal" with its certificate and the exact
    # minimum.
    cases = two_point_contact_cases()
    rng = np.random.default_rng(15)
    shots = collections.Counter()
    for grasp, lams, w in cases:
        P = plain(grasp)
        for norm, repeats in (("L1", 56), ("Linf", 14)):
            truth = sum(lams) if norm == "L1" else max(lams)
            for k in range(repeats):
                wp = w * (1.0 + 1e-15 * rng.normal(size=6))
                res = grasp.min_force(wp, norm, method=method)
                ctx = (method, norm, k, lams)
                assert res.status == "optimal", (ctx, res)
                check_optimal(grasp, P, wp, res, ctx)
                assert abs(res.sigma / truth - 1.0) <= 2e-9, (ctx, res.sigma, truth)
                shots[norm] += 1
    assert len(cases) >= 18 and shots["L1"] >= 1000 and shots["Linf"] >= 250


# --- no step left is no hit -----------------------------------------------------------------------
@pytest.mark.parametrize("method", METHODS)
def test_a_shot_without_steps_is_not_a_hit(method):
    # IE's steps from a start table's facet with max_iter = 0 (only the compiled entry point
    # takes it) never queried a hyperplane: it reported a hit with t_upper = 0/0. Now such a shot
    # is "max_iter" with its honest bracket: t from the facet, t_upper from a hyperplane or inf.
    from graspforce import _core
    from graspforce.geometry._start_table import start_table
    from graspforce.shooting.ray_shoot import shot_layout
    A = gf.Ellipsoid(np.zeros(4), np.diag([1.0, 2.0, 0.5, 1.5]))
    r = np.array([0.3, -0.2, 1.0, 0.5])
    for _ in range(2):
        gf.ray_shoot(A, r, method=method)
    table = start_table(A)
    assert table.size > 0
    ints, floats, ws, size, compiled = shot_layout(A)
    packed = np.empty(size)
    head = compiled(ints, floats, r, ws, gf.METHODS[method], 1e-9, 0, packed, table)
    status, t, t_upper = head[0], head[1], head[2]
    assert status != _core.HIT, head
    assert t_upper >= t * (1 - 1e-12), head         # a bracket, possibly [t, inf)
    # with a few iterations, every hit is certified
    for max_iter in range(1, 6):
        shot = gf.ray_shoot(A, r, method=method, max_iter=max_iter)
        assert shot.status in ("hit", "max_iter"), shot
        if shot.hit:
            check_hit(shot, (method, max_iter))
