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
HULL = 10
SUM = 11
AFFINE = 12    # params: m, n, M (m*n), t (m)


@njit(cache=True)
def _leaf_support(k, p, u, point, wit, w):
    """Support of one leaf with parameters at p[...]; writes the point and the local witness."""
    if k == POLYTOPE:
        m = int(p[0])
        n = int(p[1])
        best = -np.inf
        arg = 0
        for j in range(m):
            s = 0.0
            for a in range(n):
                s += p[2 + j * n + a] * u[a]
            if s > best:
                best = s
                arg = j
        for a in range(n):
            point[a] = p[2 + arg * n + a]
        wit[w + 1] = arg
        return best
    if k == ELLIPSOID:
        n = int(p[0])
        kk = int(p[1])
        c0 = 2
        s0 = 2 + n
        # x = S^T u / ||S^T u||: the pre-image of the support point on the unit ball
        nrm2 = 0.0
        for b in range(kk):
            y = 0.0
            for a in range(n):
                y += p[s0 + a * kk + b] * u[a]
            wit[w + 1 + b] = y
            nrm2 += y * y
        nrm = np.sqrt(nrm2)
        inv = 1.0 / nrm if nrm > 0.0 else 0.0
        for b in range(kk):
            wit[w + 1 + b] *= inv
        h = nrm
        for a in range(n):
            s = p[c0 + a]
            for b in range(kk):
                s += p[s0 + a * kk + b] * wit[w + 1 + b]
            point[a] = s
            h += p[c0 + a] * u[a]
        return h
    if k == BOX:
        n = int(p[0])
        h = 0.0
        for a in range(n):
            half = p[1 + a]
            if u[a] >= 0.0:
                point[a] = half
                h += half * u[a]
            else:
                point[a] = -half
                h -= half * u[a]
            wit[w + 1 + a] = point[a]
        return h
    # TRUNCATED_CONE: the hull of two coaxial disks
    rb = p[0]
    rt = p[1]
    hz = 0.5 * p[2]
    q = np.sqrt(u[0] * u[0] + u[1] * u[1])
    h_top = hz * u[2] + rt * q
    h_bot = -hz * u[2] + rb * q
    if h_top >= h_bot:
        r = rt
        point[2] = hz
        h = h_top
    else:
        r = rb
        point[2] = -hz
        h = h_bot
    if q > 0.0:
        point[0] = r * u[0] / q
        point[1] = r * u[1] / q
    else:
        point[0] = 0.0
        point[1] = 0.0
    for a in range(3):
        wit[w + 1 + a] = point[a]
    return h


@njit(cache=True)
def support(ints, floats, u, point, wit):
    """h_A(u) (returned) and s_A(u) (into `point`) of eq. (2); the witness goes into `wit`."""
    nn = ints[0]
    kind = ints[1:1 + nn]
    dim = ints[1 + nn:1 + 2 * nn]
    pstart = ints[1 + 2 * nn:1 + 3 * nn]
    cstart = ints[1 + 3 * nn:1 + 4 * nn]
    ccount = ints[1 + 4 * nn:1 + 5 * nn]
    wstart = ints[1 + 5 * nn:1 + 6 * nn]
    dstart = ints[1 + 6 * nn:1 + 7 * nn]
    choice = ints[1 + 7 * nn:1 + 8 * nn]
    active = ints[1 + 8 * nn:1 + 9 * nn]
    children = ints[1 + 9 * nn:]
    params = floats
    scratch = floats
    # scratch per node i: direction at dstart[i], point at dstart[i] + dim[i], value at + 2 dim[i]
    for a in range(dim[0]):
        scratch[dstart[0] + a] = u[a]
    for i in range(nn):
        k = kind[i]
        if k < HULL:
            continue
        di = dstart[i]
        for c in range(ccount[i]):
            ch = children[cstart[i] + c]
            dc = dstart[ch]
            if k == AFFINE:
                p0 = pstart[i]
                m = int(params[p0])
                n = int(params[p0 + 1])
                for b in range(n):
                    s = 0.0
                    for a in range(m):
                        s += params[p0 + 2 + a * n + b] * scratch[di + a]
                    scratch[dc + b] = s
            else:
                for a in range(dim[i]):
                    scratch[dc + a] = scratch[di + a]
    for i in range(nn - 1, -1, -1):
        k = kind[i]
        di = dstart[i]
        ni = dim[i]
        if k < HULL:
            scratch[di + 2 * ni] = _leaf_support(
                k, params[pstart[i]:], scratch[di:di + ni], scratch[di + ni:di + 2 * ni],
                wit, wstart[i])
        elif k == HULL:
            best = -np.inf
            arg = children[cstart[i]]
            for c in range(ccount[i]):
                ch = children[cstart[i] + c]
                hc = scratch[dstart[ch] + 2 * dim[ch]]
                if hc > best:
                    best = hc
                    arg = ch
            choice[i] = arg
            src = dstart[arg] + ni
            for a in range(ni):
                scratch[di + ni + a] = scratch[src + a]
            scratch[di + 2 * ni] = best
        elif k == SUM:
            for a in range(ni):
                scratch[di + ni + a] = 0.0
            h = 0.0
            for c in range(ccount[i]):
                ch = children[cstart[i] + c]
                dc = dstart[ch]
                for a in range(ni):
                    scratch[di + ni + a] += scratch[dc + ni + a]
                h += scratch[dc + 2 * ni]
            scratch[di + 2 * ni] = h
        else:
            ch = children[cstart[i]]
            dc = dstart[ch]
            nc = dim[ch]
            p0 = pstart[i]
            h = scratch[dc + 2 * nc]
            for a in range(ni):
                s = params[p0 + 2 + ni * nc + a]
                h += s * scratch[di + a]
                for b in range(nc):
                    s += params[p0 + 2 + a * nc + b] * scratch[dc + nc + b]
                scratch[di + ni + a] = s
            scratch[di + 2 * ni] = h
    # flag the leaves that produced the point: every child of a sum, the chosen child of a hull
    active[0] = 1
    for i in range(nn):
        k = kind[i]
        if k < HULL:
            wit[wstart[i]] = active[i]
            continue
        for c in range(ccount[i]):
            ch = children[cstart[i] + c]
            active[ch] = active[i] if (k != HULL or ch == choice[i]) else 0
    for a in range(dim[0]):
        point[a] = scratch[dstart[0] + dim[0] + a]
    return scratch[dstart[0] + 2 * dim[0]]
