"""ZC-IE warm-started from a previous answer's normal (time coherence, the paper's future work).

When a query follows a similar one (an object pair that moved a little), the new z_A(r) lies
near the old supporting hyperplane's touching point. Instead of ZC's search from the origin,
take n support points in directions spread around the previous normal; if the ray crosses
their facet (positive conic coordinates), IE steps start right there, with the probes'
directions for IE's secant query (graspforce._shooters).
"""
import numpy as np
from numba import njit
from numba.extending import register_jitable

from ._kernel import support
from ._jit import borrowing, view
from ._linalg import lu_factor, lu_solve, smallest
from ._packed import pack, pack_arrays
from ._shooters import (HIT, LIMIT, MISS, ST_CALLS, ST_H, ST_IT, ST_KZ, ST_SINGULAR, ST_T,
                        ST_T_UP, WITH_IE, loop_arrays, reported_upper, start_state, zc_drive,
                        zc_family, zc_loop, zc_work, zc_work_size)

# probe rounds before the cold start: spread, 4 spread, 16 spread. Recentring the next round
# where the secant model through the probes puts the normal (sum_j gam_j d_j) was tried: fewer
# support calls on the protocol (mean 22.2 -> 21.6) and random pairs (24.7 -> 24.2), but on the
# moving pair of the warm-start benchmark the secant query stalled on the recentred facets (61
# support calls against 33 from widened ones, 78 of 400 poses), so it was dropped (before the
# secant query's gain rule, which catches such stalls: worth measuring again)
WIDENINGS = 3


# `_warm_shot`'s stop when the ray misses every round of probes
PROBES_MISSED = -1


@njit(cache=True)
def shoot_warm(ints, floats, r, ws, eps, max_iter, normal, spread, packed, e):
    """ZC-IE (section 3.4.2) from the facet of the support points in the directions
    normal + spread w_j (`normal` a unit vector), w_j the vertices of a regular simplex in the
    plane orthogonal to `normal`, widened while the ray misses that facet; after WIDENINGS
    rounds, cold ZC-IE. Writes the shot's arrays to packed[e:] (graspforce._packed) and returns
    its head (status, t, t_upper, h_n, iterations, support_calls, singular_steps, k)."""
    n = r.shape[0]
    # zc_from's loop's work array with room for the probes' (`_probe_arrays`): the probes and
    # the loop count no references (graspforce._jit), and the shot allocates twice
    work, piv = zc_work(n, ws, _probe_size(n, ws))
    head = _warm_shot(ints, floats, r, ws, eps, max_iter, normal, spread, work, piv, packed, e)
    if head[0] >= 0:
        return head
    if head[0] == PROBES_MISSED:
        calls = head[5]
        out = pack(zc_family(ints, floats, r, ws, eps, max_iter, WITH_IE), packed, e)
        return out[0], out[1], out[2], out[3], out[4], out[5] + calls, out[6], out[7]
    # a stop that zc_from's counted driver settles (ZC's uncertified point: the Newton finish)
    rows, witnesses, lam, _ = _probe_arrays(work, n, ws)
    return pack(zc_drive(ints, floats, r, ws, eps, max_iter, WITH_IE + 0, rows[:n + 2],
                         witnesses[:n + 2], lam, rows[:0], rows[n + 7:], work, piv, -head[0]),
                packed, e)


@register_jitable
def _probe_size(n, ws):
    """Entries of the probes' arrays (`_probe_arrays`)."""
    return (2 * n + 7) * n + (n + 3) * ws + n + 2 + 2 * n * n


@register_jitable
def _probe_arrays(work, n, ws):
    """`_probe_facet`'s arrays (rows: the facet P, the n-vectors, the probes' directions;
    witnesses; weights; two n x n matrices) as views of shoot_warm's work array, after zc_from's
    loop's."""
    a = zc_work_size(n, ws)
    b = a + (2 * n + 7) * n
    c = b + (n + 3) * ws
    d = c + n + 2
    return (view(work, a, (2 * n + 7, n)), view(work, b, (n + 3, ws)), view(work, c, n + 2),
            view(work, d, (2, n, n)))


@borrowing
def _warm_shot(ints, floats, r, ws, eps, max_iter, normal, spread, work, piv, packed, e):
    """shoot_warm's probes and ZC-IE, in its arrays. A finished shot is packed and its head
    returned; else the head's status is PROBES_MISSED (with the probes' support calls) or minus
    zc_from's loop's stop, for its driver."""
    n = r.shape[0]
    rows, witnesses, lam, matrices = _probe_arrays(work, n, ws)
    t, calls = _probe_facet(ints, floats, r, ws, normal, spread, rows, witnesses, lam, matrices,
                            piv)
    if t <= 0.0:
        return PROBES_MISSED, 0.0, 0.0, 0.0, 0, calls, 0, 0
    P, Wt = rows[:n + 2], witnesses[:n + 2]
    start_state(work, n, ws, t, n, 0, calls)
    # the probes' unit directions turn on IE's secant query; no facet inverse to hand over: an
    # empty view
    code = zc_loop(ints, floats, r, ws, eps, max_iter, WITH_IE + 0, P, Wt, lam, rows[:0],
                   rows[n + 7:], work, piv)
    if code != HIT and code != MISS and code != LIMIT:
        return -code, 0.0, 0.0, 0.0, 0, 0, 0, 0
    loop_rows, _, _, _, _, state = loop_arrays(work, n, ws)
    t = state[ST_T]
    kz = int(state[ST_KZ])
    pack_arrays(loop_rows[n + 2], P, lam, Wt, kz, packed, e)
    return (code, t, reported_upper(code, t, state[ST_T_UP]), state[ST_H], int(state[ST_IT]),
            int(state[ST_CALLS]), int(state[ST_SINGULAR]), kz)


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
