"""The one compiled support kernel.

A convex set compiles to a *support program*: a tree of nodes stored in pre-order (a parent before
its children) in flat arrays. `support` evaluates h_A(u) and s_A(u) of eq. (2) for any program in
three passes: directions flow down the tree (an affine node maps u to M^T u), support points flow
up (a hull keeps its best child, a sum adds), and finally the leaves that produced the point are
flagged in the witness vector. Every algorithm is compiled once against this kernel, whatever the
shape.

A program is two arrays, `ints` and `floats`, so that a call from Python unboxes two arrays, not
twelve. `ints` = [nn, kind, dim, pstart, cstart, ccount, wstart, dstart, choice, active, children]
(each block nn long but `children`); `floats` = [params, scratch]. The blocks:
    kind[i]      node kind (constants below)
    dim[i]       dimension of the node's output space
    pstart[i]    offset of the node's parameters in `params`
    cstart[i], ccount[i]   its children are children[cstart[i] : cstart[i] + ccount[i]]
    wstart[i]    leaves: offset of its witness slot [active, local...] in the witness vector
    dstart[i]    offset of its direction, point and value in `scratch`
    choice[i], active[i]   work arrays: a hull's best child, whether node i produced the point
"""
import numpy as np
from numba import njit

POLYTOPE = 0   # params: m, n, vertices (m*n)            witness: [active, vertex index]
ELLIPSOID = 1  # params: n, k, center (n), shape (n*k)   witness: [active, x (k)]
BOX = 2        # params: n, half extents (n)             witness: [active, corner (n)]
TRUNCATED_CONE = 3  # params: bottom radius, top radius, height    witness: [active, point (3)]
CONE_CAP = 4   # params: n, mu                             witness: [active, g (n)]
HULL = 10
SUM = 11
AFFINE = 12    # params: m, n, M (m*n), t (m)


@njit(cache=True)
def _leaf_support(k, f, p, d, wit, w):
    """Support of one leaf: parameters at f[p:], direction at f[d:d + dim], point written to
    f[d + dim:], local witness to wit[w + 1:]. Offsets, not slices: a slice costs a reference
    count round trip, which at a few hundred nanoseconds a call dominates the arithmetic."""
    if k == POLYTOPE:
        m = int(f[p])
        n = int(f[p + 1])
        best = -np.inf
        arg = 0
        for j in range(m):
            s = 0.0
            for a in range(n):
                s += f[p + 2 + j * n + a] * f[d + a]
            if s > best:
                best = s
                arg = j
        for a in range(n):
            f[d + n + a] = f[p + 2 + arg * n + a]
        wit[w + 1] = arg
        return best
    if k == ELLIPSOID:
        n = int(f[p])
        kk = int(f[p + 1])
        c0 = p + 2
        s0 = p + 2 + n
        # x = S^T u / ||S^T u||: the pre-image of the support point on the unit ball
        nrm2 = 0.0
        for b in range(kk):
            y = 0.0
            for a in range(n):
                y += f[s0 + a * kk + b] * f[d + a]
            wit[w + 1 + b] = y
            nrm2 += y * y
        nrm = np.sqrt(nrm2)
        inv = 1.0 / nrm if nrm > 0.0 else 0.0
        for b in range(kk):
            wit[w + 1 + b] *= inv
        h = nrm
        for a in range(n):
            s = f[c0 + a]
            for b in range(kk):
                s += f[s0 + a * kk + b] * wit[w + 1 + b]
            f[d + n + a] = s
            h += f[c0 + a] * f[d + a]
        return h
    if k == BOX:
        n = int(f[p])
        h = 0.0
        for a in range(n):
            half = f[p + 1 + a]
            x = half if f[d + a] >= 0.0 else -half
            f[d + n + a] = x
            h += x * f[d + a]
            wit[w + 1 + a] = x
        return h
    if k == CONE_CAP:
        return _cone_cap_support(f, p, d, wit, w)
    # TRUNCATED_CONE: the hull of two coaxial disks
    rb = f[p]
    rt = f[p + 1]
    hz = 0.5 * f[p + 2]
    ux = f[d]
    uy = f[d + 1]
    uz = f[d + 2]
    q = np.sqrt(ux * ux + uy * uy)
    h_top = hz * uz + rt * q
    h_bot = -hz * uz + rb * q
    if h_top >= h_bot:
        rad = rt
        z = hz
        h = h_top
    else:
        rad = rb
        z = -hz
        h = h_bot
    x = rad * ux / q if q > 0.0 else 0.0
    y = rad * uy / q if q > 0.0 else 0.0
    f[d + 3] = x
    f[d + 4] = y
    f[d + 5] = z
    wit[w + 1] = x
    wit[w + 2] = y
    wit[w + 3] = z
    return h


@njit(cache=True)
def _cone_cap_support(f, p, d, wit, w):
    """Support of the unit vectors g of the circular cone K = {||g_2:n|| <= mu g_1}.

    For y at angle phi from the axis e_1 and the cone's half-angle beta = atan(mu), the unit
    vector of K closest in angle to y is y/||y|| when phi <= beta, else the boundary ray
    b = (cos beta, sin beta y_perp/||y_perp||) in the plane of e_1 and y, so that
    h(y) = ||y|| cos(max(0, phi - beta)) = y_1 cos beta + ||y_perp|| sin beta outside K. This holds
    for every phi up to pi (the angle to K stays below pi), so the cap's support is negative for
    y in the polar cone. Where positive it equals ||Pi_K(y)||, the support of K cut by the unit
    ball (NOTES.md item 3).
    """
    n = int(f[p])
    mu = f[p + 1]
    y1 = f[d]
    q2 = 0.0
    for a in range(1, n):
        q2 += f[d + a] * f[d + a]
    q = np.sqrt(q2)
    ny = np.sqrt(y1 * y1 + q2)
    if y1 >= 0.0 and q <= mu * y1:
        # y in K: the cap's point is y itself, normalized (e_1 for y = 0). The sign test is
        # not redundant: with mu = 0 and q = 0, q <= mu y1 holds for y1 < 0 too (0 <= -0.0)
        if ny > 0.0:
            for a in range(n):
                f[d + n + a] = f[d + a] / ny
        else:
            f[d + n] = 1.0
            for a in range(1, n):
                f[d + n + a] = 0.0
        h = ny
    else:
        cb = 1.0 / np.sqrt(1.0 + mu * mu)
        sb = mu * cb
        f[d + n] = cb
        if q > 0.0:
            for a in range(1, n):
                f[d + n + a] = sb * f[d + a] / q
        else:
            # y = -|y| e_1: every boundary ray is equally close; take the one along e_2
            for a in range(1, n):
                f[d + n + a] = 0.0
            if n > 1:
                f[d + n + 1] = sb
        h = y1 * cb + q * sb
    for a in range(n):
        wit[w + 1 + a] = f[d + n + a]
    return h


@njit(cache=True)
def support(ints, f, u, point, wit):
    """h_A(u) (returned) and s_A(u) (into `point`) of eq. (2); the witness goes into `wit`.

    Blocks of `ints` (each nn long): 1 kind, 2 dim, 3 pstart, 4 cstart, 5 ccount, 6 wstart,
    7 dstart, 8 choice, 9 active, then children. Node i's direction is at f[dstart:], its point
    at f[dstart + dim:], its value at f[dstart + 2 dim].
    """
    nn = ints[0]
    KIND = 1
    DIM = 1 + nn
    PSTART = 1 + 2 * nn
    CSTART = 1 + 3 * nn
    CCOUNT = 1 + 4 * nn
    WSTART = 1 + 5 * nn
    DSTART = 1 + 6 * nn
    CHOICE = 1 + 7 * nn
    ACTIVE = 1 + 8 * nn
    CHILDREN = 1 + 9 * nn
    d0 = ints[DSTART]
    n0 = ints[DIM]
    for a in range(n0):
        f[d0 + a] = u[a]
    # directions flow down
    for i in range(nn):
        k = ints[KIND + i]
        if k < HULL:
            continue
        di = ints[DSTART + i]
        ni = ints[DIM + i]
        for c in range(ints[CCOUNT + i]):
            ch = ints[CHILDREN + ints[CSTART + i] + c]
            dc = ints[DSTART + ch]
            if k == AFFINE:
                p0 = ints[PSTART + i]
                nc = ints[DIM + ch]
                for b in range(nc):
                    s = 0.0
                    for a in range(ni):
                        s += f[p0 + 2 + a * nc + b] * f[di + a]
                    f[dc + b] = s
            else:
                for a in range(ni):
                    f[dc + a] = f[di + a]
    # support points flow up
    for i in range(nn - 1, -1, -1):
        k = ints[KIND + i]
        di = ints[DSTART + i]
        ni = ints[DIM + i]
        if k < HULL:
            f[di + 2 * ni] = _leaf_support(k, f, ints[PSTART + i], di, wit, ints[WSTART + i])
        elif k == HULL:
            best = -np.inf
            arg = ints[CHILDREN + ints[CSTART + i]]
            for c in range(ints[CCOUNT + i]):
                ch = ints[CHILDREN + ints[CSTART + i] + c]
                hc = f[ints[DSTART + ch] + 2 * ni]
                if hc > best:
                    best = hc
                    arg = ch
            ints[CHOICE + i] = arg
            src = ints[DSTART + arg] + ni
            for a in range(ni):
                f[di + ni + a] = f[src + a]
            f[di + 2 * ni] = best
        elif k == SUM:
            for a in range(ni):
                f[di + ni + a] = 0.0
            h = 0.0
            for c in range(ints[CCOUNT + i]):
                dc = ints[DSTART + ints[CHILDREN + ints[CSTART + i] + c]]
                for a in range(ni):
                    f[di + ni + a] += f[dc + ni + a]
                h += f[dc + 2 * ni]
            f[di + 2 * ni] = h
        else:
            ch = ints[CHILDREN + ints[CSTART + i]]
            dc = ints[DSTART + ch]
            nc = ints[DIM + ch]
            p0 = ints[PSTART + i]
            h = f[dc + 2 * nc]
            for a in range(ni):
                s = f[p0 + 2 + ni * nc + a]
                h += s * f[di + a]
                for b in range(nc):
                    s += f[p0 + 2 + a * nc + b] * f[dc + nc + b]
                f[di + ni + a] = s
            f[di + 2 * ni] = h
    # flag the leaves that produced the point: every child of a sum, the chosen child of a hull
    ints[ACTIVE] = 1
    for i in range(nn):
        k = ints[KIND + i]
        if k < HULL:
            wit[ints[WSTART + i]] = ints[ACTIVE + i]
            continue
        for c in range(ints[CCOUNT + i]):
            ch = ints[CHILDREN + ints[CSTART + i] + c]
            ints[ACTIVE + ch] = ints[ACTIVE + i] if (k != HULL or ch == ints[CHOICE + i]) else 0
    for a in range(n0):
        point[a] = f[d0 + n0 + a]
    return f[d0 + 2 * n0]
