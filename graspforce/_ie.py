"""The generalized internal-expanding (IE) procedure of section 3.2, with facet and ridge
collections, so that it converges when the ray crosses a face of dimension lower than n - 1.

State: b_k = t r on the face CH(S_k) of the inner polytope CH(support points), and the
collection F_k of facets (n support points each) that contain S_k. A facet is stored by its
hyperplane y^T x = 1 (so its distance from the origin is 1/||y||, its unit normal y/||y||) and the
conic coordinates gam of r in its vertices (r = sum gam_l a_l, t = 1 / sum gam). A vertex of S_k is
one with gam_l > 0.

Each iteration takes the facet i* nearest the origin, evaluates s = s_A(n_i*), and stops when
h_A(n_i*) - n_i*^T b_k <= eps n_i*^T b_k. Otherwise, with F+ the facets s lies beyond:
- case 1 (F+ = F_k): the ray leaves through one of the facets that join s to the ridges of F_k
  not containing S_k; b_{k+1} is the farthest crossing, F_{k+1} every new facet through it;
- case 2 (F+ a proper sub-collection): each visible facet's ridges that contain S_k and are not
  shared with another visible facet are joined to s; b_k and S_k stay, the nearest facet moves
  away from the origin, so case 1 follows after finitely many steps (the paper's argument).
"""
import numpy as np
from numba import njit

from ._jit import borrowing
from ._kernel import support
from ._linalg import dot, lu_factor, lu_solve, lu_solve_t
from ._shooters import FACET, HIT, LIMIT, UNTIL_FACET, _result, zc_from, zc_family

FACE_TOL = 1e-12      # gam_l <= FACE_TOL * sum(gam): vertex l is not in the face of b_k
BEYOND_TOL = 1e-12    # y^T s > 1 + BEYOND_TOL: s lies beyond the facet


@borrowing
def _factor(pool, idx, M, lu, piv):
    """LU of the matrix whose columns are the facet's vertices pool[idx]; False if singular."""
    n = idx.shape[0]
    for j in range(n):
        for i in range(n):
            M[i, j] = pool[idx[j], i]
    return lu_factor(M, n, lu, piv)


@borrowing
def _facet(pool, idx, r, M, lu, piv, ones, y, gam):
    """Hyperplane y and conic coordinates gam of the facet with vertices pool[idx]; False when
    it is degenerate or does not face the ray (y^T r <= 0)."""
    n = r.shape[0]
    if not _factor(pool, idx, M, lu, piv):
        return False
    lu_solve_t(lu, piv, n, ones, y)
    lu_solve(lu, piv, n, r, gam)
    return dot(y, r) > 0.0


@borrowing
def _ratio_test(pool, facet, gam, s, M, lu, piv, alpha):
    """The vertex j* that s replaces so that the ray still crosses the facet: with
    s = sum alpha_l a_l, j* minimizes gam_j / alpha_j over alpha_j > 0. -1 on a tie (the ray
    would cross a lower-dimensional face: the general step handles it) or a singular facet."""
    n = s.shape[0]
    if not _factor(pool, facet, M, lu, piv):
        return -1
    lu_solve(lu, piv, n, s, alpha)
    js = -1
    best = np.inf
    second = np.inf
    for j in range(n):
        if alpha[j] > 0.0:
            ratio = gam[j] / alpha[j]
            if ratio < best:
                second = best
                best = ratio
                js = j
            elif ratio < second:
                second = ratio
    if js >= 0 and second <= best * (1.0 + 1e-9):
        return -1
    return js


@njit(cache=True)
def _push(F, Y, GAM, nf, idx, y, gam):
    """Append a facet to a collection; -1 when the collection is full."""
    if nf == F.shape[0]:
        return -1
    F[nf] = idx
    Y[nf] = y
    GAM[nf] = gam
    return nf + 1


@borrowing
def _contains(F, g, ridge, m):
    """Whether facet row F[g] holds all m indices of `ridge`."""
    n = F.shape[1]
    for a in range(m):
        found = False
        for j in range(n):
            if F[g, j] == ridge[a]:
                found = True
                break
        if not found:
            return False
    return True


@njit(cache=True)
def ie(ints, floats, r, ws, eps, max_iter):
    n = r.shape[0]
    # initialization shared with ZC-IE: ZC-based iterations until V_k is a facet crossed by the
    # ray in its interior (a flat set never has one: ZC-based then finishes the job)
    none = np.empty((0, 0))
    out = zc_from(ints, floats, r, ws, eps, max_iter, UNTIL_FACET, 0.0, np.empty((n + 2, n)),
                  np.empty((n + 2, ws)), np.empty(n + 2), 0, 0, 0, none, none)
    if out[0] != FACET:
        return out
    return ie_from(ints, floats, r, ws, eps, max_iter, out[7], out[9], out[4], out[5])


@njit(cache=True)
def ie_from(ints, floats, r, ws, eps, max_iter, V, Wv, it, calls):
    """IE's steps from the facet V[:n] (support points of A, witnesses Wv) that the ray crosses:
    ZC's first facet (`ie`) or a start table's (graspforce._start_table)."""
    n = r.shape[0]
    cap_pts = n + 1 + max_iter
    pool = np.empty((cap_pts, n))
    pwit = np.empty((cap_pts, ws))
    pool[:n] = V[:n]
    pwit[:n] = Wv[:n]
    npts = n
    cap_f = 64 * n
    F = np.empty((cap_f, n), np.int64)
    Y = np.empty((cap_f, n))
    GAM = np.empty((cap_f, n))
    F2 = np.empty((cap_f, n), np.int64)
    Y2 = np.empty((cap_f, n))
    GAM2 = np.empty((cap_f, n))
    M = np.empty((n, n))
    lu = np.empty((n, n))
    piv = np.empty(n, np.int64)
    ones = np.ones(n)
    y = np.empty(n)
    gam = np.empty(n)
    idx = np.empty(n, np.int64)
    ridge = np.empty(n, np.int64)
    visible = np.empty(cap_f, np.bool_)
    nvec = np.empty(n)
    point = np.empty(n)
    wit = np.empty(ws)
    for j in range(n):
        F[0, j] = j
    if not _facet(pool, F[0], r, M, lu, piv, ones, Y[0], GAM[0]):
        return zc_family(ints, floats, r, ws, eps, max_iter, 0)
    nf = 1
    t = 1.0 / dot(Y[0], r)
    best = 0
    h = 0.0
    ny = 1.0
    singular = 0
    while it < max_iter:
        # the facet of F_k nearest the origin: largest ||y||
        best = 0
        by = 0.0
        for f in range(nf):
            yy = dot(Y[f], Y[f])
            if yy > by:
                by = yy
                best = f
        ny = np.sqrt(by)
        for i in range(n):
            nvec[i] = Y[best, i] / ny
        h = support(ints, floats, nvec, point, wit)
        calls += 1
        it += 1
        if h - 1.0 / ny <= eps / ny:
            break
        if npts == cap_pts:
            return _ie_result(LIMIT, t, pool, pwit, F[best], GAM[best], nvec, h, ny, r, it,
                              calls, singular)
        q = npts
        pool[q] = point
        pwit[q] = wit
        npts += 1
        all_visible = True
        for f in range(nf):
            visible[f] = dot(Y[f], point) > 1.0 + BEYOND_TOL
            all_visible = all_visible and visible[f]
        nf2 = 0
        if nf == 1 and GAM[0].min() > FACE_TOL * GAM[0].sum():
            # b_k inside the single facet (the usual case): the ratio test of the simplex
            # method picks the new facet with one solve instead of n factorizations
            js = _ratio_test(pool, F[0], GAM[0], point, M, lu, piv, y)
            if js >= 0:
                idx[:] = F[0]
                idx[js] = q
                if _facet(pool, idx, r, M, lu, piv, ones, y, gam):
                    yr = dot(y, r)
                    if gam.min() > FACE_TOL * yr:
                        F[0] = idx
                        Y[0] = y
                        GAM[0] = gam
                        t = 1.0 / yr
                        continue
        if all_visible:
            # case 1: replace each vertex of S_k in each facet by s; keep the farthest crossing
            t_best = t
            for f in range(nf):
                gsum = GAM[f].sum()
                for a in range(n):
                    if GAM[f, a] <= FACE_TOL * gsum:
                        continue
                    idx[:] = F[f]
                    idx[a] = q
                    if not _facet(pool, idx, r, M, lu, piv, ones, y, gam):
                        continue
                    yr = dot(y, r)
                    if gam.min() < -FACE_TOL * yr:
                        continue
                    tc = 1.0 / yr
                    if tc < t_best * (1.0 - 1e-12):
                        continue
                    if tc > t_best * (1.0 + 1e-12):
                        # strictly farther: the earlier candidates cross elsewhere
                        t_best = tc
                        nf2 = 0
                    nf2 = _push(F2, Y2, GAM2, nf2, idx, y, gam)
                    if nf2 < 0:
                        return _ie_result(LIMIT, t, pool, pwit, F[best], GAM[best], nvec, h,
                                          ny, r, it, calls, singular)
            if nf2 == 0:
                # rounding left no candidate crossing the ray: finish with ZC-based iterations
                return _from_facet(ints, floats, r, ws, eps, max_iter, t, pool, pwit, F[best],
                                   GAM[best], it, calls)
            t = t_best
        else:
            # case 2: keep the facets s does not see; join s to the ridges that contain S_k
            # and border a facet s does not see
            for f in range(nf):
                if not visible[f]:
                    nf2 = _push(F2, Y2, GAM2, nf2, F[f], Y[f], GAM[f])
            for f in range(nf):
                if not visible[f]:
                    continue
                gsum = GAM[f].sum()
                for a in range(n):
                    if GAM[f, a] > FACE_TOL * gsum:
                        continue   # dropping a vertex of S_k: this ridge does not contain S_k
                    m = 0
                    for j in range(n):
                        if j != a:
                            ridge[m] = F[f, j]
                            m += 1
                    shared = False
                    for g in range(nf):
                        if g != f and visible[g] and _contains(F, g, ridge, n - 1):
                            shared = True
                            break
                    if shared:
                        continue
                    idx[:] = F[f]
                    idx[a] = q
                    if not _facet(pool, idx, r, M, lu, piv, ones, y, gam):
                        continue
                    nf2 = _push(F2, Y2, GAM2, nf2, idx, y, gam)
                    if nf2 < 0:
                        return _ie_result(LIMIT, t, pool, pwit, F[best], GAM[best], nvec, h,
                                          ny, r, it, calls, singular)
            if nf2 == 0:
                return _from_facet(ints, floats, r, ws, eps, max_iter, t, pool, pwit, F[best],
                                   GAM[best], it, calls)
        nf = nf2
        if nf > 1:
            singular += 1   # b_k sits on a face of dimension < n - 1 shared by nf facets
        F[:nf] = F2[:nf]
        Y[:nf] = Y2[:nf]
        GAM[:nf] = GAM2[:nf]
    status = HIT if it <= max_iter and h - 1.0 / ny <= eps / ny else LIMIT
    return _ie_result(status, t, pool, pwit, F[best], GAM[best], nvec, h, ny, r, it, calls,
                      singular)


@njit(cache=True)
def _face(pool, pwit, facet, gam, t):
    """Z_A(r): the vertices of the facet that carry b_k (gam > 0), with weights gam t."""
    n = facet.shape[0]
    gsum = gam.sum()
    k = 0
    for a in range(n):
        if gam[a] > FACE_TOL * gsum:
            k += 1
    V = np.empty((k, n))
    W = np.empty((k, pwit.shape[1]))
    lam = np.empty(k)
    k = 0
    for a in range(n):
        if gam[a] > FACE_TOL * gsum:
            V[k] = pool[facet[a]]
            W[k] = pwit[facet[a]]
            lam[k] = gam[a]
            k += 1
    lam /= lam.sum()
    return V, W, lam, k


@njit(cache=True)
def _ie_result(status, t, pool, pwit, facet, gam, nvec, h, ny, r, it, calls, singular):
    V, W, lam, k = _face(pool, pwit, facet, gam, t)
    t_up = h / dot(nvec, r)
    return _result(status, t, t_up, h, it, calls, nvec, V, lam, W, k, singular)


@njit(cache=True)
def _from_facet(ints, floats, r, ws, eps, max_iter, t, pool, pwit, facet, gam, it, calls):
    V, W, lam, k = _face(pool, pwit, facet, gam, t)
    n = r.shape[0]
    Pz = np.empty((n + 2, n))
    Wz = np.empty((n + 2, ws))
    lz = np.empty(n + 2)
    Pz[:k] = V
    Wz[:k] = W
    lz[:k] = lam
    none = np.empty((0, 0))
    return zc_from(ints, floats, r, ws, eps, max_iter, 0, t, Pz, Wz, lz, k, it, calls, none, none)
