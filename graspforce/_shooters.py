"""The compiled ray-shooting procedures of section 3.

Every procedure returns the same tuple, packed by `_result`:
    (status, t, t_upper, h_n, iterations, support_calls, normal, V, weights, W, singular)
with z = t r a convex combination `weights` of the rows of V (points of A, witnesses in W), and
the hyperplane {x : normal^T x = h_n} supporting A (h_n = h_A(normal)) crossing the ray at
t_upper r. `singular` counts the iterations spent on a face of dimension < n - 1 (IE's
collections, ZC-IE's hand-overs to ZC-based steps). On a miss, normal separates:
h_A(normal) <= 0 < normal^T r.

Tolerance: every stopping rule is relative, (h_A(n) - n^T z) <= eps * n^T z, i.e.
(t_upper - t) / t <= eps, so eps bounds the relative error in t whatever the units of A
(../shared/paper/NOTES.md item 5).
"""
import numpy as np
from numba import njit
from numba.extending import register_jitable

from ._corral import drop_point, reproduce, residual2, set_row, weights_on_ray
from ._distance import CONVERGED, INSIDE, MAX_ITER, STALLED, gjk, scratch, scratch_of, zc
from ._jit import borrowing, view
from ._kernel import support
from ._linalg import dot, invert, lstsq, lu_factor, lu_solve, lu_solve_t, smallest
from ._newton import newton_finish

HIT = 0
MISS = 1
LIMIT = 2
FACET = 3   # internal: ZC-based iterations reached a facet the ray crosses (IE takes over)
# a ZC stall is a hit when its bracket is within eps or this (below it double precision cannot
# always certify: docs/core-api.md, "Numerical floor")
STALL_FLOOR = 1e-11

ZC_ONLY = 0
WITH_IE = 1
UNTIL_FACET = 2
WITH_NEWTON = 3   # ZC-IE with the Newton finish of graspforce._newton

GJK_BASED = 0
IE = 1
ZC_BASED = 2
BI_GJK = 3
ZC_IE = 4
ZC_IE_NEWTON = 5


# a hit's t_upper = h_A(n) / n^T r below t by at most this (relative) is rounding: the ray left
# through an exact face of A, whose hyperplane is the facet's own, and the bracket closes at t
FACE_ROUNDING = 1e-12


@register_jitable
def reported_upper(status, t, t_up):
    """t_upper as a result reports it: a hit's, below t by at most FACE_ROUNDING, is t."""
    if status == HIT and t * (1.0 - FACE_ROUNDING) <= t_up < t:
        return t
    return t_up


@njit(cache=True)
def _result(status, t, t_up, h_n, iters, calls, normal, P, lam, Wt, k, singular):
    # views, not copies: the shooter's arrays die with it, and every caller packs or reads the
    # result before shooting again (four allocations a shot saved)
    return (status, t, reported_upper(status, t, t_up), h_n, iters, calls, normal, P[:k],
            lam[:k], Wt[:k], singular)


@borrowing(forceinline=True)
def _keep(P, Wt, lam, k, Pz, Wz, lz, changed=-1):
    """Save the simplex holding the current point on the ray: it becomes Z_A(r) at the end.
    changed >= 0: Pz[:k], Wz[:k] already hold P[:k], Wt[:k] but for that row (an IE step
    replaces one vertex), which alone is copied. Element loops, not slices: a slice costs a
    reference-count round trip per call."""
    for j in range(k):
        if changed < 0 or j == changed:
            for i in range(P.shape[1]):
                Pz[j, i] = P[j, i]
            for i in range(Wt.shape[1]):
                Wz[j, i] = Wt[j, i]
        lz[j] = lam[j]
    return k


@borrowing
def _holds(P, lam, k, t, r, b, tol):
    """Whether the weights lam[:k] of the rows P[:k] reproduce t r (written to b) to tol
    relative, or to the sum's own rounding, 1e-14 sum_j lam_j ||P_j|| (about 50 unit roundoffs;
    it matters where the origin is near A's boundary and t r is far shorter than the points
    that make it: the paper's sphere at lambda = 1e-5). The point on the ray is then in A to
    that accuracy. Relative, unlike `reproduce`'s floor: A's units do not matter."""
    for i in range(r.shape[0]):
        b[i] = t * r[i]
    res, bb = residual2(P, lam, k, b)
    if res <= tol * tol * bb:
        return True
    mass = 0.0
    for j in range(k):
        pp = 0.0
        for i in range(P.shape[1]):
            pp += P[j, i] * P[j, i]
        mass += abs(lam[j]) * np.sqrt(pp)
    return res <= 1e-28 * mass * mass


# _holds: an IE step's facet weights, whose drift a fresh LU removes when they miss this
FACET_HOLDS = 1e-12
# _holds: ZC's and Bi-GJK's final point, which nothing re-solves: the bound on the
# equilibrium residual (a rounding floor of ~3e-10 is seen on the paper's sphere at
# lambda = 1e-6; ZC's loose INSIDE answers reproduce b_k to ~1e-8)
POINT_HOLDS = 1e-9


@njit(cache=True)
def _miss(ints, floats, r, ws, eps, iters, calls, max_iter):
    """A miss with its certificate: ZC from the origin finds n with h_A(n) < 0 < n^T r; or, when
    ZC finds r in CO(A), the hit that ZC-IE then computes."""
    n = r.shape[0]
    P = np.empty((n + 1, n))
    Wt = np.empty((n + 1, ws))
    lam = np.empty(n + 1)
    nvec = np.empty(n)
    v = np.empty(n)
    point = np.empty(n)
    wit = np.empty(ws)
    st, k, d, h, it, c = zc(ints, floats, np.zeros(n), r, P, Wt, lam, 0, 0.0, 0.0, max_iter,
                            nvec, v, point, wit, scratch(n))
    if st == INSIDE:
        # r is in CO(A) after all: the caller's miss test was rounding (seen with GJK on a flat
        # A whose affine span holds the ray), and the ray meets A. ZC-IE decides it.
        out = zc_family(ints, floats, r, ws, eps, max_iter, WITH_IE)
        return (out[0], out[1], out[2], out[3], out[4] + iters + it, out[5] + calls + c,
                out[6], out[7], out[8], out[9], out[10] + 1)
    status = MISS if st != MAX_ITER else LIMIT
    return _result(status, 0.0, 0.0, h, iters + it, calls + c, nvec, P, lam, Wt, 0, 0)


@borrowing
def _on_ray(P, k, r, t, eps, x, tol, sc):
    """Fig. 3b's improved stopping rule, the ray meets CH(V_A(b_k)): returns where, t' with
    barycentric weights x[:k] of t' r in CH(P[:k]), or -1. t' and the weights are solved
    together, P_0 + sum_j x_j (P_j - P_0) = t' r, so that t' r is in the hull to rounding: eq.
    (4)'s t = t_k - d_A(b_k) / n^T r carries the rounding of d_A(b_k), which put t r 1e-12
    (relative) outside an 8-D facet the least squares then still accepted. A ray along the
    face (the joint system is singular), or a t' more than eps from t, keeps eq. (4)'s t.
    sc: `scratch(n)`."""
    n = P.shape[1]
    D, work, rhs, wrhs, _, _ = sc
    tj = weights_on_ray(P, k, r, x, D, work, wrhs, rhs)
    if not (tj > 0.0 and abs(tj - t) <= eps * t):
        tj = t
        for i in range(n):
            rhs[i] = t * r[i] - P[0, i]
            for j in range(1, k):
                D[i, j - 1] = P[j, i] - P[0, i]
        if not lstsq(D, n, k - 1, rhs, x, 1, work, wrhs):
            return -1.0
        s = 1.0
        for j in range(1, k):
            s -= x[j]
        x[0] = s
    for j in range(k):
        if x[j] < -tol:
            return -1.0
    for i in range(n):
        rhs[i] = tj * r[i]
    return tj if reproduce(P, x, k, rhs) else -1.0


@njit(cache=True)
def _work(n, ws):
    """Work arrays of a shooter's GJK and ZC calls: (normal, v, point, witness, weights x,
    the subproblem's scratch)."""
    return np.empty(n), np.empty(n), np.empty(n), np.empty(ws), np.empty(n + 2), scratch(n)


INEXACT_GJK = 1.0   # gjk_based: GJK's tolerance, relative to the last step squared, until eps
TIGHTEN = 1e-2      # gjk_based: GJK's tolerance after an inexact direction that did not cut the ray


@njit(cache=True)
def gjk_based(ints, floats, r, ws, eps, max_iter):
    """Section 3.1: b_k outside A walks down the ray, stopped by Fig. 3b's rule.

    Eq. (4) steps to the hyperplane H(n_k, v_A(b_k)), which needs d_A(b_k) exactly: GJK run to
    eps at every b_k. The steps converge quadratically where A is curved (the tangent plane at
    v_A(b_k) crosses the ray within O(d^2) of z_A(r)), so an early step needs far less: while the
    last step moved t by a relative `step`, GJK stops at a relative gap of step^2 (the next
    step's expected size) and b_{k+1} is where the supporting hyperplane H(n_k, s_A(n_k))
    crosses the ray, outside A whatever GJK's accuracy. Once that tolerance reaches eps, eq. (4)
    and Fig. 3b's rule as written. (Ingot W_L1, 300 rays: median support calls 168 -> 80;
    INEXACT_GJK 0.1 gave 98, 0.01 106.) A direction from an unconverged GJK may not cut the ray
    below b at all, or even point away from it (n^T r <= 0, which only a converged GJK turns into
    a miss): GJK then goes on from the same b, TIGHTEN times tighter (62 -> 55 calls; before,
    such a ray fell into the miss test's ZC and was answered by ZC-IE, 59 of 300)."""
    n = r.shape[0]
    rr = dot(r, r)
    P = np.empty((n + 2, n))
    Wt = np.empty((n + 2, ws))
    lam = np.empty(n + 2)
    nvec, v, point, wit, x, sc = _work(n, ws)
    h0 = support(ints, floats, r, point, wit)
    calls = 1
    if h0 <= 0.0:
        return _miss(ints, floats, r, ws, eps, 0, calls, max_iter)
    t = h0 / rr
    t_up = t
    best_n = r / np.sqrt(rr)
    best_h = h0 / np.sqrt(rr)
    set_row(P, Wt, 0, point, wit)
    lam[0] = 1.0
    k = 1
    t_floor = -1.0   # max(-h_A(-r), 0) / r^T r, evaluated when first needed
    eps_gjk = max(eps, INEXACT_GJK)
    for it in range(max_iter):
        b = t * r
        st, k, d, h, gi, gc = gjk(ints, floats, b, P, Wt, lam, k, eps_gjk, 0.0, True,
                                  max_iter, nvec, v, point, wit, sc)
        calls += gc
        if st == INSIDE:
            # b_k = t r is in A: it met the boundary, or rounding in v_A(b_{k-1}) put it inside.
            # Done if the last supporting hyperplane certifies it; else GJK has reached its
            # numerical floor (ingot W_L1: 255 of 300 rays).
            if t_up - t <= eps * t:
                # GJK's weights reproduce b only to its distance floor: on a face, solve
                # again with t free, as Fig. 3b's rule does
                t_ray = _on_ray(P, k, r, t, eps, x, 1e-12, sc) if k <= n else -1.0
                if t_ray > 0.0:
                    t = t_ray
                    for j in range(k):
                        lam[j] = x[j]
                return _result(HIT, t, t_up, best_h, it + 1, calls, best_n, P, lam, Wt, k, 0)
            return _finish_inside(ints, floats, r, ws, eps, max_iter, t, P, Wt, lam, k, it + 1,
                                  calls)
        if st == MAX_ITER:
            return _result(LIMIT, t, t_up, best_h, it + 1, calls, best_n, P, lam, Wt, k, 0)
        rn = dot(r, nvec)
        exact = eps_gjk <= eps
        if not exact and (rn <= 0.0 or h >= t * rn):
            # an unconverged direction whose hyperplane does not cut the ray below b tells
            # nothing yet (n^T r <= 0 is no miss before GJK converges): tighten, same b
            eps_gjk = max(eps, TIGHTEN * eps_gjk)
            continue
        if rn <= 0.0:
            return _miss(ints, floats, r, ws, eps, it + 1, calls, max_iter)
        t_next = t - d / rn if exact else min(h / rn, t)
        if t_floor < 0.0:
            t_floor = max(-support(ints, floats, -r, point, wit), 0.0) / rr
            calls += 1
        if t_next < t_floor:
            return _miss(ints, floats, r, ws, eps, it + 1, calls, max_iter)
        if h / rn < t_up:
            t_up = h / rn
            best_n[:] = nvec
            best_h = h
        step = (t - t_next) / t_next if t_next > 0.0 else 0.0
        t = t_next
        t_ray = _on_ray(P, k, r, t, eps, x, 1e-12, sc) if exact and st == CONVERGED else -1.0
        if t_ray > 0.0:
            for j in range(k):
                lam[j] = x[j]
            return _result(HIT, t_ray, t_up, best_h, it + 1, calls, best_n, P, lam, Wt, k, 0)
        eps_gjk = max(eps, INEXACT_GJK * step * step)
    return _result(LIMIT, t, t_up, best_h, max_iter, calls, best_n, P, lam, Wt, k, 0)


@borrowing
def _zc_step(ints, floats, r, t, P, Wt, lam, k, eps, max_iter, nvec, v, point, wit, b, sc):
    """One ZC-based iteration (section 3.3) from b_k = t r (written to b): ZC on A - b_k toward
    r."""
    for i in range(r.shape[0]):
        b[i] = t * r[i]
    # purely relative: an absolute floor would accept h > eps n^T b when n^T r is small
    return zc(ints, floats, b, r, P, Wt, lam, k, eps, 0.0, max_iter, nvec, v, point, wit, sc)


REFACTOR = 64   # IE steps between fresh factorizations of the facet matrix
# "zc-ie-newton" tries the Newton finish (graspforce._newton, docs/core-api.md) once an IE step's
# relative gap is at most NEWTON_GAP; after a failed try, the next waits for the gap to shrink by
# NEWTON_RETRY
NEWTON_GAP = 0.1
NEWTON_RETRY = 1e-2
# the secant query (ZC-IE from a facet whose points' support directions are known: `zc_from`'s
# `directions`): a secant point must keep at least SECANT_HOLD of the weight of t r in the next
# facet, and its query's gap must be at most SECANT_GAIN times the last query's, else
# SECANT_REST plain IE steps follow before the next try. Measured on the growth protocol and on
# random pairs (BENCHMARKS.md, "Stop 28"): 0.9 and 4 (support calls, protocol median 26 -> 19;
# 0.5 or 1 step of rest tried secant queries on flat pieces too often); the gain rule, 0.5,
# catches secant points that keep their weight but not their pace (random pairs' mean 22.2 ->
# 19.1 calls; 0.25 and 0.1 were worse)
SECANT_HOLD = 0.9
SECANT_REST = 4
SECANT_GAIN = 0.5


@borrowing(forceinline=True)
def _facet_matrix(P, n, M):
    """M = [P_0 .. P_{n-1}]: the facet's points as columns."""
    for j in range(n):
        for i in range(n):
            M[i, j] = P[j, i]


@borrowing
def _factor_facet(P, n, M, lu, piv):
    """LU of [P_0 .. P_{n-1}] (facet points as columns) into lu, piv; False when singular."""
    _facet_matrix(P, n, M)
    return lu_factor(M, n, lu, piv)


@borrowing
def _solve_facet(P, n, r, M, lu, piv, ones, y, gam):
    """y (the facet's hyperplane y^T x = 1) and gam (r = sum gam_l P_l) by LU solves on a fresh
    factorization of [P_0 .. P_{n-1}], left in lu, piv; False when singular."""
    if not _factor_facet(P, n, M, lu, piv):
        return False
    lu_solve_t(lu, piv, n, ones, y)
    lu_solve(lu, piv, n, r, gam)
    return True


@borrowing
def _invert(P, n, M, piv, B):
    """B = [P_0 .. P_{n-1}]^{-1} (facet points as columns); False when singular."""
    _facet_matrix(P, n, M)
    return invert(M, n, B, piv)


@borrowing(forceinline=True)
def _matvec(B, n, x, out):
    for i in range(n):
        s = 0.0
        for j in range(n):
            s += B[i, j] * x[j]
        out[i] = s


@borrowing(forceinline=True)
def _matvec_t_ones(B, n, out):
    """out = B^T 1: the facet's hyperplane y^T x = 1."""
    for j in range(n):
        out[j] = 0.0
    for i in range(n):
        for j in range(n):
            out[j] += B[i, j]


@borrowing(forceinline=True)
def _same_point(P, j, x):
    """Whether row j of P is x, exactly."""
    for i in range(x.shape[0]):
        if P[j, i] != x[i]:
            return False
    return True


@borrowing(forceinline=True)
def _pivot(B, n, alpha, js, y, gam):
    """Column js of the facet replaced by s, with B s = alpha (Sherman-Morrison, as in the
    revised simplex method): row js of the new inverse is B[js] / alpha_js, and every other
    row i loses alpha_i times it. y = B^T 1 and gam = B r follow in O(n): gam like a column
    of B, and y gains (1 - sum alpha) times the new row js (the column sums of the row
    operations). No test for alpha_i = 0: the loops stay branch-free, which LLVM unrolls in
    zc_from's versions compiled for one n."""
    inv = 1.0 / alpha[js]
    asum = 0.0
    for i in range(n):
        asum += alpha[i]
    for j in range(n):
        B[js, j] *= inv
        y[j] += (1.0 - asum) * B[js, j]
    gam[js] *= inv
    for i in range(n):
        if i != js:
            f = alpha[i]
            gam[i] -= f * gam[js]
            for j in range(n):
                B[i, j] -= f * B[js, j]


# zc_from gives up after this many ZC steps in a row that find b_k inside ZC's cone without
# moving it: a corner its steps never leave (W_Linf's lift of two point contacts at the edge of
# what they resist went on to max_iter, 10000 steps, t unchanged after the 23rd). Not 1: giving
# up at the first such step failed a doubled contact 1e-9 inside its cone's edge (Linf) once
IDLE_STEPS = 100
NEGLIGIBLE = 1e-6   # _restart: a relative weight this small leaves b on the face of the others


@borrowing
def _restart(P, Wt, lam, k, r, sc):
    """Warm start for the next ZC call (section 3.3) from b = sum_l lam_l P_l, the new point on
    the ray: the generators P_l - b are linearly dependent (sum_l lam_l (P_l - b) = 0), so one
    point must go. Drop the one whose loss leaves r_L, the part of r along aff(P[:k]), inside
    the cone of the others' generators: ZC's first residual is then r - r_L, normal to
    aff(P[:k]), and its first query IE's (the facet's normal when k = n). With
    r_L = sum_l beta_l (P_l - b) (beta_0 = 0, the others by least squares), the others' cone
    holds r_L iff beta - (beta_j / lam_j) lam >= 0: j = argmin_l beta_l / lam_l. (Ingot W_L1,
    ZC-based: median support calls 191 -> 36 against dropping the largest weight, which left
    ZC to find the outward direction by many small steps.) Points of weight below NEGLIGIBLE go
    first: b lies on the face of the others, and the rule applies there (kept, such a point was
    dropped and found again by every ZC call, with no progress: seen on a 6-D ball).
    sc: `scratch(n)`."""
    total = 0.0
    for l in range(k):
        total += lam[l]
    floor = NEGLIGIBLE * total
    l = k - 1
    while l >= 0 and k > 1:
        if lam[l] <= floor:
            total -= lam[l]
            k = drop_point(P, Wt, lam, k, l)
        l -= 1
    if k <= 1:
        return 0
    n = P.shape[1]
    D, work, rhs, wrhs, x, _ = sc
    for i in range(n):
        b = 0.0
        for l in range(k):
            b += lam[l] * P[l, i]
        b /= total
        for l in range(1, k):
            D[i, l - 1] = P[l, i] - b
        rhs[i] = r[i]
    j = 0
    if lstsq(D, n, k - 1, rhs, x, 1, work, wrhs):
        x[0] = 0.0
        best = np.inf
        for l in range(k):
            ratio = x[l] / lam[l] if lam[l] > 0.0 else -np.inf
            if ratio < best:
                best = ratio
                j = l
    else:
        # no direction space to speak of (the points nearly coincide): keep the spread-out ones
        for l in range(1, k):
            if lam[l] > lam[j]:
                j = l
    return drop_point(P, Wt, lam, k, j)


@njit(cache=True)
def zc_family(ints, floats, r, ws, eps, max_iter, mode):
    """Section 3.3 (ZC-based) and, with mode WITH_IE, section 3.4.2 (ZC-IE): ZC-based
    iterations, and plain IE steps whenever V_k has n points (a facet the ray crosses inside);
    with mode WITH_NEWTON, ZC-IE with the Newton finish (graspforce._newton)."""
    n = r.shape[0]
    none = np.empty((0, 0))
    return zc_from(ints, floats, r, ws, eps, max_iter, mode, 0.0, np.empty((n + 2, n)),
                   np.empty((n + 2, ws)), np.empty(n + 2), 0, 0, 0, none, none)


# zc_from's loop (`_zc_loop_of`) counts no references (graspforce._jit): it runs in arrays its
# caller allocates (`zc_work`) and stops, with its state in one of them, wherever
# something counted must act, its driver `zc_drive`: the Newton finish and the result record.
# Counted, the loop's ~20 views and its chain of callers took ~140 reference-count updates a
# growth query (BENCHMARKS.md, "Stop 29")
(ST_T, ST_K, ST_KZ, ST_IT, ST_CALLS, ST_SINGULAR, ST_AGE, ST_CHANGED, ST_FRESH, ST_NEWTON_GAP,
 ST_IDLE, ST_SECANT, ST_REST, ST_PACE, ST_LAST, ST_PENDING, ST_T_UP, ST_H) = range(18)
STATE = 18
# the loop's stops besides the statuses HIT, MISS, LIMIT and FACET (the result's)
NEWTON_TRY = 4   # "zc-ie-newton": the last IE step asks for the Newton finish; resume after it
NEWTON_END = 5   # ZC's point could not be certified: the Newton finish, else LIMIT


@register_jitable
def zc_work_size(n, ws):
    """Entries of the work array of zc_from's loop in R^n, witnesses of ws entries
    (`loop_arrays`)."""
    return ((n + 10) * n + (n + 3) * ws + n + 2 + 4 * n * n + (2 * n + 5) * (n + 1) + n + 2
            + STATE)


@register_jitable
def zc_work(n, ws, room=0):
    """The work array of zc_from's loop (with `room` entries after the loop's for the caller)
    and its pivots."""
    return np.empty(zc_work_size(n, ws) + room), np.empty(n, np.int64)


@register_jitable
def loop_rows_state(work, n, ws):
    """The loop's rows ((n + 10) x n: the simplex P, then the n-vectors, the normal at n + 2)
    and its state (STATE entries, at the end of its work array), as views of `work`
    (graspforce._jit.view: shapes that LLVM sees). A pair: Numba refuses to compile a function
    without reference counts that returns an array it did not get."""
    return view(work, 0, (n + 10, n)), view(work, zc_work_size(n, ws) - STATE, STATE)


@register_jitable
def loop_arrays(work, n, ws):
    """The arrays of zc_from's loop as views of `work`: rows, witnesses ((n + 3) x ws), weights
    (n + 2), four n x n matrices, the subproblem's `scratch`, the state (`loop_rows_state`)."""
    rows, state = loop_rows_state(work, n, ws)
    a = (n + 10) * n
    b = a + (n + 3) * ws
    c = b + n + 2
    d = c + 4 * n * n
    e = d + (2 * n + 5) * (n + 1)
    return (rows, view(work, a, (n + 3, ws)), view(work, b, n + 2), view(work, c, (4, n, n)),
            scratch_of(view(work, d, (2 * n + 5, n + 1)), view(work, e, n + 2), n), state)


@register_jitable
def loop_result(code, work, n, ws, Pz, Wz, lz):
    """The result tuple of a loop that stopped with HIT, MISS, LIMIT or FACET."""
    rows, state = loop_rows_state(work, n, ws)
    t = state[ST_T]
    return _result(code, t, state[ST_T_UP], state[ST_H], int(state[ST_IT]),
                   int(state[ST_CALLS]), rows[n + 2], Pz, lz, Wz, int(state[ST_KZ]),
                   int(state[ST_SINGULAR]))


def _zc_loop_of(fixed_n):
    """zc_from's loop compiled for one dimension n (every loop over n in it and in the helpers
    it inlines then has a constant bound, which LLVM unrolls) or, when fixed_n is None, for any
    (n then passed last). Without LLVM's fast-math flags: IDLE_STEPS's test `t + 1 / sigma == t`
    is exact rounding on purpose."""
    @borrowing(fastmath=False)
    def zc_loop_n(ints, floats, r, ws, eps, max_iter, mode, Pz, Wz, lz, inverse, directions,
                  work, piv, n=fixed_n):
        """`zc_loop` (its docstring), with n = r's dimension fixed or passed."""
        rows, witnesses, lam, matrices, sc, state = loop_arrays(work, n, ws)
        P = rows[:n + 2]
        nvec, v, point, ones, y, gam, alpha, b = (rows[n + 2], rows[n + 3], rows[n + 4],
                                                  rows[n + 5], rows[n + 6], rows[n + 7],
                                                  rows[n + 8], rows[n + 9])
        Wt = witnesses[:n + 2]
        wit = witnesses[n + 2]
        M, lu, B, D = matrices[0], matrices[1], matrices[2], matrices[3]
        use_ie = mode == WITH_IE or mode == WITH_NEWTON
        t = state[ST_T]
        kz = int(state[ST_KZ])
        it = int(state[ST_IT])
        calls = int(state[ST_CALLS])
        if state[ST_K] < 0.0:
            # the first call: from the caller's simplex
            singular = 0
            _keep(Pz, Wz, lz, kz, P, Wt, lam)     # element loops, not slices (`_keep`)
            if use_ie and kz == n:
                k = kz        # a warm-start facet (graspforce._warm): IE steps from it at once
            else:
                k = _restart(P, Wt, lam, kz, r, sc) if kz > 0 else 0
            ones[:] = 1.0
            age = -1
            # the secant query needs every facet point's support direction (D's rows): known
            # from the caller's facet, kept by IE steps, lost to any other step
            secant = mode == WITH_IE and kz == n and directions.shape[0] >= n
            if secant:
                for j in range(n):
                    for i in range(n):
                        D[j, i] = directions[j, i]
            rest = 0          # plain IE steps before the next secant query
            pace = np.inf     # the last query's relative gap h_A(n) / (t n^T r) - 1
            last = -1         # the facet row the last secant point went to (-1: none to judge)
            if use_ie and kz == n and inverse.shape[0] == n:
                # the table's inverse of its facet: IE's first step factors nothing
                for i in range(n):
                    for j in range(n):
                        B[i, j] = inverse[i, j]
                _matvec_t_ones(B, n, y)
                _matvec(B, n, r, gam)
                age = 0
            # the row of P that the last IE step replaced since Pz last held the facet (-1:
            # unknown)
            changed = -1
            fresh_only = False
            newton_gap = NEWTON_GAP if mode == WITH_NEWTON else -1.0
            idle = 0          # ZC steps in a row that left b_k where it was
        else:
            # resumed after the driver's Newton try (it and calls include the try's)
            k = int(state[ST_K])
            singular = int(state[ST_SINGULAR])
            age = int(state[ST_AGE])
            changed = int(state[ST_CHANGED])
            fresh_only = state[ST_FRESH] != 0.0
            newton_gap = state[ST_NEWTON_GAP]
            idle = int(state[ST_IDLE])
            secant = state[ST_SECANT] != 0.0
            rest = int(state[ST_REST])
            pace = state[ST_PACE]
            last = int(state[ST_LAST])
        # a Newton try the driver owes: the gap of the IE step that asked for it (0: none). Its
        # simplex is the step's facet, kept in Pz[:n], and the step's support point, P[n]
        pending = 0.0
        code = LIMIT
        t_up = np.inf
        h_n = 0.0
        while it < max_iter:
            if pending > 0.0:
                code = NEWTON_TRY
                break
            if use_ie and k == n:
                # IE step on the facet CH(V), columns a_l: hyperplane y^T x = 1, r = sum gam_l a_l.
                # y and gam come from B, the facet's inverse, refactored every REFACTOR steps and
                # updated in between by the revised simplex method's pivot rule (O(n^2) a step).
                if fresh_only:
                    # LU solves only, no inverse: y, gam here, alpha below
                    ok = _solve_facet(P, n, r, M, lu, piv, ones, y, gam)
                elif age < 0 or age >= REFACTOR:
                    ok = _invert(P, n, M, piv, B)
                    age = 0
                    if ok:
                        _matvec_t_ones(B, n, y)
                        _matvec(B, n, r, gam)
                else:
                    ok = True         # y and gam came with the last pivot
                if ok:
                    yr = dot(y, r)
                    ok = yr > 0.0 and smallest(gam, n) >= -1e-12 * yr
                if not ok and age > 0:
                    age = -1          # perhaps only drift in the updated inverse: refactor first
                    continue
                if not ok:
                    # rounding broke the facet: return to the last simplex known to hold b_k
                    _keep(Pz, Wz, lz, kz, P, Wt, lam)
                    k = _restart(P, Wt, lam, kz, r, sc)
                elif smallest(gam, n) <= 1e-12 * yr:
                    # the ray crosses a lower-dimensional face of the facet: keep that face and
                    # continue with ZC-based iterations (section 3.4.2)
                    t = 1.0 / yr
                    for j in range(n):
                        lam[j] = max(gam[j], 0.0) * t
                    kz = _keep(P, Wt, lam, n, Pz, Wz, lz)
                    j = n - 1
                    while j >= 0:
                        if lam[j] <= 1e-12:
                            k = drop_point(P, Wt, lam, k, j)
                        j -= 1
                    k = _restart(P, Wt, lam, k, r, sc)
                    singular += 1
                else:
                    t = 1.0 / yr
                    ny = np.sqrt(dot(y, y))
                    # one division, not n: the direction needs to be y's only to rounding
                    iny = 1.0 / ny
                    query_secant = False
                    if secant:
                        # the last secant point, judged by its weight in this facet's t r
                        if last >= 0 and gam[last] * t < SECANT_HOLD:
                            rest = SECANT_REST
                        last = -1
                        if rest > 0:
                            rest -= 1
                        else:
                            query_secant = True
                    h = 0.0
                    closed = False
                    if query_secant:
                        # the secant query (docs/core-api.md): the support map's linear model
                        # through the facet, s(d_j) = P_j, puts s(sum_j gam_j d_j) at t r
                        for i in range(n):
                            v[i] = 0.0
                        for j in range(n):
                            for i in range(n):
                                v[i] += gam[j] * D[j, i]
                        nv = np.sqrt(dot(v, v))
                        if nv > 0.0:
                            for i in range(n):
                                nvec[i] = v[i] / nv
                            h = support(ints, floats, nvec, point, wit)
                            calls += 1
                            nr = dot(nvec, r)
                            closed = nr > 0.0 and h - t * nr <= eps * (t * nr)
                            secant_gap = h / (t * nr) - 1.0 if nr > 0.0 else np.inf
                            if secant_gap > SECANT_GAIN * pace:
                                rest = SECANT_REST
                            pace = secant_gap
                        if not closed and not (nv > 0.0 and dot(y, point) - 1.0 > eps):
                            # neither a bound nor new ground (a flat piece: the model's point
                            # is a vertex): IE's query after all
                            rest = SECANT_REST
                            query_secant = False
                    if not query_secant:
                        # h_A is positively homogeneous (eq. 2): y itself is queried, so that
                        # the support call waits for no square root and division (IE's gap
                        # h_A(y/|y|) |y| - 1 is h_A(y) - 1); the unit normal is made alongside
                        h = support(ints, floats, y, point, wit)
                        calls += 1
                        closed = h - 1.0 <= eps
                        pace = h - 1.0
                        h *= iny
                        for i in range(n):
                            nvec[i] = y[i] * iny
                    it += 1
                    if closed and fresh_only:
                        for j in range(n):
                            lam[j] = gam[j] * t
                        kz = _keep(P, Wt, lam, n, Pz, Wz, lz)
                        code = HIT
                        t_up = h / dot(nvec, r) if query_secant else h * ny / yr
                        h_n = h
                        break
                    if closed:
                        # certify: the normal and h_A(n) already evaluated bound t from above
                        # whatever n is; from below, t r must be the convex combination gam /
                        # sum(gam) of the facet's points, checked by its residual (the updated
                        # inverse's drift shows there). Failing that, LU solves on a fresh
                        # factorization.
                        nr = dot(nvec, r)
                        for refine in range(2):
                            if refine == 1:
                                # one step of iterative refinement with the updated inverse:
                                # gam += B (r - sum_j gam_j P_j), ~3 n^2 flops where the LU
                                # below costs ~n^3 / 3 + 4 n^2 (taken on 66% of W_Linf's lift's
                                # shots on the ingot, 24% of W_L1's)
                                for i in range(n):
                                    e = r[i]
                                    for j in range(n):
                                        e -= gam[j] * P[j, i]
                                    alpha[i] = e
                                _matvec(B, n, alpha, v)
                                for j in range(n):
                                    gam[j] += v[j]
                            gsum = 0.0
                            for j in range(n):
                                gsum += gam[j]
                            if not (gsum > 0.0 and smallest(gam, n) >= 0.0):
                                break
                            tz = 1.0 / gsum
                            if h / nr - tz > eps * tz:
                                break
                            for j in range(n):
                                lam[j] = gam[j] * tz
                            if _holds(P, lam, n, tz, r, b, FACET_HOLDS):
                                kz = _keep(P, Wt, lam, n, Pz, Wz, lz)
                                code = HIT
                                t = tz
                                t_up = h / nr
                                h_n = h
                                break
                        if code == HIT:
                            break
                        ok = _solve_facet(P, n, r, M, lu, piv, ones, y, gam)
                        yr = dot(y, r)
                        if (ok and yr > 0.0 and smallest(gam, n) >= 0.0
                                and h / nr - 1.0 / yr <= eps / yr):
                            t = 1.0 / yr
                            for j in range(n):
                                lam[j] = gam[j] * t
                            kz = _keep(P, Wt, lam, n, Pz, Wz, lz)
                            code = HIT
                            t_up = h / nr
                            h_n = h
                            break
                        # the updated inverse's drift matters at this eps: from here on, LU
                        # solves at every step (the floor of docs/core-api.md, "Numerical floor")
                        fresh_only = True
                        continue
                    for j in range(n):
                        lam[j] = gam[j] * t
                    gap = h * ny - 1.0
                    kz = _keep(P, Wt, lam, n, Pz, Wz, lz, changed)
                    if gap <= newton_gap:
                        # IE's cutting planes have found the exit face's pieces: Newton on them
                        # (graspforce._newton), with the new support point as a candidate
                        # piece. The driver tries it when this step is done: its simplex,
                        # Pz[:n] and P[n], stays as it is until then
                        set_row(P, Wt, n, point, wit)
                        pending = gap
                    # ratio test: the new facet the ray crosses replaces the vertex j*
                    if fresh_only:
                        lu_solve(lu, piv, n, point, alpha)
                    else:
                        _matvec(B, n, point, alpha)
                    # the least gam_j / alpha_j over alpha_j > 0, compared as products: no
                    # division
                    js = -1
                    amax = 0.0
                    for j in range(n):
                        amax = max(amax, abs(alpha[j]))
                        if alpha[j] > 0.0 and (js < 0 or gam[j] * alpha[js] < gam[js] * alpha[j]):
                            js = j
                    js = max(js, 0)
                    if _same_point(P, js, point):
                        # s is the vertex it would replace: the step cannot move, and the gap was
                        # the updated inverse's drift (a vertex lies on its facet). Fresh factors,
                        # then LU solves; s a vertex even then is rounding at this eps: the
                        # bracket stands (before, the step repeated itself until max_iter: a
                        # full-magnitude lift at eps = 3e-12, BENCHMARKS.md "Stop 22")
                        if fresh_only:
                            code = LIMIT
                            t_up = h * ny / yr
                            h_n = h
                            break
                        if age > 0:
                            age = -1
                        else:
                            fresh_only = True
                        continue
                    set_row(P, Wt, js, point, wit)
                    changed = js
                    if secant:
                        for i in range(n):
                            D[js, i] = nvec[i]
                        if query_secant:
                            last = js
                    if not fresh_only and alpha[js] > 1e-8 * amax:
                        _pivot(B, n, alpha, js, y, gam)
                        age += 1
                    else:
                        age = -1
                    continue
            age = -1
            changed = -1
            secant = False
            st, k, d, h, zi, zcalls = _zc_step(ints, floats, r, t, P, Wt, lam, k, eps, max_iter,
                                               nvec, v, point, wit, b, sc)
            calls += zcalls
            if st == STALLED and t > 0.0:
                # rounding in the warm-started generators: start ZC afresh from b_k once
                st, k, d, h, zi, zcalls = _zc_step(ints, floats, r, t, P, Wt, lam, 0, eps,
                                                   max_iter, nvec, v, point, wit, b, sc)
                calls += zcalls
            it += 1
            if st == INSIDE:
                sigma = lam[:k].sum()
                idle = idle + 1 if t + 1.0 / sigma == t else 0
                if idle == IDLE_STEPS:
                    break
                t += 1.0 / sigma
                for j in range(k):
                    lam[j] /= sigma
                kz = _keep(P, Wt, lam, k, Pz, Wz, lz)
                if mode == UNTIL_FACET and k == n:
                    code = FACET
                    singular = 0
                    break
                if not (use_ie and k == n):
                    k = _restart(P, Wt, lam, k, r, sc)
                continue
            if st == MAX_ITER:
                break
            if t == 0.0:
                # CONVERGED here means h_A(n) <= 0 < n^T r: a certified miss. STALLED means r lies
                # on the boundary of CO(A) to rounding: the ray at most grazes A, reported a miss.
                code = MISS
                t_up = 0.0
                h_n = h
                kz = 0
                singular = 0
                break
            # converged (or stalled): z = b_k, supported by H(n, s_A(n)). A stall certifies
            # nothing by itself: ZC's cone from b_k also loses rank far from z_A(r), on rays near
            # the boundary of a set whose origin is on its boundary (two contacts' wrench set, which
            # is never force-closure: gaps up to 2% were reported as hits). Nor does b_k always lie
            # in A: on a ray along the boundary of CO(A), ZC's INSIDE rule for a cone that lost
            # orthogonality accepts weights that reproduce b_k only to ~1e-8 (two point contacts,
            # wrenches on the edge of what they resist: answers 5e-8 below the true minimum were
            # reported optimal). Newton on the simplex's pieces then finishes the shot exactly
            # where it can (the two-point-contact case); else the bracket stands, with the status
            # of an unfinished shot. Newton's plain steps first: its corner steps (complete
            # pivoting, the shortest normal) lose some two-point-contact cases the plain ones finish.
            h_n = h + t * dot(nvec, r)
            t_up = h_n / dot(nvec, r)
            if ((st == CONVERGED or t_up - t <= max(eps, STALL_FLOOR) * t)
                    and _holds(Pz, lz, kz, t, r, b, POINT_HOLDS)):
                code = HIT
            else:
                code = NEWTON_END
            break
        state[ST_T] = t
        state[ST_K] = k
        state[ST_KZ] = kz
        state[ST_IT] = it
        state[ST_CALLS] = calls
        state[ST_SINGULAR] = singular
        state[ST_AGE] = age
        state[ST_CHANGED] = changed
        state[ST_FRESH] = 1.0 if fresh_only else 0.0
        state[ST_NEWTON_GAP] = newton_gap
        state[ST_IDLE] = idle
        state[ST_SECANT] = 1.0 if secant else 0.0
        state[ST_REST] = rest
        state[ST_PACE] = pace
        state[ST_LAST] = last
        state[ST_PENDING] = pending
        state[ST_T_UP] = t_up
        state[ST_H] = h_n
        return code
    return zc_loop_n


# zc_from's loop in the dimensions the goals' calls shoot in, compiled for each: 3-D bodies
# (growth distance), wrenches (W_L1) and W_Linf's lift for four contacts (R^9). Each costs the
# loop's compile time again; other dimensions take the general version. ab.py: BENCHMARKS.md,
# "Stop 24"
_zc_loop_any = _zc_loop_of(None)
_zc_loop_3 = _zc_loop_of(3)
_zc_loop_6 = _zc_loop_of(6)
_zc_loop_9 = _zc_loop_of(9)


@borrowing(fastmath=False)
def zc_loop(ints, floats, r, ws, eps, max_iter, mode, Pz, Wz, lz, inverse, directions, work,
            piv):
    """ZC-based iterations (section 3.3) and, with mode WITH_IE or WITH_NEWTON, IE steps
    whenever V_k is a facet (section 3.4.2), in `zc_work(n, ws)`'s arrays. The state
    (`start_state` before the first call) says where to start; the loop returns why it
    stopped: HIT, MISS, LIMIT or FACET with the result in its state, the normal (rows[n + 2])
    and Pz[:kz], Wz[:kz], lz[:kz]; or NEWTON_TRY, NEWTON_END, which `zc_drive` settles. Runs
    the version compiled for r's dimension (`_zc_loop_of`)."""
    n = r.shape[0]
    if n == 6:
        return _zc_loop_6(ints, floats, r, ws, eps, max_iter, mode, Pz, Wz, lz, inverse,
                          directions, work, piv)
    if n == 3:
        return _zc_loop_3(ints, floats, r, ws, eps, max_iter, mode, Pz, Wz, lz, inverse,
                          directions, work, piv)
    if n == 9:
        return _zc_loop_9(ints, floats, r, ws, eps, max_iter, mode, Pz, Wz, lz, inverse,
                          directions, work, piv)
    return _zc_loop_any(ints, floats, r, ws, eps, max_iter, mode, Pz, Wz, lz, inverse,
                        directions, work, piv, n)


@borrowing(forceinline=True)
def start_state(work, n, ws, t, kz, it, calls):
    """The state (in `zc_work`'s work array) of a loop that starts from b = t r, the convex
    combination lz of Pz[:kz], with it iterations and calls support calls spent."""
    e = zc_work_size(n, ws) - STATE
    work[e + ST_T] = t
    work[e + ST_K] = -1.0
    work[e + ST_KZ] = kz
    work[e + ST_IT] = it
    work[e + ST_CALLS] = calls


@njit(cache=True)
def zc_drive(ints, floats, r, ws, eps, max_iter, mode, Pz, Wz, lz, inverse, directions, work,
             piv, code):
    """The result tuple of zc_from's loop, which stopped with `code` (`zc_loop`): the Newton
    finish it asks for (resuming it after a try that fails), then the record."""
    n = r.shape[0]
    rows, state = loop_rows_state(work, n, ws)
    nvec = rows[n + 2]
    while True:
        pending = state[ST_PENDING]
        if pending > 0.0:
            # the IE step's facet (Pz[:n]) and its support point (P[n]) as Newton's pieces
            witnesses = loop_arrays(work, n, ws)[1]
            for i in range(n):
                Pz[n, i] = rows[n, i]
            for i in range(ws):
                Wz[n, i] = witnesses[n, i]
            lz[n] = 0.0
            fin = newton_finish(ints, floats, r, eps, Pz, Wz, lz, n + 1, nvec, state[ST_T],
                                False)
            it = int(state[ST_IT]) + fin[5]
            calls = int(state[ST_CALLS]) + fin[6]
            if fin[0]:
                return _result(HIT, fin[1], fin[2], fin[3], it, calls, fin[7], fin[8], fin[9],
                               fin[10], fin[4], int(state[ST_SINGULAR]))
            state[ST_IT] = it
            state[ST_CALLS] = calls
            state[ST_NEWTON_GAP] = pending * NEWTON_RETRY
            state[ST_PENDING] = 0.0
        if code == NEWTON_TRY:
            code = zc_loop(ints, floats, r, ws, eps, max_iter, mode, Pz, Wz, lz, inverse,
                           directions, work, piv)
            continue
        break
    if code != NEWTON_END:
        return loop_result(code, work, n, ws, Pz, Wz, lz)
    t = state[ST_T]
    kz = int(state[ST_KZ])
    it = int(state[ST_IT])
    calls = int(state[ST_CALLS])
    singular = int(state[ST_SINGULAR])
    t_up = state[ST_T_UP]
    for corner in (False, True):
        fin = newton_finish(ints, floats, r, eps, Pz, Wz, lz, kz, nvec, t, corner)
        it += fin[5]
        calls += fin[6]
        if fin[0]:
            return _result(HIT, fin[1], fin[2], fin[3], it, calls, fin[7], fin[8], fin[9],
                           fin[10], fin[4], singular)
    # t r need not be in A here: an estimate, never above the certified bound
    return _result(LIMIT, min(t, t_up), t_up, state[ST_H], it, calls, nvec, Pz, lz, Wz, kz,
                   singular)


@njit(cache=True)
def zc_from(ints, floats, r, ws, eps, max_iter, mode, t, Pz, Wz, lz, kz, it, calls, inverse,
            directions):
    """ZC-based iterations from b = t r in A, the convex combination lz of Pz[:kz] (t = 0,
    kz = 0: from the origin, which first decides whether the ray meets A; kz = n with WITH_IE: a
    facet the ray crosses, where IE steps start). mode: ZC_ONLY
    (section 3.3), WITH_IE (ZC-IE, section 3.4.2: plain IE steps while V_k is a facet),
    WITH_NEWTON (ZC-IE with the Newton finish) or UNTIL_FACET (return FACET with V_k as soon as
    it is a facet: IE's initialization). inverse: [Pz_0 .. Pz_{n-1}]^{-1} when it is known (a
    start table's facet, graspforce._start_table), else a 0 x 0 array. directions: with WITH_IE
    and kz = n, the unit directions whose support points Pz[:kz] are (graspforce._warm's probes),
    which turn on the secant query (docs/core-api.md), else a 0 x 0 array. Pz, Wz, lz have
    n + 2 rows. `zc_loop` in arrays of its own (`zc_work`), then `zc_drive`."""
    n = r.shape[0]
    # callers pass the mode as a constant, which Numba types as a literal and would compile the
    # loop's versions for again (nine signatures: the test suite's compile time 383 -> 963 s); a
    # sum is a plain int64
    mode_ = mode + 0
    work, piv = zc_work(n, ws)
    start_state(work, n, ws, t, kz, it, calls)
    code = zc_loop(ints, floats, r, ws, eps, max_iter, mode_, Pz, Wz, lz, inverse, directions,
                   work, piv)
    if code <= FACET and loop_rows_state(work, n, ws)[1][ST_PENDING] == 0.0:
        # the common stop, recorded here: the driver's call and views cost reference counts
        # (min_force L1 and Linf 1.03 and 1.02 x in ab.py with every stop through it)
        return loop_result(code, work, n, ws, Pz, Wz, lz)
    return zc_drive(ints, floats, r, ws, eps, max_iter, mode_, Pz, Wz, lz, inverse, directions,
                    work, piv, code)


@borrowing
def _simplex_exit(P, Wt, lam, k, r, t, M, lu, piv, rhs, mu):
    """GJK proved t r inside A with n + 1 points P[:k] (weights lam): the ray stays in their
    simplex up to t + s, where the barycentric weights lam + s mu of (t + s) r (mu: those of r,
    summing to 0) first reach zero. Moves lam there, drops the point whose weight reached zero
    and returns (t + s, k - 1); (t, k) when the simplex is degenerate."""
    n = P.shape[1]
    for j in range(k):
        for i in range(n):
            M[i, j] = P[j, i]
        M[n, j] = 1.0
    for i in range(n):
        rhs[i] = r[i]
    rhs[n] = 0.0
    if not lu_factor(M, k, lu, piv):
        return t, k
    lu_solve(lu, piv, k, rhs, mu)
    s = np.inf
    js = -1
    for j in range(k):
        if mu[j] < 0.0 and lam[j] / -mu[j] < s:
            s = lam[j] / -mu[j]
            js = j
    if js < 0:
        return t, k
    for j in range(k):
        lam[j] = max(lam[j] + s * mu[j], 0.0)
    lam[js] = 0.0
    return t + s, drop_point(P, Wt, lam, k, js)


@njit(cache=True)
def _finish_inside(ints, floats, r, ws, eps, max_iter, t, P, Wt, lam, k, it, calls):
    """GJK-based's and Bi-GJK's finish at GJK's numerical floor (docs/core-api.md), from
    t r = sum lam_l P_l in A: IE steps from the facet P[:k] when k = n (its facets are solved
    from the origin and stay well-conditioned), ZC-based steps from a lower face. (Ingot W_L1:
    ZC-based steps from the facet, the former finish, stalled above eps on 70 of GJK-based's 300
    rays, which the dispatcher's IE then redid from scratch; Bi-GJK's mean support calls
    181 -> 131.)"""
    mode = WITH_IE if k == r.shape[0] else ZC_ONLY
    none = np.empty((0, 0))
    return zc_from(ints, floats, r, ws, eps, max_iter, mode, t, P, Wt, lam, k, it, calls, none,
                   none)


@njit(cache=True)
def bi_gjk(ints, floats, r, ws, eps, max_iter):
    """Section 3.4.1: bisection between a point of A on the ray (from ZC) and a point outside
    (from supporting hyperplanes), each midpoint tested by GJK. When GJK proves a midpoint
    inside with a full simplex of n + 1 points, the inner point moves on to where the ray leaves
    that simplex, not just to the midpoint (`_simplex_exit`): ingot W_L1, median iterations
    32 -> 6, support calls 74 -> 72."""
    n = r.shape[0]
    P = np.empty((n + 2, n))
    Wt = np.empty((n + 2, ws))
    lam = np.empty(n + 2)
    nvec, v, point, wit, _, sc = _work(n, ws)
    st, k, d, h, zi, calls = zc(ints, floats, np.zeros(n), r, P, Wt, lam, 0, 0.0, 0.0,
                                max_iter, nvec, v, point, wit, sc)
    if st != INSIDE:
        # as in zc_from at t = 0: a certified miss, or r on the boundary of CO(A) to rounding
        return _result(MISS if st != MAX_ITER else LIMIT, 0.0, 0.0, h, 1, calls, nvec, P,
                       lam, Wt, 0, 0)
    sigma = lam[:k].sum()
    for j in range(k):
        lam[j] /= sigma
    return bi_gjk_from(ints, floats, r, ws, eps, max_iter, 1.0 / sigma, P, Wt, lam, k, r,
                       calls)


@njit(cache=True)
def bi_gjk_from(ints, floats, r, ws, eps, max_iter, t_lo, P, Wt, lam, k, u, calls):
    """Bi-GJK's bisection from t_lo r = sum lam_l P_l (l < k), a point of A, and the upper
    bound of the supporting hyperplane H(u, s_A(u)) (u = r from ZC's start; a start table's
    facet normal, much nearer the answer's, from `graspforce._start_table`)."""
    n = r.shape[0]
    rr = dot(r, r)
    Pz = np.empty((n + 2, n))
    Wz = np.empty((n + 2, ws))
    lz = np.empty(n + 2)
    nvec, v, point, wit, x, sc = _work(n, ws)
    exit_work = np.empty((2, n + 1, n + 1))
    M, lu = exit_work[0], exit_work[1]
    piv = np.empty(n + 1, np.int64)
    rhs = np.empty(n + 1)
    kz = _keep(P, Wt, lam, k, Pz, Wz, lz)
    best_n = u / np.sqrt(dot(u, u))
    best_h = support(ints, floats, best_n, point, wit)
    calls += 1
    un = dot(best_n, r)
    if not (un > 0.0 and best_h >= t_lo * un):
        # a table's facet normal that rounding left behind t_lo: r's own bound instead
        best_n = r / np.sqrt(rr)
        best_h = support(ints, floats, best_n, point, wit)
        calls += 1
        un = np.sqrt(rr)
    t_hi = best_h / un
    t_up = t_hi
    for it in range(max_iter):
        if t_up - t_lo <= eps * t_lo:
            if _holds(Pz, lz, kz, t_lo, r, point, POINT_HOLDS):
                # a table's t_lo = 1 / sum(gam) can exceed t_up by an ulp or two where the ray
                # leaves A exactly at a vertex of the table's facet
                return _result(HIT, min(t_lo, t_up), t_up, best_h, it + 1, calls, best_n, Pz,
                               lz, Wz, kz, 0)
            # ZC's first point reproduced only to ~1e-8 (a ray along the boundary of CO(A):
            # zc_from's end), which zc_from's finish settles
            return _finish_inside(ints, floats, r, ws, eps, max_iter, t_lo, Pz, Wz, lz, kz,
                                  it + 1, calls)
        if t_hi - t_lo <= 1e-3 * eps * t_lo:
            # the bracket closed on points GJK could not certify: its numerical floor
            return _finish_inside(ints, floats, r, ws, eps, max_iter, t_lo, Pz, Wz, lz, kz,
                                  it + 1, calls)
        tm = 0.5 * (t_lo + t_hi)
        b = tm * r
        st, k, d, h, gi, gc = gjk(ints, floats, b, P, Wt, lam, k, eps, 0.0, True,
                                  max_iter, nvec, v, point, wit, sc)
        calls += gc
        if st == MAX_ITER:
            break
        if st == INSIDE:
            t_lo = tm
            if k == n + 1:
                t_lo, k = _simplex_exit(P, Wt, lam, k, r, tm, M, lu, piv, rhs, x)
            kz = _keep(P, Wt, lam, k, Pz, Wz, lz)
            continue
        rn = dot(r, nvec)
        if rn > 0.0 and h / rn < t_up:
            t_up = h / rn
            best_n[:] = nvec
            best_h = h
        # GJK puts tm r outside A; when its gap is too wide to certify that, the bisection
        # still moves (t_up stays the certified bound)
        t_hi = min(tm, t_up)
        if rn <= 0.0:
            continue
        t_b = tm - d / rn
        t_ray = -1.0
        if st == CONVERGED and t_b > t_lo:
            t_ray = _on_ray(P, k, r, t_b, eps, x, 1e-12, sc)
        if t_ray > t_lo:
            t_lo = t_ray
            kz = _keep(P, Wt, x, k, Pz, Wz, lz)
    return _result(LIMIT, t_lo, t_up, best_h, max_iter, calls, best_n, Pz, lz, Wz, kz, 0)

