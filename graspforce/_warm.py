"""ZC-IE warm-started from a previous answer's normal (time coherence, the paper's future work).

When a query follows a similar one (an object pair that moved a little), the new z_A(r) lies
near the old supporting hyperplane's touching point. Instead of ZC's search from the origin,
take n support points in directions spread around the previous normal; if the ray crosses
their facet (positive conic coordinates), IE steps start right there, with the probes'
directions for IE's secant query (graspforce._shooters).
"""
import numpy as np
from numba import njit

from ._kernel import support
from ._jit import borrowing
from ._linalg import lu_factor, lu_solve, smallest
from ._shooters import WITH_IE, zc_family, zc_from

# probe rounds before the cold start: spread, 4 spread, 16 spread. Recentring the next round
# where the secant model through the probes puts the normal (sum_j gam_j d_j) was tried: fewer
# support calls on the protocol (mean 22.2 -> 21.6) and random pairs (24.7 -> 24.2), but on the
# moving pair of the warm-start benchmark the secant query stalled on the recentred facets (61
# support calls against 33 from widened ones, 78 of 400 poses), so it was dropped (before the
# secant query's gain rule, which catches such stalls: worth measuring again)
WIDENINGS = 3


@njit(cache=True)
def shoot_warm(ints, floats, r, ws, eps, max_iter, normal, spread):
    """ZC-IE (section 3.4.2) from the facet of the support points in the directions
    normal + spread w_j (`normal` a unit vector), w_j the vertices of a regular simplex in the
    plane orthogonal to `normal`, widened while the ray misses that facet; after WIDENINGS
    rounds, cold ZC-IE. Same result tuple as `shoot`."""
    n = r.shape[0]
    # rows of few allocations, as in zc_from; the views are made in `_probe_facet`, which
    # counts no references (graspforce._jit): here each would cost two atomic updates
    rows = np.empty((2 * n + 7, n))
    witnesses = np.empty((n + 3, ws))
    lam = np.empty(n + 2)
    matrices = np.empty((2, n, n))
    piv = np.empty(n, np.int64)
    t, calls = _probe_facet(ints, floats, r, ws, normal, spread, rows, witnesses, lam, matrices,
                            piv)
    if t > 0.0:
        # the probes' unit directions (rows[n + 7:]) turn on IE's secant query; no facet
        # inverse to hand over: an empty view, not an allocation
        return zc_from(ints, floats, r, ws, eps, max_iter, WITH_IE, t, rows[:n + 2],
                       witnesses[:n + 2], lam, n, 0, calls, rows[:0], rows[n + 7:])
    out = zc_family(ints, floats, r, ws, eps, max_iter, WITH_IE)
    return (out[0], out[1], out[2], out[3], out[4], out[5] + calls, out[6], out[7], out[8],
            out[9], out[10])


@borrowing
def _probe_facet(ints, floats, r, ws, normal, spread, rows, witnesses, lam, matrices, piv):
    """`shoot_warm`'s probe rounds: (t, support calls), t > 0 when the ray crosses the facet of
    the probes P = rows[:n] (witnesses[:n], unit directions rows[n + 7:]) at t r = lam @ P,
    else 0."""
    n = r.shape[0]
    P = rows[:n + 2]
    v, d, w, point, gam = rows[n + 2], rows[n + 3], rows[n + 4], rows[n + 5], rows[n + 6]
    # the probes' unit directions: with them, IE's steps may take the secant query
    directions = rows[n + 7:]
    Wt = witnesses[:n + 2]
    wit = witnesses[n + 2]
    M, lu = matrices[0], matrices[1]
    # Householder reflection taking (1, ..., 1)/sqrt(n) to the normal: it maps the simplex
    # e_j - 1/n, orthogonal to (1, ..., 1), into the normal's orthogonal plane
    vv = 0.0
    for a in range(n):
        v[a] = 1.0 / np.sqrt(n) - normal[a]
        vv += v[a] * v[a]
    calls = 0
    for attempt in range(WIDENINGS):
        for j in range(n):
            for a in range(n):
                w[a] = (1.0 if a == j else 0.0) - 1.0 / n
            if vv > 1e-30:
                vw = 0.0
                for a in range(n):
                    vw += v[a] * w[a]
                for a in range(n):
                    w[a] -= 2.0 * vw / vv * v[a]
            dd = 0.0
            for a in range(n):
                d[a] = normal[a] + spread * w[a]
                dd += d[a] * d[a]
            support(ints, floats, d, point, wit)
            dn = 1.0 / np.sqrt(dd)
            for a in range(n):
                P[j, a] = point[a]
                directions[j, a] = d[a] * dn
            for a in range(ws):
                Wt[j, a] = wit[a]
        calls += n
        # conic coordinates of r in the n points: r = sum gam_j P[j]
        for i in range(n):
            for j in range(n):
                M[i, j] = P[j, i]
        if lu_factor(M, n, lu, piv):
            lu_solve(lu, piv, n, r, gam)
            gs = 0.0
            for j in range(n):
                gs += gam[j]
            if smallest(gam, n) > 0.0:
                t = 1.0 / gs
                for j in range(n):
                    lam[j] = gam[j] * t
                return t, calls
        # a wider spread when the ray misses the facet: the pose moved more than expected
        spread *= 4.0
    return 0.0, calls
