"""Force closure and Ferrari-Canny quality on the exact cones, against LPs on pyramids and
against the closed-form support of W_L1."""
import math

import numpy as np
import pytest
import scipy.optimize
from grasps import box_grasp, random_grasp, sphere_grasp, two_finger_pinch
from scipy.spatial import ConvexHull

from graspforce.baselines.pyramid import generators


def origin_interior_lp(wrenches):
    """0 is interior to CH(wrenches) iff they span R^6 and some lambda >= s > 0 with
    sum lambda_j w_j = 0, sum lambda = 1 exists: maximize s (HiGHS)."""
    k = len(wrenches)
    if np.linalg.matrix_rank(wrenches, tol=1e-9) < 6:
        return False
    c = np.zeros(k + 1)
    c[-1] = -1.0
    A_eq = np.zeros((7, k + 1))
    A_eq[:6, :k] = np.asarray(wrenches).T
    A_eq[6, :k] = 1.0
    b_eq = np.r_[np.zeros(6), 1.0]
    A_ub = np.hstack((-np.eye(k), np.ones((k, 1))))       # s - lambda_j <= 0
    res = scipy.optimize.linprog(c, A_ub=A_ub, b_ub=np.zeros(k), A_eq=A_eq, b_eq=b_eq,
                                 bounds=[(0, None)] * k + [(None, None)], method="highs")
    return res.status == 0 and -res.fun > 1e-9


def primitive_wrenches(grasp, faces, outer):
    """G_i g for the generators g of each contact's inscribed pyramid, or of a circumscribed one:
    the inscribed cross-section scaled by 1 / (its inradius), which then contains the exact
    ellipse/ellipsoid cross-section."""
    out = []
    for c in grasp.contacts:
        g = generators(c, faces)
        if outer and c.mu > 0:
            # cross-section points in the unit-ball coordinates of eq. (12)
            scale = np.array([1 / c.mu, 1 / c.mu] + ([1 / c.mu_spin] if c.mu_spin > 0 else []))
            cols = [1, 2, 3] if c.mu_spin > 0 else [1, 2]
            pts = g[:, cols] * scale
            if len(cols) == 2:
                inradius = math.cos(math.pi / faces)
            else:
                inradius = -ConvexHull(pts).equations[:, -1].max()
            g = g.copy()
            g[:, cols] /= inradius
        out.extend(c.matrix @ gi for gi in g)
    return np.array(out)


def test_force_closure_agrees_with_pyramid_lps():
    rng = np.random.default_rng(3)
    decided = 0
    total = 0
    verdicts = set()
    for m in [2, 2, 3, 3, 3, 4, 4, 4, 5, 6] * 2:
        grasp = random_grasp(rng, m, ("soft", "point"))
        inner = origin_interior_lp(primitive_wrenches(grasp, 16, outer=False))
        outer = origin_interior_lp(primitive_wrenches(grasp, 16, outer=True))
        total += 1
        if inner == outer:                 # both pyramids agree: the exact cone must too
            decided += 1
            assert grasp.is_force_closure() == inner, grasp.contacts
            verdicts.add(inner)
    assert decided >= 0.8 * total and verdicts == {True, False}


@pytest.mark.parametrize("grasp, closure", [(box_grasp(), True), (two_finger_pinch(), False),
                                            (sphere_grasp(0.5), True)])
def test_known_grasps(grasp, closure):
    assert grasp.is_force_closure() == closure
    q = grasp.quality()
    assert q.force_closure == closure
    if not closure:
        assert q.value == q.lower == q.upper == 0.0


def support_l1(grasp, u):
    """h of W_L1 in closed form (NOTES.md item 3): max_i c_i.u + ||S_i^T u||."""
    best = -np.inf
    for c in grasp.contacts:
        G = c.matrix
        S = G[:, 1:] @ np.diag([c.mu, c.mu, c.mu_spin])
        best = max(best, G[:, 0] @ u + np.linalg.norm(S.T @ u))
    return best


def test_quality_bracket_is_certified():
    grasp = box_grasp()
    eps = 1e-6
    q = grasp.quality(eps=eps)
    assert q.force_closure and 0 < q.lower <= q.value <= q.upper
    assert q.upper - q.lower <= eps * q.upper
    # upper = h_W(direction), recomputed independently
    assert np.linalg.norm(q.direction) == pytest.approx(1.0)
    assert support_l1(grasp, q.direction) == pytest.approx(q.upper, rel=1e-12)
    # lower: the ball of that radius is inside W, so no direction may have a smaller support
    rng = np.random.default_rng(0)
    U = rng.normal(size=(2000, 6))
    U /= np.linalg.norm(U, axis=1)[:, None]
    assert min(support_l1(grasp, u) for u in U) >= q.lower
    # nor may a local minimization of h_W on the unit sphere, from many starts
    def h(x):
        return support_l1(grasp, x / np.linalg.norm(x))
    for x0 in U[:8]:
        res = scipy.optimize.minimize(h, x0, method="Nelder-Mead",
                                      options={"xatol": 1e-10, "fatol": 1e-14, "maxiter": 4000})
        assert res.fun >= q.lower * (1 - 1e-12)


def test_non_closure_direction_cannot_be_resisted():
    grasp = two_finger_pinch()
    q = grasp.quality()
    assert not q.force_closure
    # h_W(direction) ~ 0: no contact force has a positive component along it, so the wrench
    # -direction cannot be resisted
    assert support_l1(grasp, q.direction) <= 1e-9
