"""A second-order finish for ray shooting: Newton's method on the pieces that form the exit face.

Ray shooting is the convex program t* = min { h_A(u) : u^T r = 1 } (z_A(r) = t* r; the facet
normals of IE are its cutting planes, which is why IE converges only linearly on curved sets).
Near the answer, h_A is the maximum of the supports h_p of a few smooth pieces (graspforce._piece)
and the minimum is the root of the KKT system, in u, the piece weights lam_p, t and tau:

    sum_p lam_p s_p(u) + sum_l T_l y_l = t r,   h_p(u) = tau (each p),   T_l^T u = 0 (each l),
    sum_p lam_p = 1,   u^T r = 1

(the first line is z_A(r) = t r as the convex combination of eq. 2's support points that
Z_A(r) holds; the second puts every piece's point on one hyperplane with normal u). A flat leaf l
of piece p (graspforce._piece: a body whose whole face the hyperplane holds, such as a soft
finger whose friction is not saturated) adds the point T_l x_l, x_l free, through y_l = lam_p x_l,
and the condition T_l^T u = 0 that makes its face the hyperplane's. The Jacobian of the system
needs the pieces' curvature J_p = ds_p/du; Newton converges quadratically from the facet that IE's
cutting planes have brought close. The pieces are read off the witnesses of the facet's vertices
(a leaf is flat where ||T^T u|| is tiny); a piece whose weight turns negative leaves the system,
one that the final check finds sticking out joins it, a smooth leaf that meets its kink turns
flat, and a flat leaf whose point leaves the body turns smooth.

Nothing of Newton's is trusted: the answer certifies itself as every other one does. The points
s_p(u) are points of A, so their convex combination z (weights re-solved by least squares on the
final points) is in A and lies on the ray to rounding (the rule of Fig. 3b's `_on_ray`); one call
of the full support map at u gives the hyperplane H(u, s_A(u)) that bounds z_A(r) from outside.
When the bracket is wider than eps, or the system is singular (a polytope face with fewer than
n vertices, a flat face whose normal sits on a piece's kink), the finish fails and IE goes on.
"""
import numpy as np
from numba import njit

from ._jit import borrowing
from ._kernel import ELLIPSOID, HULL, blocks, support
from ._corral import drop_point, reproduce, weights_on_ray
from ._linalg import (basic_null_space, dot, lstsq, lu_factor, lu_solve, smallest,
                      solve_basic)
from ._piece import (FLAT, KINK, TRUNCATED_CONE, flat_columns, flat_radius2, jacobian_size,
                     local_size, piece_support, same_piece)

NEWTON_STEPS = 12      # Newton steps of one attempt, over all changes of the piece set
STEP_TOL = 1e-7        # ||du|| <= STEP_TOL ||u||: one more step leaves an error far below eps
FLAT_RHO = 1e-3        # ||T^T u|| <= FLAT_RHO ||T|| ||u|| on the facet's normal: the leaf is flat
FLAT_SPREAD = 0.5      # or its facet vertices' mean local point is this far inside (squared)
# a corner finish's rank tolerance, relative to the KKT matrix's largest entry: rounding in u
# and the curvatures of the pieces, amplified where the normal is far from unique
CORNER_RANK = 1e-9
MAX_CHANGES = 6        # changes of the piece set in one attempt


@borrowing
def _flats(ints, f, PW, lam, m, T, y, fpiece, fleaf, foff, fq, C, C2):
    """The flat leaves of the pieces: their piece, node, offset in y and size; T's columns and
    y = lam_p x. Returns (count, entries of y); count -1 when T has no room for them."""
    nn = ints[0]
    KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN = \
        blocks(nn)
    nf = 0
    ny = 0
    for p in range(m):
        for i in range(nn):
            if ints[KIND + i] >= HULL:
                continue
            w = ints[WSTART + i]
            if PW[p, w] != FLAT:
                continue
            q = flat_columns(ints, f, i, T, ny, C, C2)
            if q < 0:
                return -1, ny
            for b in range(q):
                y[ny + b] = lam[p] * PW[p, w + 1 + b]
            fpiece[nf] = p
            fleaf[nf] = i
            foff[nf] = ny
            fq[nf] = q
            nf += 1
            ny += q
    return nf, ny


@borrowing
def _mark_flat(ints, f, PW, p, leaf, x):
    """Turn a leaf of piece p flat with local point x (a disk keeps its side)."""
    nn = ints[0]
    KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN = \
        blocks(nn)
    w = ints[WSTART + leaf]
    PW[p, w] = FLAT
    for b in range(local_size(ints[KIND + leaf], f, ints[PSTART + leaf])):
        PW[p, w + 1 + b] = x[b]


@borrowing
def _shortest_u(u, n, N, rank, lu, pcol, dx, mats, vecs):
    """Move the basic solution dx of a rank-deficient system (`solve_basic`'s factors in lu,
    pcol) within the system's null space so that u + du is shortest. mats (3, N, N) and
    vecs (3, N) are scratch."""
    Z, D, work = mats[0], mats[1], mats[2]
    x, rhs, wrhs = vecs[0], vecs[1], vecs[2]
    q = N - rank
    basic_null_space(lu, pcol, N, rank, Z, x)
    for i in range(n):
        for e in range(q):
            D[i, e] = Z[i, e]
        rhs[i] = -(u[i] + dx[i])
    # False when some null direction leaves u alone (free weights): the basic solution stands
    if lstsq(D, n, q, rhs, x, 0, work, wrhs):
        for i in range(N):
            for e in range(q):
                dx[i] += Z[i, e] * x[e]


@borrowing
def _solve_kkt(r, u, t, tau, lam, S, JJ, m, T, y, nf, ny, fpiece, foff, fq, sm, K, lu, prow, pcol,
               rhs, dx, corner, mats, vecs):
    """One Newton step of the KKT system (module docstring) into dx = (du, dlam, dy, dt, dtau),
    by LU with partial pivoting, or a basic solution (complete pivoting) where the weights are
    not unique (two flat leaves that share a direction: two fingers on one face whose friction
    split is free). sm: (m, n) work for the pieces' smooth parts. corner: every step by
    complete pivoting, the shortest u (newton_finish); mats, vecs: `_shortest_u`'s scratch."""
    n = r.shape[0]
    N = n + m + ny + 2
    it = n + m + ny
    for i in range(N):
        rhs[i] = 0.0
        for j in range(N):
            K[i, j] = 0.0
    # the smooth part s_p of each piece's point: S_p less its flat leaves' T x
    for p in range(m):
        for i in range(n):
            sm[p, i] = S[p, i]
    for e in range(nf):
        p = fpiece[e]
        if lam[p] != 0.0:
            for b in range(fq[e]):
                xb = y[foff[e] + b] / lam[p]
                for i in range(n):
                    sm[p, i] -= T[i, foff[e] + b] * xb
    for i in range(n):
        F = -t * r[i]
        for p in range(m):
            F += lam[p] * S[p, i]
            for b in range(n):
                K[i, b] += lam[p] * JJ[p, i, b]
            K[i, n + p] = sm[p, i]
        for c in range(ny):
            K[i, n + m + c] = T[i, c]
        K[i, it] = -r[i]
        rhs[i] = -F
    for p in range(m):
        for b in range(n):
            K[n + p, b] = sm[p, b]
        K[n + p, it + 1] = -1.0
        rhs[n + p] = tau - dot(u, sm[p])
    row = n + m
    for c in range(ny):
        s = 0.0
        for b in range(n):
            K[row, b] = T[b, c]
            s += T[b, c] * u[b]
        rhs[row] = -s
        row += 1
    total = 0.0
    for p in range(m):
        K[row, n + p] = 1.0
        total += lam[p]
    rhs[row] = 1.0 - total
    for b in range(n):
        K[row + 1, b] = r[b]
    rhs[row + 1] = 1.0 - dot(u, r)
    if corner:
        rank = solve_basic(K, N, lu, prow, pcol, rhs, dx, CORNER_RANK)
        if rank < N:
            _shortest_u(u, n, N, rank, lu, pcol, dx, mats, vecs)
        return rank > 0
    if lu_factor(K, N, lu, prow):
        lu_solve(lu, prow, N, rhs, dx)
        return True
    return solve_basic(K, N, lu, prow, pcol, rhs, dx) > n


@njit(cache=True)
def _failed(t, t_up, h, steps, calls, nrm, S, lm, WS):
    """newton_finish's answer when it gives up: the steps and support calls it spent."""
    return (False, t, t_up, h, 0, steps, calls, nrm, S, lm, WS)


@njit(cache=True)
def newton_finish(ints, f, r, eps, P, Wt, lam, k, normal, t, corner):
    """Try to finish a shot from the simplex P[:k] (witnesses Wt, weights lam: t r is their
    convex combination or near it) and the normal of its facet. Returns (ok, t, t_upper, h_n,
    m, newton_steps, support_calls, normal, V, weights, W): on ok, z = t r is the convex
    combination `weights` of V[:m] (points of A, witnesses W), within rounding of the ray, and
    H(normal, h_n) supports A with (t_upper - t) <= eps t.

    corner: the ray runs along the boundary of CO(A) (ZC stalled, or its cone reproduced b_k
    only to ~1e-8: graspforce._shooters.zc_from), so z_A(r) is a corner whose normals form a
    cone of more than one ray, the KKT system is singular, and the given normal (ZC's, nearly
    orthogonal to r) is a poor certificate. Every step is then a basic solution by complete
    pivoting, moved within the null space so that u (u^T r = 1) stays shortest: the normal
    that bounds t best. (Two contacts, wrenches on the edge of what they resist: the plain
    steps finish some two-point-contact cases of tests/test_grasp_forces.py, the corner steps
    the others, and three-term corners where the plain steps fail.)"""
    n = r.shape[0]
    ws = Wt.shape[1]
    nn = ints[0]
    KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN = \
        blocks(nn)
    cap = k + 3
    PW = np.empty((cap, ws))
    S = np.empty((cap, n))
    WS = np.empty((cap, ws))
    JJ = np.empty((cap, n, n))
    sm = np.empty((cap, n))
    lm = np.empty(cap)
    group = np.empty(k, np.int64)
    size, nmax, qmax = jacobian_size(ints, f)
    ycap = 2 * n + 2
    T = np.empty((n, ycap))
    y = np.empty(ycap)
    fpiece = np.empty(ycap, np.int64)
    fleaf = np.empty(ycap, np.int64)
    foff = np.empty(ycap, np.int64)
    fq = np.empty(ycap, np.int64)
    C = np.empty((nmax, qmax))
    C2 = np.empty((nmax, qmax))
    N = n + cap + ycap + 2
    K = np.empty((N, N))
    lu = np.empty((N, N))
    prow = np.empty(N, np.int64)
    pcol = np.empty(N, np.int64)
    rhs = np.empty(N)
    dx = np.empty(N)
    jw = np.empty(size)
    mats = np.empty((3, N, N) if corner else (3, 0, 0))
    vecs = np.empty((3, N) if corner else (3, 0))
    u = np.empty(n)
    point = np.empty(n)
    wit = np.empty(ws)
    nrm = np.empty(n)
    xbar = np.zeros(qmax)
    steps = 0
    calls = 0
    nr = dot(normal, r)
    if nr <= 0.0:
        return _failed(t, np.inf, 0.0, steps, calls, nrm, S, lm, WS)
    for i in range(n):
        u[i] = normal[i] / nr
    # the pieces of the simplex, each weighted by the sum of its vertices' weights
    m = 0
    for j in range(k):
        group[j] = m
        for p in range(m):
            if same_piece(ints, Wt[j], PW[p]):
                group[j] = p
                break
        if group[j] == m:
            PW[m] = Wt[j]
            lm[m] = lam[j]
            m += 1
        else:
            lm[group[j]] += lam[j]
    # flat leaves: the facet's normal nearly annihilates T, or the facet's vertices spread over
    # the body (a smooth piece's crowd together); x starts at their weighted mean
    un = np.sqrt(dot(u, u))
    for p in range(m):
        for i in range(nn):
            kind = ints[KIND + i]
            if kind != ELLIPSOID and kind != TRUNCATED_CONE:
                continue
            w = ints[WSTART + i]
            if PW[p, w] == 0.0:
                continue
            q = flat_columns(ints, f, i, T, 0, C, C2)
            if q < 0:
                continue
            tu = 0.0
            tt = 0.0
            for b in range(q):
                s = 0.0
                for a in range(n):
                    s += T[a, b] * u[a]
                    tt += T[a, b] * T[a, b]
                tu += s * s
            wsum = 0.0
            for b in range(q):
                xbar[b] = 0.0
            for j in range(k):
                if group[j] == p:
                    wsum += lam[j]
                    for b in range(q):
                        xbar[b] += lam[j] * Wt[j, w + 1 + b]
            for b in range(q):
                xbar[b] = xbar[b] / wsum if wsum > 0.0 else 0.0
            PW[p, w + 1:w + 1 + q] = xbar[:q]
            if tu <= (FLAT_RHO * un) ** 2 * tt or flat_radius2(ints, f, i, PW[p]) < FLAT_SPREAD:
                _mark_flat(ints, f, PW, p, i, xbar)
    nf, ny = _flats(ints, f, PW, lm, m, T, y, fpiece, fleaf, foff, fq, C, C2)
    tau = t
    changes = 0
    converged = False
    while steps < NEWTON_STEPS:
        if m < 1 or m > n or nf < 0 or n + m + ny + 2 > N or changes > MAX_CHANGES:
            return _failed(t, np.inf, 0.0, steps, calls, nrm, S, lm, WS)
        kinked = False
        for p in range(m):
            h = piece_support(ints, f, u, PW[p], S[p], WS[p], JJ[p], jw, nmax)
            if h != h:
                # a smooth leaf at its kink: its whole body is in the face, it turns flat
                for i in range(nn):
                    if ints[KIND + i] < HULL and WS[p, ints[WSTART + i]] == KINK:
                        for b in range(qmax):
                            xbar[b] = 0.0
                        _mark_flat(ints, f, PW, p, i, xbar)
                kinked = True
        if kinked:
            nf, ny = _flats(ints, f, PW, lm, m, T, y, fpiece, fleaf, foff, fq, C, C2)
            changes += 1
            continue
        if converged:
            # certify: flat points inside their bodies, weights on the ray, the full support
            outside = -1
            for e in range(nf):
                if flat_radius2(ints, f, fleaf[e], PW[fpiece[e]]) > 1.0 + 1e-12:
                    outside = e
            if outside >= 0:
                PW[fpiece[outside], ints[WSTART + fleaf[outside]]] = 1.0
                nf, ny = _flats(ints, f, PW, lm, m, T, y, fpiece, fleaf, foff, fq, C, C2)
                changes += 1
                converged = False
                continue
            # a flat point outside its body by rounding (<= 1e-12) goes onto its boundary, so
            # that the forces read off it lie in their cones to rounding (a soft finger's x
            # 5e-14 outside its unit ball was a force 5e-14 outside its cone); its piece's
            # point is evaluated again, the others are as they were
            for e in range(nf):
                p = fpiece[e]
                rho2 = flat_radius2(ints, f, fleaf[e], PW[p])
                if rho2 > 1.0:
                    w = ints[WSTART + fleaf[e]]
                    inv = 1.0 / np.sqrt(rho2)
                    for b in range(local_size(ints[KIND + fleaf[e]], f, ints[PSTART + fleaf[e]])):
                        PW[p, w + 1 + b] *= inv
                    piece_support(ints, f, u, PW[p], S[p], WS[p], JJ[p], jw, nmax)
            tz = weights_on_ray(S, m, r, lm, K, lu, dx, rhs)
            if tz <= 0.0 or smallest(lm, m) < -1e-12:
                return _failed(t, np.inf, 0.0, steps, calls, nrm, S, lm, WS)
            for i in range(n):
                point[i] = tz * r[i]
            if not reproduce(S, lm, m, point):
                return _failed(t, np.inf, 0.0, steps, calls, nrm, S, lm, WS)
            un = np.sqrt(dot(u, u))
            if not dot(u, r) > 0.0:
                return _failed(t, np.inf, 0.0, steps, calls, nrm, S, lm, WS)
            for i in range(n):
                nrm[i] = u[i] / un
            h_full = support(ints, f, nrm, point, wit)
            calls += 1
            t_up = h_full / dot(nrm, r)
            if t_up - tz <= eps * tz and t_up >= tz * (1.0 - 1e-12):
                return (True, tz, max(t_up, tz), h_full, m, steps, calls, nrm, S, lm, WS)
            # a piece the system did not hold sticks out at u: it joins with weight 0
            for p in range(m):
                if same_piece(ints, wit, PW[p]):
                    return _failed(t, t_up, h_full, steps, calls, nrm, S, lm, WS)
            if m == n:
                return _failed(t, t_up, h_full, steps, calls, nrm, S, lm, WS)
            PW[m] = wit
            lm[m] = 0.0
            m += 1
            changes += 1
            converged = False
            continue
        if not _solve_kkt(r, u, t, tau, lm, S, JJ, m, T, y, nf, ny, fpiece, foff, fq, sm, K, lu,
                          prow, pcol, rhs, dx, corner, mats, vecs):
            return _failed(t, np.inf, 0.0, steps, calls, nrm, S, lm, WS)
        steps += 1
        du = 0.0
        for i in range(n):
            u[i] += dx[i]
            du = max(du, abs(dx[i]))
        un = 0.0
        for i in range(n):
            un = max(un, abs(u[i]))
        worst = -1
        for p in range(m):
            lm[p] += dx[n + p]
            if lm[p] <= 0.0 and (worst < 0 or lm[p] < lm[worst]):
                worst = p
        for c in range(ny):
            y[c] += dx[n + m + c]
        t += dx[n + m + ny]
        tau += dx[n + m + ny + 1]
        if worst >= 0:
            # not a piece of the exit face: its weight would be negative (or is zero: the
            # basic solution left it out)
            # (S's rows shift along: every round evaluates them afresh)
            m = drop_point(S, PW, lm, m, worst)
            nf, ny = _flats(ints, f, PW, lm, m, T, y, fpiece, fleaf, foff, fq, C, C2)
            changes += 1
            converged = False
            continue
        for e in range(nf):
            w = ints[WSTART + fleaf[e]]
            for b in range(fq[e]):
                PW[fpiece[e], w + 1 + b] = y[foff[e] + b] / lm[fpiece[e]]
        converged = du <= STEP_TOL * un
    return _failed(t, np.inf, 0.0, steps, calls, nrm, S, lm, WS)
