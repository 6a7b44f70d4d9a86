"""The one compiled support kernel.

A convex set compiles to a *support program*: a tree of nodes stored in pre-order (a parent before
its children) in flat arrays. `support` evaluates h_A(u) and s_A(u) of eq. (2) for any program in
four passes: directions flow down the tree (an affine node maps u to M^T u), support values flow
up (a hull keeps its best child, a sum adds), the leaves that produced the point are flagged in the
witness vector, and the support point is built up from the flagged nodes only. Every algorithm is
compiled once against this kernel, whatever the shape. Two program shapes take loops of their
own instead of the passes (their `plan`): the soft fingers' wrench sets, shot at on every
min_force call, and sums of posed 3-D bodies, growth distance's Delta.

A program is two arrays, `ints` and `floats`, so that a call from Python unboxes two arrays, not
twelve. `ints` = [nn, kind, dim, pstart, cstart, ccount, wstart, dstart, ostart, choice,
active, children, plan] (each block nn long but `children` and the one entry `plan`);
`floats` = [params, scratch]. The blocks:
    kind[i]      node kind (constants below)
    dim[i]       dimension of the node's output space
    pstart[i]    offset of the node's parameters in `params`
    cstart[i], ccount[i]   its children are children[cstart[i] : cstart[i] + ccount[i]]
    wstart[i]    leaves: offset of its witness slot [active, local...] in the witness vector
    dstart[i]    offset of its direction in `scratch`: its parent's, unless the parent is affine
                 (an embedding's child: the last entries of its parent's)
    ostart[i]    offset of its point and value in `scratch`
    choice[i], active[i]   work arrays: a hull's best child (an origin embedding's child, or -1
                 for its origin), whether node i produced the point
    plan         how `support` evaluates the program (GENERAL, ELLIPSOID_HULL or POSED_SUM
                 below, decided by `plan_of` when the set compiles)
"""
import numpy as np
from numba import njit

from ._jit import borrowing

POLYTOPE = 0   # params: m, n, vertices (m*n)            witness: [active, vertex index]
ELLIPSOID = 1  # params: n, k, center (n), shape (n*k)   witness: [active, x (k)]
BOX = 2        # params: n, half extents (n)             witness: [active, corner (n)]
TRUNCATED_CONE = 3  # params: bottom radius, top radius, height    witness: [active, point (3)]
CONE_CAP = 4   # params: n, mu                             witness: [active, g (n)]
HULL = 10
SUM = 11
AFFINE = 12    # params: m, n, M (m*n), t (m)
EMBED = 13     # params: m, n, span, t (m): x -> (0, x) + t, an affine map whose M is [0; I]
               # (k = m - n zero rows): its child reads the last n entries of its direction in
               # place; t is zero after its first `span` entries (the lift's t = (e_i - c, 0))
ORIGIN_EMBED = 14  # params as EMBED: the embedding of CH({0} U child), h = t^T u + max(0, h_c);
                   # witness: the origin's slot [active, 0] (sets._origin_hull)


# plans (the last entry of `ints`): the four passes for any program, or `_ellipsoid_hull`'s loop
# for a hull of ellipsoids in R^6 with 3 axes (soft fingers' W_i of eq. 14), each bare (W_L1) or
# under an embedding (W_Linf's lift, graspforce.wrench_space). Point contacts' ellipsoids (2 axes)
# keep the passes: the loop's rounding, which differs from theirs in the last bits, sent a shot at
# two point contacts on the edge of what they resist to max_iter (tests/test_grasp_forces.py,
# the edge-of-cone cases), where the passes' rounding lets the Newton finish close it
GENERAL = 0
ELLIPSOID_HULL = 1
# a sum in R^3 of leaves each under its own 3x3 affine map: Delta = R_A(A_0) - R_B(B_0) of growth
# distance (graspforce.growth), and any sum of posed bodies
POSED_SUM = 2

# the blocks of `ints` after nn, in order (`blocks` gives their offsets to compiled code)
BLOCKS = ("kind", "dim", "pstart", "cstart", "ccount", "wstart", "dstart", "ostart", "choice",
          "active", "children")


@njit(cache=True, inline='always')
def blocks(nn):
    """The offsets in `ints` of the blocks of BLOCKS, in that order, for a program of nn nodes
    (compiled code unpacks them into named constants)."""
    return (1, 1 + nn, 1 + 2 * nn, 1 + 3 * nn, 1 + 4 * nn, 1 + 5 * nn, 1 + 6 * nn, 1 + 7 * nn,
            1 + 8 * nn, 1 + 9 * nn, 1 + 10 * nn)


def _block(ints, name, node=0):
    return 1 + BLOCKS.index(name) * int(ints[0]) + node


def param_start(ints, node):
    """Offset of a node's parameters in `floats` (Python side, for callers that update them)."""
    return int(ints[_block(ints, "pstart", node)])


def params_size(ints):
    """Entries of `floats` that hold parameters (Python side); the scratch the kernel writes
    follows them."""
    return int(ints[_block(ints, "dstart")])


def plan_of(kind, dim, params, child_lists):
    """The plan of a program (module docstring) from its nodes' kinds, dimensions, parameter
    arrays and children (Python side, when the set compiles)."""
    if kind[0] == SUM and dim[0] == 3:
        for c in child_lists[0]:
            leaf = child_lists[c][0] if kind[c] == AFFINE else c
            if kind[c] != AFFINE or kind[leaf] >= HULL or dim[leaf] != 3:
                return GENERAL
        return POSED_SUM
    if kind[0] != HULL:
        return GENERAL
    for c in child_lists[0]:
        leaf = child_lists[c][0] if kind[c] in (EMBED, ORIGIN_EMBED) else c
        # an ellipsoid's parameters start [n, k]
        if kind[leaf] != ELLIPSOID or dim[leaf] != 6 or params[leaf][1] != 3:
            return GENERAL
    return ELLIPSOID_HULL


def children(ints, node):
    """The node indices of a node's children (Python side)."""
    start = _block(ints, "children", ints[_block(ints, "cstart", node)])
    return [int(c) for c in ints[start:start + ints[_block(ints, "ccount", node)]]]


@njit(cache=True, inline='always')
def _leaf_value(k, f, p, d, o, wit, w):
    """h of one leaf: parameters at f[p:], direction at f[d:d + dim]. Writes what the leaf's point
    needs to its witness slot wit[w + 1:] (a polytope's vertex index, an ellipsoid's S^T u); the
    cheap leaves write their point to f[o:o + dim] too. Offsets, not slices: a slice builds an
    array structure (and, in code that counts references, a round trip of its count), which
    dominates the arithmetic; inlined into `support` (10% of a hull of four ellipsoids)."""
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
        wit[w + 1] = arg
        return best
    if k == ELLIPSOID:
        n = int(f[p])
        kk = int(f[p + 1])
        if n == 6 and kk == 3:
            return _ellipsoid_6_3_value(f, p, d, wit, w)
        if n == 3 and kk == 3:
            return _ellipsoid_3_3_value(f, p, d, wit, w)
        return _ellipsoid_value(f, p, d, wit, w, n, kk)
    if k == BOX:
        n = int(f[p])
        h = 0.0
        for a in range(n):
            half = f[p + 1 + a]
            x = half if f[d + a] >= 0.0 else -half
            f[o + a] = x
            h += x * f[d + a]
            wit[w + 1 + a] = x
        return h
    if k == CONE_CAP:
        return _cone_cap_support(f, p, d, o, wit, w)
    h, x, y, z = _truncated_cone(f, p, w, wit, f[d], f[d + 1], f[d + 2])
    f[o] = x
    f[o + 1] = y
    f[o + 2] = z
    return h


@njit(cache=True, inline='always')
def _truncated_cone(f, p, w, wit, ux, uy, uz):
    """(h, x, y, z) of a truncated cone (the hull of two coaxial disks; parameters rb, rt,
    height at f[p:]) in direction u, its point written to its witness slot wit[w + 1:]."""
    rb = f[p]
    rt = f[p + 1]
    hz = 0.5 * f[p + 2]
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
    wit[w + 1] = x
    wit[w + 2] = y
    wit[w + 3] = z
    return h, x, y, z


def _ellipsoid_of(fixed_n, fixed_k):
    """(value, point) of an ellipsoid leaf {c + S x : ||x|| <= 1}, compiled for the given sizes
    or, when they are None, for any. value: h = c^T u + ||S^T u||, leaving S^T u in the witness
    slot; point: x = S^T u / ||S^T u|| (the pre-image on the unit ball) into the slot, c + S x."""
    @njit(cache=True, inline='always')
    def value(f, p, d, wit, w, n=fixed_n, kk=fixed_k):
        s0 = p + 2 + n
        nrm2 = 0.0
        for b in range(kk):
            y = 0.0
            for a in range(n):
                y += f[s0 + a * kk + b] * f[d + a]
            wit[w + 1 + b] = y
            nrm2 += y * y
        h = np.sqrt(nrm2)
        for a in range(n):
            h += f[p + 2 + a] * f[d + a]
        return h

    @njit(cache=True, inline='always')
    def point(f, p, o, wit, w, n=fixed_n, kk=fixed_k):
        s0 = p + 2 + n
        nrm2 = 0.0
        for b in range(kk):
            nrm2 += wit[w + 1 + b] * wit[w + 1 + b]
        inv = 1.0 / np.sqrt(nrm2) if nrm2 > 0.0 else 0.0
        for b in range(kk):
            wit[w + 1 + b] *= inv
        for a in range(n):
            s = f[p + 2 + a]
            for b in range(kk):
                s += f[s0 + a * kk + b] * wit[w + 1 + b]
            f[o + a] = s
    return value, point


# the contact wrench sets of eq. (14) and 3-D bodies: loops of known length unroll, which makes
# these about four times faster than the general loops
_ellipsoid_value, _ellipsoid_point = _ellipsoid_of(None, None)
_ellipsoid_6_3_value, _ellipsoid_6_3_point = _ellipsoid_of(6, 3)
_ellipsoid_3_3_value, _ellipsoid_3_3_point = _ellipsoid_of(3, 3)


def _affine_of(fixed_m, fixed_n):
    """(pull, push) of an affine node x -> M x + t, M (m, n) row-major at f[M0:], compiled for
    the given sizes or, when they are None, for any. pull: the child's direction M^T u from the
    node's; push: the node's point M x + t (t at f[M0 + m n:]) from the child's."""
    @njit(cache=True, inline='always')
    def pull(f, M0, du, dc, m=fixed_m, n=fixed_n):
        for b in range(n):
            s = 0.0
            for a in range(m):
                s += f[M0 + a * n + b] * f[du + a]
            f[dc + b] = s

    @njit(cache=True, inline='always')
    def push(f, M0, oc, oi, m=fixed_m, n=fixed_n):
        for a in range(m):
            s = f[M0 + m * n + a]
            for b in range(n):
                s += f[M0 + a * n + b] * f[oc + b]
            f[oi + a] = s
    return pull, push


# the poses of 3-D bodies (growth distance) unroll
_affine_pull, _affine_push = _affine_of(None, None)
_affine_3_3_pull, _affine_3_3_push = _affine_of(3, 3)
# the full-magnitude contact wrench sets G_i D U_i of soft fingers (eq. 15)
_affine_6_4_pull, _affine_6_4_push = _affine_of(6, 4)


@njit(cache=True, inline='always')
def _leaf_point(k, f, p, o, wit, w):
    """s of one leaf that produced the support point, from what `_leaf_value` left in its witness
    slot, to f[o:o + dim]. Only the leaves a hull chose get here, so a hull of m ellipsoids pays
    for one point, not m."""
    if k == POLYTOPE:
        n = int(f[p + 1])
        v0 = p + 2 + int(wit[w + 1]) * n
        for a in range(n):
            f[o + a] = f[v0 + a]
    elif k == ELLIPSOID:
        n = int(f[p])
        kk = int(f[p + 1])
        if n == 6 and kk == 3:
            _ellipsoid_6_3_point(f, p, o, wit, w)
        elif n == 3 and kk == 3:
            _ellipsoid_3_3_point(f, p, o, wit, w)
        else:
            _ellipsoid_point(f, p, o, wit, w, n, kk)


@njit(cache=True, inline='always')
def cap_direction(f, p, d):
    """(n, mu, y_1, ||y_perp||^2, ||y_perp||, ||y||) of a cone cap's direction y at f[d:] (its
    parameters n, mu at f[p:])."""
    n = int(f[p])
    y1 = f[d]
    q2 = 0.0
    for a in range(1, n):
        q2 += f[d + a] * f[d + a]
    return n, f[p + 1], y1, q2, np.sqrt(q2), np.sqrt(y1 * y1 + q2)


@borrowing
def _cone_cap_support(f, p, d, o, wit, w):
    """Support of the unit vectors g of the circular cone K = {||g_2:n|| <= mu g_1}.

    For y at angle phi from the axis e_1 and the cone's half-angle beta = atan(mu), the unit
    vector of K closest in angle to y is y/||y|| when phi <= beta, else the boundary ray
    b = (cos beta, sin beta y_perp/||y_perp||) in the plane of e_1 and y, so that
    h(y) = ||y|| cos(max(0, phi - beta)) = y_1 cos beta + ||y_perp|| sin beta outside K. This holds
    for every phi up to pi (the angle to K stays below pi), so the cap's support is negative for
    y in the polar cone. Where positive it equals ||Pi_K(y)||, the support of K cut by the unit
    ball (NOTES.md item 3).
    """
    n, mu, y1, q2, q, ny = cap_direction(f, p, d)
    if y1 >= 0.0 and q <= mu * y1:
        # y in K: the cap's point is y itself, normalized (e_1 for y = 0). The sign test is
        # not redundant: with mu = 0 and q = 0, q <= mu y1 holds for y1 < 0 too (0 <= -0.0)
        if ny > 0.0:
            for a in range(n):
                f[o + a] = f[d + a] / ny
        else:
            f[o] = 1.0
            for a in range(1, n):
                f[o + a] = 0.0
        h = ny
    else:
        cb = 1.0 / np.sqrt(1.0 + mu * mu)
        sb = mu * cb
        f[o] = cb
        if q > 0.0:
            for a in range(1, n):
                f[o + a] = sb * f[d + a] / q
        else:
            # y = -|y| e_1: every boundary ray is equally close; take the one along e_2
            for a in range(1, n):
                f[o + a] = 0.0
            if n > 1:
                f[o + 1] = sb
        h = y1 * cb + q * sb
    for a in range(n):
        wit[w + 1 + a] = f[o + a]
    return h


@borrowing
def _ellipsoid_hull(ints, f, u, point, wit):
    """`support` for the plan ELLIPSOID_HULL: every child of the root hull is an ellipsoid
    {c + S x : ||x|| <= 1} in R^6 with S (6, 3), bare or under an embedding (x -> (0, x) + t;
    an origin embedding's value is t^T u + max(0, h), the origin winning a tie). One loop over
    the children with the direction read from u and the best child's S^T u held in registers,
    then one point: the four passes' value, point and witnesses (the same flags and ties) at
    112 ns a call on the ingot's W_Linf lift against 189, 89 against 127 on its W_L1
    (benchmarks/support_plans.py; BENCHMARKS.md, "Stop 25"). The passes pay for what a general
    tree needs: each node's kind and offsets are read in every pass, and its direction, value
    and point go through the scratch part of `floats`."""
    nn = ints[0]
    KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN = \
        blocks(nn)
    n0 = ints[DIM]
    lead = n0 - 6               # an embedding's leading entries (the lift's contact coordinates)
    first = CHILDREN + ints[CSTART]
    best = -np.inf
    arg = ints[first]
    origin = False              # the best child is an origin embedding's origin
    bx0 = bx1 = bx2 = 0.0
    for c in range(ints[CCOUNT]):
        i = ints[first + c]
        k = ints[KIND + i]
        leaf = i if k < HULL else ints[CHILDREN + ints[CSTART + i]]
        p = ints[PSTART + leaf] + 2         # c (6), then S (6, 3) row-major
        cu = x0 = x1 = x2 = 0.0
        for a in range(6):
            ua = u[lead + a]
            cu += f[p + a] * ua
            x0 += f[p + 6 + 3 * a] * ua
            x1 += f[p + 7 + 3 * a] * ua
            x2 += f[p + 8 + 3 * a] * ua
        w = ints[WSTART + leaf]
        wit[w] = 0.0
        wit[w + 1] = x0
        wit[w + 2] = x1
        wit[w + 3] = x2
        # c^T u apart: the sum waits on the square root once, not six times
        h = cu + np.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
        at_origin = False
        if k >= HULL:
            p0 = ints[PSTART + i]
            tu = 0.0
            for a in range(int(f[p0 + 2])):
                tu += f[p0 + 3 + a] * u[a]
            if k == ORIGIN_EMBED:
                wo = ints[WSTART + i]
                wit[wo] = 0.0
                wit[wo + 1] = 0.0
                if not h > 0.0:
                    h = 0.0
                    at_origin = True
            h += tu
        if h > best:
            best = h
            arg = i
            origin = at_origin
            bx0 = x0
            bx1 = x1
            bx2 = x2
    k = ints[KIND + arg]
    if k >= HULL:
        t0 = ints[PSTART + arg] + 3
        for a in range(n0):
            point[a] = f[t0 + a]
    else:
        for a in range(n0):
            point[a] = 0.0
    if origin:
        wit[ints[WSTART + arg]] = 1.0
        return best
    nrm2 = bx0 * bx0 + bx1 * bx1 + bx2 * bx2
    inv = 1.0 / np.sqrt(nrm2) if nrm2 > 0.0 else 0.0
    bx0 *= inv
    bx1 *= inv
    bx2 *= inv
    leaf = arg if k < HULL else ints[CHILDREN + ints[CSTART + arg]]
    w = ints[WSTART + leaf]
    wit[w] = 1.0
    wit[w + 1] = bx0
    wit[w + 2] = bx1
    wit[w + 3] = bx2
    p = ints[PSTART + leaf] + 2
    for a in range(6):
        point[lead + a] += (f[p + a] + f[p + 6 + 3 * a] * bx0 + f[p + 7 + 3 * a] * bx1
                            + f[p + 8 + 3 * a] * bx2)
    return best


@borrowing
def _posed_sum(ints, f, u, point, wit):
    """`support` for the plan POSED_SUM: the root sums children x -> M x + t in R^3, each over a
    leaf (`plan_of` checked that every leaf is 3-D). One loop over the children with the
    direction M^T u and the leaf's point in registers (timings: benchmarks/support_plans.py;
    BENCHMARKS.md, "Stop 26"). Ellipsoids with 3 axes and truncated cones are evaluated in
    registers; other leaves (boxes, polytopes) take the passes' leaf code through the scratch
    part of `floats` (the protocol's Delta written that way for every leaf: 65 ns against 39 in
    one harness). The ellipsoid's arithmetic is `_ellipsoid_3_3_value` and `_point` fused,
    because every leaf of a sum is active: the passes split them so that a hull pays for its
    chosen child's point only."""
    nn = ints[0]
    KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN = \
        blocks(nn)
    u0 = u[0]
    u1 = u[1]
    u2 = u[2]
    first = CHILDREN + ints[CSTART]
    h = 0.0
    p0 = p1 = p2 = 0.0
    for c in range(ints[CCOUNT]):
        i = ints[first + c]
        M = ints[PSTART + i] + 2            # M (3, 3) row-major, then t
        v0 = f[M] * u0 + f[M + 3] * u1 + f[M + 6] * u2
        v1 = f[M + 1] * u0 + f[M + 4] * u1 + f[M + 7] * u2
        v2 = f[M + 2] * u0 + f[M + 5] * u1 + f[M + 8] * u2
        leaf = ints[CHILDREN + ints[CSTART + i]]
        k = ints[KIND + leaf]
        p = ints[PSTART + leaf]
        w = ints[WSTART + leaf]
        wit[w] = 1.0
        if k == ELLIPSOID and f[p + 1] == 3.0:
            s = p + 5                       # n, k, c (3), then S (3, 3) row-major
            y0 = f[s] * v0 + f[s + 3] * v1 + f[s + 6] * v2
            y1 = f[s + 1] * v0 + f[s + 4] * v1 + f[s + 7] * v2
            y2 = f[s + 2] * v0 + f[s + 5] * v1 + f[s + 8] * v2
            nrm = np.sqrt(y0 * y0 + y1 * y1 + y2 * y2)
            hl = f[p + 2] * v0 + f[p + 3] * v1 + f[p + 4] * v2 + nrm
            inv = 1.0 / nrm if nrm > 0.0 else 0.0
            y0 *= inv
            y1 *= inv
            y2 *= inv
            wit[w + 1] = y0
            wit[w + 2] = y1
            wit[w + 3] = y2
            x = f[p + 2] + f[s] * y0 + f[s + 1] * y1 + f[s + 2] * y2
            y = f[p + 3] + f[s + 3] * y0 + f[s + 4] * y1 + f[s + 5] * y2
            z = f[p + 4] + f[s + 6] * y0 + f[s + 7] * y1 + f[s + 8] * y2
        elif k == TRUNCATED_CONE:
            hl, x, y, z = _truncated_cone(f, p, w, wit, v0, v1, v2)
        else:
            d = ints[DSTART + leaf]
            o = ints[OSTART + leaf]
            f[d] = v0
            f[d + 1] = v1
            f[d + 2] = v2
            hl = _leaf_value(k, f, p, d, o, wit, w)
            _leaf_point(k, f, p, o, wit, w)
            x = f[o]
            y = f[o + 1]
            z = f[o + 2]
        t = M + 9
        h += hl + f[t] * u0 + f[t + 1] * u1 + f[t + 2] * u2
        p0 += f[t] + f[M] * x + f[M + 1] * y + f[M + 2] * z
        p1 += f[t + 1] + f[M + 3] * x + f[M + 4] * y + f[M + 5] * z
        p2 += f[t + 2] + f[M + 6] * x + f[M + 7] * y + f[M + 8] * z
    point[0] = p0
    point[1] = p1
    point[2] = p2
    return h


@borrowing
def support(ints, f, u, point, wit):
    """h_A(u) (returned) and s_A(u) (into `point`) of eq. (2); the witness goes into `wit`.

    The blocks of `ints` are those of BLOCKS, at the offsets `blocks(nn)`. Node i reads its
    direction at f[dstart:], writes its point to f[ostart:ostart + dim] and its value to
    f[ostart + dim].
    """
    plan = ints[ints.shape[0] - 1]
    if plan == ELLIPSOID_HULL:
        return _ellipsoid_hull(ints, f, u, point, wit)
    if plan == POSED_SUM:
        return _posed_sum(ints, f, u, point, wit)
    nn = ints[0]
    KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN = \
        blocks(nn)
    d0 = ints[DSTART]
    n0 = ints[DIM]
    for a in range(n0):
        f[d0 + a] = u[a]
    # directions flow down; the children of a hull or a sum read their parent's
    for i in range(nn):
        if ints[KIND + i] != AFFINE:
            continue
        di = ints[DSTART + i]
        ni = ints[DIM + i]
        ch = ints[CHILDREN + ints[CSTART + i]]
        dc = ints[DSTART + ch]
        p0 = ints[PSTART + i]
        nc = ints[DIM + ch]
        if ni == 3 and nc == 3:
            _affine_3_3_pull(f, p0 + 2, di, dc)
        elif ni == 6 and nc == 4:
            _affine_6_4_pull(f, p0 + 2, di, dc)
        else:
            _affine_pull(f, p0 + 2, di, dc, ni, nc)
    # values flow up: h of every node; a hull keeps its best child
    for i in range(nn - 1, -1, -1):
        k = ints[KIND + i]
        oi = ints[OSTART + i]
        ni = ints[DIM + i]
        if k < HULL:
            h = _leaf_value(k, f, ints[PSTART + i], ints[DSTART + i], oi, wit, ints[WSTART + i])
        elif k == HULL:
            h = -np.inf
            arg = ints[CHILDREN + ints[CSTART + i]]
            for c in range(ints[CCOUNT + i]):
                ch = ints[CHILDREN + ints[CSTART + i] + c]
                hc = f[ints[OSTART + ch] + ni]
                if hc > h:
                    h = hc
                    arg = ch
            ints[CHOICE + i] = arg
        elif k == SUM:
            h = 0.0
            for c in range(ints[CCOUNT + i]):
                h += f[ints[OSTART + ints[CHILDREN + ints[CSTART + i] + c]] + ni]
        else:
            # h_{MA + t}(u) = h_A(M^T u) + t^T u; an embedding's t follows its span, no M
            ch = ints[CHILDREN + ints[CSTART + i]]
            nc = ints[DIM + ch]
            p0 = ints[PSTART + i]
            if k == AFFINE:
                t0 = p0 + 2 + ni * nc
                span = ni
            else:
                t0 = p0 + 3
                span = int(f[p0 + 2])
            di = ints[DSTART + i]
            h = f[ints[OSTART + ch] + nc]
            if k == ORIGIN_EMBED:
                # the origin wins a tie, as the first child of the hull it stands for
                if h > 0.0:
                    ints[CHOICE + i] = ch
                else:
                    h = 0.0
                    ints[CHOICE + i] = -1
            for a in range(span):
                h += f[t0 + a] * f[di + a]
        f[oi + ni] = h
    # flag the leaves that produced the point: every child of a sum, the chosen child of a hull
    ints[ACTIVE] = 1
    for i in range(nn):
        k = ints[KIND + i]
        if k < HULL:
            wit[ints[WSTART + i]] = ints[ACTIVE + i]
            continue
        if k == ORIGIN_EMBED:
            origin = ints[ACTIVE + i] if ints[CHOICE + i] < 0 else 0
            w = ints[WSTART + i]
            wit[w] = origin
            wit[w + 1] = 0.0
            ints[ACTIVE + ints[CHILDREN + ints[CSTART + i]]] = ints[ACTIVE + i] - origin
            continue
        for c in range(ints[CCOUNT + i]):
            ch = ints[CHILDREN + ints[CSTART + i] + c]
            ints[ACTIVE + ch] = ints[ACTIVE + i] if (k != HULL or ch == ints[CHOICE + i]) else 0
    # points flow up through the flagged nodes only
    for i in range(nn - 1, -1, -1):
        if ints[ACTIVE + i] == 0:
            continue
        k = ints[KIND + i]
        oi = ints[OSTART + i]
        ni = ints[DIM + i]
        if k < HULL:
            _leaf_point(k, f, ints[PSTART + i], oi, wit, ints[WSTART + i])
        elif k == HULL:
            src = ints[OSTART + ints[CHOICE + i]]
            for a in range(ni):
                f[oi + a] = f[src + a]
        elif k == SUM:
            for a in range(ni):
                f[oi + a] = 0.0
            for c in range(ints[CCOUNT + i]):
                oc = ints[OSTART + ints[CHILDREN + ints[CSTART + i] + c]]
                for a in range(ni):
                    f[oi + a] += f[oc + a]
        else:
            ch = ints[CHILDREN + ints[CSTART + i]]
            oc = ints[OSTART + ch]
            nc = ints[DIM + ch]
            p0 = ints[PSTART + i]
            if k == EMBED or k == ORIGIN_EMBED:
                lead = ni - nc
                for a in range(lead):
                    f[oi + a] = f[p0 + 3 + a]
                if ints[CHOICE + i] < 0 and k == ORIGIN_EMBED:
                    for a in range(nc):
                        f[oi + lead + a] = f[p0 + 3 + lead + a]
                else:
                    for a in range(nc):
                        f[oi + lead + a] = f[oc + a] + f[p0 + 3 + lead + a]
            elif ni == 3 and nc == 3:
                _affine_3_3_push(f, p0 + 2, oc, oi)
            elif ni == 6 and nc == 4:
                _affine_6_4_push(f, p0 + 2, oc, oi)
            else:
                _affine_push(f, p0 + 2, oc, oi, ni, nc)
    o0 = ints[OSTART]
    for a in range(n0):
        point[a] = f[o0 + a]
    return f[o0 + n0]
