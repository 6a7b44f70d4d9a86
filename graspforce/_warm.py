"""ZC-IE warm-started from a previous answer's normal (time coherence, the paper's future work).

When a query follows a similar one (an object pair that moved a little), the new z_A(r) lies
near the old supporting hyperplane's touching point. Instead of ZC's search from the origin,
take n support points in directions spread around the previous normal; if the ray crosses
their facet (positive conic coordinates), IE steps start right there, with the probes'
directions for IE's secant query (graspforce._shooters). If it misses, the same secant model
says where the normal at z_A(r) is: the next probes are centred there.
"""
import numpy as np
from numba import njit
from numba.extending import register_jitable

from ._kernel import support
from ._jit import borrowing, view
from ._linalg import dot, lu_factor, lu_solve, smallest
from ._packed import pack, pack_arrays
from ._shooters import (HIT, LIMIT, MISS, ST_CALLS, ST_H, ST_IT, ST_KZ, ST_SINGULAR, ST_T,
                        ST_T_UP, WITH_IE, loop_rows_state, reported_upper, start_state,
                        zc_drive, zc_family, zc_loop, zc_work, zc_work_size)

# probe rounds before the cold start; a round that misses the ray recentres the next one (same
# spread) where the secant model through its probes puts the normal at z_A(r), or, when the
# model gives no centre, widens it by 4. Recentring against widening alone, zc-ie growth
# support calls: protocol mean 21.9 -> 21.7, median 21 -> 20; random pairs' mean 21.6 -> 21.5
# (BENCHMARKS.md, "Stop 29"). Without the secant query's gain rule the secant query stalled
# on recentred facets of the warm-start benchmark's moving pair (61 support calls against 33,
# stop 28); with it, they take 31.3 against 31.7
WIDENINGS = 3


# `_warm_shot`'s stop when the ray misses every round of probes
PROBES_MISSED = -1


@njit(cache=True)
def shoot_warm(ints, floats, r, ws, eps, max_iter, normal, spread, packed, e):
    """ZC-IE (section 3.4.2) from the facet of the support points in the directions
    normal + spread w_j (`normal` a unit vector), w_j the vertices of a regular simplex in the
    plane orthogonal to `normal`; while the ray misses that facet, the next probes are centred
    at the secant model's normal sum_j gam_j d_j / sum_j gam_j (r = sum_j gam_j P_j), or
    widened when that points away from r; after WIDENINGS rounds, cold ZC-IE. Writes the shot's arrays to packed[e:] (graspforce._packed) and returns
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
                         witnesses[:n + 2], lam, rows[:0], rows[n + 8:], work, piv, -head[0]),
                packed, e)


@register_jitable
def _probe_size(n, ws):
    """Entries of the probes' arrays (`_probe_arrays`)."""
    return (2 * n + 8) * n + (n + 3) * ws + n + 2 + 2 * n * n


@register_jitable
def _probe_arrays(work, n, ws):
    """`_probe_facet`'s arrays (rows: the facet P, the n-vectors, the probes' directions;
    witnesses; weights; two n x n matrices) as views of shoot_warm's work array, after zc_from's
    loop's."""
    a = zc_work_size(n, ws)
    b = a + (2 * n + 8) * n
    c = b + (n + 3) * ws
    d = c + n + 2
    return (view(work, a, (2 * n + 8, n)), view(work, b, (n + 3, ws)), view(work, c, n + 2),
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
                   rows[n + 8:], work, piv)
    if code != HIT and code != MISS and code != LIMIT:
        return -code, 0.0, 0.0, 0.0, 0, 0, 0, 0
    loop_rows, state = loop_rows_state(work, n, ws)
    t = state[ST_T]
    kz = int(state[ST_KZ])
    pack_arrays(loop_rows[n + 2], P, lam, Wt, kz, packed, e)
    return (code, t, reported_upper(code, t, state[ST_T_UP]), state[ST_H], int(state[ST_IT]),
            int(state[ST_CALLS]), int(state[ST_SINGULAR]), kz)


@borrowing
def _probe_facet(ints, floats, r, ws, normal, spread, rows, witnesses, lam, matrices, piv):
    """`shoot_warm`'s probe rounds: (t, support calls), t > 0 when the ray crosses the facet of
    the probes P = rows[:n] (witnesses[:n], unit directions rows[n + 8:]) at t r = lam @ P,
    else 0."""
    n = r.shape[0]
    P = rows[:n + 2]
    v, d, w, point, gam, centre = (rows[n + 2], rows[n + 3], rows[n + 4], rows[n + 5],
                                   rows[n + 6], rows[n + 7])
    # the probes' unit directions: with them, IE's steps may take the secant query
    directions = rows[n + 8:]
    Wt = witnesses[:n + 2]
    wit = witnesses[n + 2]
    M, lu = matrices[0], matrices[1]
    for a in range(n):
        centre[a] = normal[a]
    calls = 0
    for attempt in range(WIDENINGS):
        # Householder reflection taking (1, ..., 1)/sqrt(n) to the centre: it maps the simplex
        # e_j - 1/n, orthogonal to (1, ..., 1), into the centre's orthogonal plane
        vv = 0.0
        for a in range(n):
            v[a] = 1.0 / np.sqrt(n) - centre[a]
            vv += v[a] * v[a]
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
                d[a] = centre[a] + spread * w[a]
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
            # the ray misses the facet. The secant model through the probes (IE's secant query,
            # graspforce._shooters) extrapolates to the normal at z_A(r):
            # sum_j gam_j d_j / sum_j gam_j. The next probes are centred there
            cr = 0.0
            for a in range(n):
                s = 0.0
                for j in range(n):
                    s += gam[j] * directions[j, a]
                w[a] = s
                cr += s * r[a]
            # gs > 0: r is beyond the probes' hyperplane, the model's weights are affine ones
            if gs > 0.0 and cr > 0.0:
                cn = 1.0 / np.sqrt(dot(w, w))
                for a in range(n):
                    centre[a] = w[a] * cn
                continue
        # a wider spread when that fails too: the pose moved more than expected
        spread *= 4.0
    return 0.0, calls
