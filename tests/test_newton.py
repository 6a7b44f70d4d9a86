"""The second-order finish of ZC-IE (core/geometry/piece.hpp, core/shooting/newton.hpp): the pieces'
supports and curvature against finite differences, the rank-revealing KKT solve against numpy, and
the finish itself against closed forms and SOCPs on the cases it was built for: smooth exits (a
growth rim contact), flat pieces (soft fingers whose friction is not saturated, an ellipsoid on a
cone's base), and two flat pieces sharing a direction (two fingers on one face)."""
import numpy as np
import pytest

import graspforce as gf
from graspforce._core import support
from graspforce._core.testing import (FLAT, basic_null_space, ellipsoid_finish, flat_columns,
                                      jacobian_size, newton_finish, piece_support, same_piece,
                                      solve_basic)

import truth as T
from conftest import random_rotation


def _sets(rng):
    R = random_rotation(rng, 3)
    return [
        gf.hull(*[gf.Ellipsoid(rng.normal(size=6), rng.normal(size=(6, 3))) for _ in range(4)]),
        gf.minkowski_sum(gf.pose(gf.Ellipsoid(np.zeros(3), np.diag([0.1, 0.2, 0.3])), R,
                                 np.zeros(3)),
                         -gf.pose(gf.TruncatedCone(0.1, 0.05, 0.2), R.T, np.zeros(3))),
        gf.affine(rng.normal(size=(6, 4)), gf.ConeCap(0.5, 4)),
        gf.minkowski_sum(gf.Polytope(rng.normal(size=(8, 3))), gf.Capsule(0.2, 0.5)),
        gf.Box([1.0, 2.0, 3.0], rng.normal(size=3), R),
        # an embedding [0; I] (min_force's Linf lift) over an ellipsoid and a cone cap
        gf.hull(gf.Polytope(rng.normal(size=(3, 8))),
                gf.affine(np.vstack((np.zeros((2, 6)), np.eye(6))),
                          gf.Ellipsoid(rng.normal(size=6), rng.normal(size=(6, 3))),
                          rng.normal(size=8)),
                gf.affine(np.vstack((np.zeros((2, 6)), np.eye(6))),
                          gf.affine(rng.normal(size=(6, 4)), gf.ConeCap(0.5, 4)))),
        # the lift's summands {e} x CH({0} U W_i) (one ORIGIN_EMBED node each), W_i off the
        # origin: directions choose an origin or an ellipsoid
        gf.hull(*[gf.affine(np.vstack((np.zeros((1, 6)), np.eye(6))),
                            gf.hull(gf.Polytope(np.zeros((1, 6))),
                                    gf.Ellipsoid(rng.normal(size=6), rng.normal(size=(6, 3)))),
                            np.r_[e, np.zeros(6)]) for e in (-0.5, 0.5)]),
    ]


def _piece(A, u, pw):
    ints, f = A.program
    size, nmax, _ = jacobian_size(ints, f)
    n = A.dim
    point, wit, J = np.empty(n), np.empty(A.witness_size), np.empty((n, n))
    h = piece_support(ints, f, np.asarray(u, float), pw, point, wit, J, np.empty(size), nmax)
    return h, point, wit, J


@pytest.mark.parametrize("which", range(7))
def test_piece_support_is_the_support_and_its_jacobian_the_derivative(which):
    rng = np.random.default_rng(which)
    A = _sets(rng)[which]
    ints, f = A.program
    n = A.dim
    for _ in range(20):
        u = rng.normal(size=n)
        point, wit = np.empty(n), np.empty(A.witness_size)
        h = support(ints, f, u, point, wit)
        hp, p, w2, J = _piece(A, u, wit)
        # on its own piece, the piece's support is the set's, with the same witness
        assert abs(hp - h) <= 1e-12 * (1 + abs(h))
        assert np.allclose(p, point, atol=1e-12)
        assert same_piece(ints, wit, w2)
        assert np.allclose(J, J.T, atol=1e-12)
        assert np.linalg.norm(J @ u) <= 1e-9 * (1 + np.abs(J).max()) * np.linalg.norm(u)
        d = 1e-6
        fd = np.column_stack([(_piece(A, u + d * e, wit)[1] - _piece(A, u - d * e, wit)[1])
                              / (2 * d) for e in np.eye(n)])
        assert np.abs(J - fd).max() <= 1e-6 * (1 + np.abs(J).max())


def test_flat_leaf_moves_along_its_columns():
    rng = np.random.default_rng(7)
    R = random_rotation(rng, 3)
    E = gf.pose(gf.Ellipsoid(np.zeros(3), np.diag([0.1, 0.2, 0.3])), R, np.zeros(3))
    A = gf.minkowski_sum(E, -gf.pose(gf.TruncatedCone(0.1, 0.05, 0.2), R.T, np.zeros(3)))
    ints, f = A.program
    size, nmax, qmax = jacobian_size(ints, f)
    cone = next(i for i in range(ints[0]) if ints[1 + i] == 3)
    w = ints[1 + 5 * ints[0] + cone]
    u = rng.normal(size=3)
    point, wit = np.empty(3), np.empty(A.witness_size)
    support(ints, f, u, point, wit)
    wit[w] = FLAT
    wit[w + 1:w + 3] = [0.01, -0.02]
    T_ = np.empty((3, 2))
    assert flat_columns(ints, f, cone, T_, 0, np.empty((nmax, qmax)), np.empty((nmax, qmax))) == 2
    h0, p0, w0, J = _piece(A, u, wit)
    for b in range(2):
        moved = wit.copy()
        moved[w + 1 + b] += 0.003
        assert np.allclose(_piece(A, u, moved)[1] - p0, 0.003 * T_[:, b], atol=1e-14)
    # the flat leaf adds no curvature, and its witness says where on the disk the point is
    assert w0[w] == 1.0 and np.allclose(w0[w + 1:w + 3], [0.01, -0.02])
    assert np.allclose(A.witness_point(A.decode_witness(w0)), p0, atol=1e-14)
    we = np.empty(E.witness_size)
    support(*E.program, u, np.empty(3), we)
    assert np.allclose(J, _piece(E, u, we)[3], atol=1e-14)


def test_flat_leaf_columns_through_an_embedding():
    # L S with L = [0; I] R (a pose under an embedding): the leaf's columns, zero-padded on top
    rng = np.random.default_rng(8)
    R = random_rotation(rng, 3)
    S = np.diag([0.1, 0.2, 0.3])
    A = gf.affine(np.vstack((np.zeros((2, 3)), np.eye(3))),
                  gf.pose(gf.Ellipsoid(np.zeros(3), S), R, rng.normal(size=3)), rng.normal(size=5))
    ints, f = A.program
    _, nmax, qmax = jacobian_size(ints, f)
    leaf = next(i for i in range(ints[0]) if ints[1 + i] == 1)
    T_ = np.empty((5, 3))
    assert flat_columns(ints, f, leaf, T_, 0, np.empty((nmax, qmax)), np.empty((nmax, qmax))) == 3
    assert np.allclose(T_, np.vstack((np.zeros((2, 3)), R @ S)), atol=1e-15)


@pytest.mark.parametrize("deficient", [0, 1, 3])
def test_solve_basic_solves_consistent_rank_deficient_systems(deficient):
    rng = np.random.default_rng(deficient)
    n = 9
    M = rng.normal(size=(n, n))
    for j in range(deficient):
        M[:, n - 1 - j] = M[:, :3] @ rng.normal(size=3)      # dependent columns
        M[n - 1 - j, :] = rng.normal(size=n - 1 - j) @ M[:n - 1 - j, :]   # dependent rows
    b = M @ rng.normal(size=n)                                 # consistent
    x = np.empty(n)
    rank = solve_basic(M.copy(), n, np.empty((n, n)), np.empty(n, np.int64),
                       np.empty(n, np.int64), b, x)
    assert rank == np.linalg.matrix_rank(M)
    assert np.linalg.norm(M @ x - b) <= 1e-10 * np.linalg.norm(b)
    if deficient == 0:
        assert np.allclose(x, np.linalg.solve(M, b))


@pytest.mark.parametrize("deficient", [1, 3])
def test_basic_null_space_spans_the_null_space(deficient):
    # the corner finish moves solve_basic's answer along these columns (core/shooting/newton.hpp)
    rng = np.random.default_rng(10 + deficient)
    n = 9
    M = rng.normal(size=(n, n))
    for j in range(deficient):
        M[:, n - 1 - j] = M[:, :3] @ rng.normal(size=3)
    lu, pcol = np.empty((n, n)), np.empty(n, np.int64)
    rank = solve_basic(M.copy(), n, lu, np.empty(n, np.int64), pcol, np.zeros(n), np.empty(n))
    assert rank == n - deficient
    Z = np.empty((n, n))
    basic_null_space(lu, pcol, n, rank, Z, np.empty(n))
    Z = Z[:, :n - rank]
    assert np.linalg.matrix_rank(Z) == n - rank
    assert np.linalg.norm(M @ Z) <= 1e-12 * np.linalg.norm(M) * np.linalg.norm(Z)


def _finish(A, r, loose):
    """The Newton finish started from the facet of an IE shot stopped at a loose eps."""
    res = gf.ray_shoot(A, r, method="ie", eps=loose)
    c = np.ascontiguousarray
    out = newton_finish(*A.program, c(r, float), 1e-9, c(res.vertices), c(res.witness_rows),
                        c(res.weights), len(res.weights), c(res.normal), res.t, False)
    return out


def _check_certificate(A, r, out, t_true):
    ok, t, t_up, h, m, steps, calls, normal, V, lam, W = out
    assert ok
    V, lam, W = V[:m], lam[:m], W[:m]
    assert abs(t - t_true) <= 1e-9 * t_true
    assert t <= t_up and (t_up - t) <= 1e-9 * t
    assert np.all(lam >= 0) and abs(lam.sum() - 1) <= 1e-12
    assert np.linalg.norm(lam @ V - t * r) <= 1e-11 * (1 + np.linalg.norm(t * r))
    ints, f = A.program
    hh = support(ints, f, normal, np.empty(A.dim), np.empty(A.witness_size))
    assert abs(hh - h) <= 1e-12 * (1 + abs(h)) and abs(t_up - h / (normal @ r)) <= 1e-12 * t_up
    for v, w in zip(V, W):
        assert np.allclose(A.witness_point(A.decode_witness(w)), v, atol=1e-12)
    return m


def test_finish_on_soft_fingers_with_unsaturated_friction():
    """4 soft fingers: most minimum-force answers leave some contact's friction inside its
    cone, the whole ellipse W_i then lies in the exit face (a flat piece). Truth: SOCP."""
    from benchmarks.grasp_sets import ingot_ellipsoids, random_wrenches
    E = ingot_ellipsoids()
    A = gf.hull(*[gf.Ellipsoid(c, S) for c, S in E])
    desc = T.hull(*[T.ell(c, S) for c, S in E])
    finished = 0
    for w in random_wrenches(20, seed=11):
        r = -w
        hit, t_true = T.ray_shoot_socp(desc, r)[:2]
        assert hit
        t_ref = gf.ray_shoot(A, r, method="ie", eps=1e-12).t   # the SOCP is good to ~1e-8
        assert abs(t_ref - t_true) <= 1e-7 * t_true
        out = _finish(A, r, 1e-3)
        if out[0]:
            _check_certificate(A, r, out, t_ref)
            finished += 1
    assert finished >= 17


def test_ellipsoid_finish_on_soft_fingers_around_a_sphere():
    """Four soft fingers around a sphere (benchmarks/families.py), every active contact's friction
    saturated on most loads: the ellipsoid path takes the facet, and its answer is the SOCP's,
    ZC-IE's within eps. A facet with a flat piece is handed over (False,)."""
    from benchmarks.families import FAMILIES
    rng = np.random.default_rng(21)
    c = np.ascontiguousarray
    taken = handed = finished = 0
    for _ in range(3):
        grasp, loads = FAMILIES["sphere-4"](rng, 15)
        A = grasp.wrench_set("L1")
        desc = T.hull(*[T.ell(e.center, e.shape) for e in A.sets])
        ints, f = A.program
        for w in loads:
            r = c(-w, float)
            res = gf.ray_shoot(A, r, method="ie", eps=1e-2)
            out = ellipsoid_finish(ints, f, r, 1e-9, c(res.witness_rows), c(res.weights),
                                   len(res.weights), c(res.normal), res.t)
            if not out[0]:
                handed += 1
                continue
            taken += 1
            if not out[1]:
                continue
            finished += 1
            t_ref = gf.ray_shoot(A, r, method="zc-ie", eps=1e-9).t
            assert abs(out[2] - t_ref) <= 1e-9 * t_ref
            t_socp = T.ray_shoot_socp(desc, r)[1]
            assert abs(out[2] - t_socp) <= 1e-7 * t_socp
            _check_certificate(A, r, out[1:], t_ref)
    assert taken >= 30 and finished >= 0.9 * taken and handed >= 1


@pytest.mark.parametrize("case", ["side", "rim", "base"])
def test_finish_on_the_growth_protocol(case):
    """Ellipsoid touching a truncated cone (growth protocol): g = 1, i.e. the ray r = p_B - p_A
    leaves Delta at z = r, t = 1 (eq. 10). Rim: one smooth piece; side: the two disks; base: the
    disk flat (the ellipsoid rests on the whole base)."""
    from benchmarks.growth_sets import protocol_pairs
    for p in protocol_pairs(20, seed=3, cases=(case,)):
        A = gf.minkowski_sum(gf.pose(gf.Ellipsoid(np.zeros(3), np.diag(p["axes"])), p["R_e"],
                                     np.zeros(3)),
                             -gf.pose(gf.TruncatedCone(p["rb"], p["rt"], p["h"]), p["R_c"],
                                      np.zeros(3)))
        r = p["p_c"] - p["p_e"]
        out = _finish(A, r, 1e-2)
        _check_certificate(A, r, out, 1.0)


def test_finish_with_two_flat_pieces_sharing_a_direction():
    """Two fingers side by side on one face, both well inside friction: their flat pieces share
    the spin direction [0; n], so the KKT system is singular and its weights are not unique."""
    n_ = np.array([0.0, 0.0, 1.0])
    contacts = [gf.Contact([x, y, -0.05], n_, 0.8, 0.05) for x, y in [(0.02, 0.0), (-0.02, 0.0)]]
    contacts += [gf.Contact([0.05, 0.0, 0.0], [-1.0, 0.0, 0.0], 0.8, 0.05),
                 gf.Contact([-0.05, 0.0, 0.0], [1.0, 0.0, 0.0], 0.8, 0.05)]
    A = gf.Grasp(contacts).wrench_set("L1")
    r = -np.array([0.1, 0.05, -3.0, 0.0, 0.0, 0.0])
    t_ref = gf.ray_shoot(A, r, method="ie", eps=1e-12).t
    _check_certificate(A, r, _finish(A, r, 1e-2), t_ref)


@pytest.mark.parametrize("case", ["side", "rim", "base"])
def test_zc_ie_newton_growth_is_exact_and_needs_fewer_support_calls(case):
    """Through the public API: on touching pairs (truth g = 1, scaled by 2: g = 2 and 0.5) the
    finished answer is exact to rounding, where ZC-IE stops at its eps, and it takes a fraction
    of ZC-IE's support calls (counted, not timed)."""
    from benchmarks.growth_sets import protocol_pairs
    calls = {"zc-ie": [], "zc-ie-newton": []}
    for p in protocol_pairs(15, seed=9, cases=(case,)):
        for scale, truth in [(1.0, 1.0), (0.5, 2.0), (2.0, 0.5)]:
            A = gf.Ellipsoid(np.zeros(3), np.diag(p["axes"] * scale))
            B = gf.TruncatedCone(p["rb"] * scale, p["rt"] * scale, p["h"] * scale)
            for method in calls:
                res = gf.growth_distance(A, (p["R_e"], p["p_e"]), B, (p["R_c"], p["p_c"]),
                                         method=method)
                assert abs(res.sigma - truth) <= (1e-12 if method == "zc-ie-newton" else 1e-8)
                gap = np.linalg.norm(res.point_a - res.point_b)
                assert gap <= 0.5e-9 * np.linalg.norm(p["p_c"] - p["p_e"])
                calls[method].append(res.support_calls)
    assert np.median(calls["zc-ie-newton"]) <= 0.6 * np.median(calls["zc-ie"])


def _steps(res):
    return (res.status, res.t, res.t_upper, res.iterations, res.support_calls)


@pytest.mark.parametrize("which", range(1, 6))
def test_default_zc_ie_takes_the_papers_steps_where_its_finish_does_not_apply(which):
    """"zc-ie" tries the Newton finish's smooth path on smooth hulls only (a root hull of
    ellipsoid leaves, W_L1, or of embeddings {e} x CH({0} U E), W_Linf's lift); on any other set
    (a sum, a cone cap, a box, an embedding under a hull with a polytope) it is "zc-ie-paper",
    step for step: the same t, bracket, iterations and support calls (both after the set's
    second shot, which builds its start table)."""
    rng = np.random.default_rng(100 + which)
    A = _sets(rng)[which]
    for method in ("zc-ie", "zc-ie-paper"):
        gf.ray_shoot(A, rng.normal(size=A.dim), method)
    for _ in range(20):
        r = rng.normal(size=A.dim)
        assert _steps(gf.ray_shoot(A, r, "zc-ie")) == _steps(gf.ray_shoot(A, r, "zc-ie-paper"))


def test_default_zc_ie_on_embeddings_with_their_origins(check_hit):
    """The lift's summands {e} x CH({0} U E) (an ORIGIN_EMBED node each): the smooth path's
    pieces are the ellipsoids' points and the embeddings' origins; its answers certify (the
    conftest's checks against an SOCP) in fewer steps than the paper's ZC-IE."""
    rng = np.random.default_rng(106)
    A = _sets(rng)[6]
    d = T.hull(*[T.affine(e.matrix, T.hull(T.poly(np.zeros((1, 6))),
                                           T.ell(e.inner.sets[1].center, e.inner.sets[1].shape)),
                          e.offset) for e in A.sets])
    iterations = {"zc-ie": [], "zc-ie-paper": []}
    for _ in range(20):
        # as the lift's rays: (0, the mean of a point of each CH({0} U E_i))
        r = np.zeros(A.dim)
        for e in A.sets:
            E = e.inner.sets[1]
            y = rng.normal(size=3)
            r[1:] += 0.5 * rng.uniform(0.2, 1.0) * (E.center + E.shape @ y / np.linalg.norm(y))
        hit, t_true, t_up = T.ray_shoot_socp(d, r)[:3]
        assert hit
        for method in iterations:
            res = gf.ray_shoot(A, r, method)
            # the conic truth is good to its certified gap
            check_hit(A, d, r, res, t_true, method, t_rtol=1e-9 + abs(t_up - t_true) / t_true,
                      exact=False, t_true_upper=t_up)
            iterations[method].append(res.iterations)
    assert np.median(iterations["zc-ie"]) < np.median(iterations["zc-ie-paper"])


def _linf_iterations(cases, label):
    """min_force Linf by "zc-ie" and "zc-ie-paper" on (grasp, loads) cases: every answer
    certifies itself (test_certificates.check_optimal) and the two agree within eps; their
    iterations."""
    from grasp_cases import plain
    from test_certificates import check_optimal
    iterations = {"zc-ie": [], "zc-ie-paper": []}
    for grasp, loads in cases:
        P = plain(grasp)
        for w in loads:
            res = {method: grasp.min_force(w, "Linf", method=method) for method in iterations}
            for method, r in res.items():
                check_optimal(grasp, P, w, r, (label, method))
                iterations[method].append(r.iterations)
            assert abs(res["zc-ie"].sigma / res["zc-ie-paper"].sigma - 1) <= 2e-9
    return iterations


def test_default_zc_ie_on_the_lift():
    """On W_Linf's lift, a hull of embeddings {e_i} x CH({0} U W_i) (which min_force's zc-ie
    shoots only where the sum's finish does not apply; forced here), where the contacts that
    push hardest saturate friction (soft fingers around a sphere), the smooth path finishes the
    shot; every answer certifies itself (test_certificates.check_optimal) and agrees with the
    paper's ZC-IE within eps, in at most half its median iterations."""
    from benchmarks.families import FAMILIES
    rng = np.random.default_rng(9)
    cases = [FAMILIES[f"sphere-{m}"](rng, 12) for m in (3, 4)]
    for grasp, _ in cases:
        space = grasp._space("Linf", "normal")
        space._by_method[("zc-ie", False)] = space._target(True, space.length)
        assert space.target("zc-ie").set.dim == 5 + len(grasp.contacts)
    iterations = _linf_iterations(cases, "lift")
    assert np.median(iterations["zc-ie"]) <= 0.5 * np.median(iterations["zc-ie-paper"])


def test_default_zc_ie_on_the_linf_sum():
    """min_force Linf with zc-ie shoots W_Linf itself, a sum of CH({0} U E_i), with the Newton
    finish on the contacts' states (core/shooting/sum_finish.hpp: on, off, pushing less than the
    most, with friction saturated or not): on five soft fingers every answer certifies itself
    (test_certificates.check_optimal) and agrees with the paper's ZC-IE on the lift within eps,
    in at most half its median iterations. Ten point contacts around a sphere (past the lift's
    eight: the sum for every method) finish the same way, in at most half the iterations of the
    paper's steps on the sum. A humanoid's eight foot corners, whose faces are degenerate (rows
    of collinear corners, states read too flat that the finish demotes), within 0.75 of the
    paper's median."""
    from benchmarks.families import FAMILIES
    rng = np.random.default_rng(13)
    soft = [FAMILIES["sphere-5"](rng, 12) for _ in range(2)]
    loads = np.hstack((rng.normal(0.0, 5.0, (12, 3)), rng.normal(0.0, 0.1, (12, 3))))
    points = []
    for _ in range(2):
        p = rng.standard_normal((10, 3))
        p = 0.05 * p / np.linalg.norm(p, axis=1)[:, None]
        points.append((gf.Grasp([gf.Contact(x, -x / 0.05, rng.uniform(0.4, 1.0)) for x in p]),
                       loads))
    feet = [FAMILIES["feet"](rng, 12) for _ in range(2)]
    for label, cases, most in (("soft", soft, 0.5), ("point", points, 0.5), ("feet", feet, 0.75)):
        iterations = _linf_iterations(cases, label)
        ratio = np.median(iterations["zc-ie"]) / np.median(iterations["zc-ie-paper"])
        assert ratio <= most, (label, ratio)


def test_default_zc_ie_on_the_full_magnitudes_l1_is_the_general_finish():
    """On W_L1 of the full magnitude (cone caps, which the smooth path does not take)
    min_force's "zc-ie" runs the Newton finish's general path, zc-ie-newton's steps: every answer
    certifies itself and agrees with the paper's ZC-IE within eps, in at most half its median
    iterations. On W_Linf of the full magnitude it stays the paper's."""
    from benchmarks.families import FAMILIES
    from grasp_cases import plain
    from test_certificates import check_optimal
    rng = np.random.default_rng(12)
    iterations = {"zc-ie": [], "zc-ie-paper": []}
    for family in ("ingot", "sphere-4", "feet"):
        grasp, loads = FAMILIES[family](rng, 10)
        P = plain(grasp)
        for norm in ("L1", "Linf"):
            # the sets' start tables, built at their second shot, before any compared call
            grasp.min_force(loads[0], norm, "full")
            grasp.min_force(loads[0], norm, "full")
        for w in loads:
            res = {method: grasp.min_force(w, "L1", "full", method)
                   for method in ("zc-ie", "zc-ie-newton", "zc-ie-paper")}
            check_optimal(grasp, P, w, res["zc-ie"], family)
            assert (res["zc-ie"].sigma, res["zc-ie"].iterations, res["zc-ie"].support_calls) == (
                res["zc-ie-newton"].sigma, res["zc-ie-newton"].iterations,
                res["zc-ie-newton"].support_calls)
            assert abs(res["zc-ie"].sigma / res["zc-ie-paper"].sigma - 1) <= 2e-9
            for method in iterations:
                iterations[method].append(res[method].iterations)
            linf = [grasp.min_force(w, "Linf", "full", m) for m in ("zc-ie", "zc-ie-paper")]
            assert (linf[0].sigma, linf[0].iterations) == (linf[1].sigma, linf[1].iterations)
    assert np.median(iterations["zc-ie"]) <= 0.5 * np.median(iterations["zc-ie-paper"])


def test_default_zc_ie_on_growth_is_the_papers():
    """Growth distance shoots at Δ, a sum of two posed shapes: "zc-ie" answers exactly as
    "zc-ie-paper"."""
    from benchmarks.growth_sets import protocol_pairs
    for p in protocol_pairs(10, seed=4):
        A = gf.Ellipsoid(np.zeros(3), np.diag(p["axes"]))
        B = gf.TruncatedCone(p["rb"], p["rt"], p["h"])
        a, b = (gf.growth_distance(A, (p["R_e"], p["p_e"]), B, (p["R_c"], p["p_c"]), method=m)
                for m in ("zc-ie", "zc-ie-paper"))
        assert (a.status, a.sigma, a.iterations, a.support_calls) == \
            (b.status, b.sigma, b.iterations, b.support_calls)


def test_default_zc_ie_finishes_saturated_grasps_in_a_third_of_the_steps():
    """Soft fingers around a sphere (benchmarks/families.py), where the minimum saturates
    friction at every active contact and the paper's ZC-IE takes ~60 steps: "zc-ie" answers
    within eps of the SOCP with its full certificate (test_certificates.check_optimal, recomputed
    with truth.py), in at most 0.4 of the paper's procedure's median iterations; answers of both
    agree to eps."""
    from benchmarks.families import FAMILIES
    from grasp_cases import plain
    from test_certificates import check_optimal
    rng = np.random.default_rng(8)
    iterations = {"zc-ie": [], "zc-ie-paper": []}
    for m in (3, 4, 5):
        for _ in range(2):
            grasp, loads = FAMILIES[f"sphere-{m}"](rng, 10)
            P = plain(grasp)
            for w in loads:
                sigma_socp = T.min_force_socp(P, w, "L1", "normal")[1]
                res = {method: grasp.min_force(w, method=method) for method in iterations}
                for method, r in res.items():
                    check_optimal(grasp, P, w, r, (m, method))
                    assert abs(r.sigma - sigma_socp) <= 1e-7 * sigma_socp
                    iterations[method].append(r.iterations)
                assert abs(res["zc-ie"].sigma / res["zc-ie-paper"].sigma - 1) <= 2e-9
    assert np.median(iterations["zc-ie"]) <= 0.4 * np.median(iterations["zc-ie-paper"])
