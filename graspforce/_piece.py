"""The support of one smooth piece of a set, with its curvature: what a second-order finish needs.

A support point's witness names the *piece* of A that produced it: the leaves it flags (the
chosen child of every hull, every summand of a sum) and, inside a leaf, the part whose support is
smooth (a polytope's or a box's vertex, a truncated cone's top or bottom disk; an ellipsoid or a
cone cap is one piece). On a piece P the support map is differentiable:

    h_P(u) = max over P of u^T a,   s_P(u) = grad h_P(u),   J_P(u) = ds_P/du = Hess h_P(u)

(eq. 2 restricted to P). J is symmetric positive semidefinite with J u = 0 (h is 1-homogeneous),
zero on a vertex, (S S^T - (s - c)(s - c)^T) / ||S^T u|| on an ellipsoid {c + S x : ||x|| <= 1},
and it transforms as M J M^T through an affine node, adds through a sum, passes through a hull.

A leaf of a piece may also be *flat*: where S^T u = 0 an ellipsoid's (or a disk's) whole body is
its face, and the face of A then holds an interior point c + S x of it, x free (a soft finger whose
friction is not saturated, an ellipsoid resting on a cone's base). A pattern marks such a leaf
with the flag FLAT instead of 1 and its local point x in the witness slot; the leaf then adds the
fixed point c + S x and no curvature, and `flat_columns` gives the columns L S (L the linear part
of the affine maps above the leaf) along which x moves the piece's point.

`piece_support` evaluates h_P, s_P, J_P and the witness of s_P; at a kink of a smooth leaf (the
direction where it is not smooth: S^T u = 0) it returns NaN and flags that leaf KINK in the
witness. Adding a leaf kind means adding its piece here, beside its support in `_kernel`.
"""
import numpy as np
from numba import njit

from ._jit import borrowing
from ._kernel import (AFFINE, BOX, CONE_CAP, ELLIPSOID, EMBED, HULL, ORIGIN_EMBED, POLYTOPE, SUM,
                      _affine_pull, _cone_cap_support, blocks, cap_direction)

KINK_TOL = 1e-9   # ||S^T u|| <= KINK_TOL ||S|| ||u||: the piece's support is not smooth there
FLAT = 2.0        # witness flag of a flat leaf (module docstring)
KINK = -1.0       # witness flag piece_support leaves on the smooth leaf whose kink it met
TRUNCATED_CONE = 3


@borrowing
def jacobian_size(ints, f):
    """(entries of the work array `piece_support` keeps one Jacobian per node in, and a product
    in, the largest dimension of a node, the largest local point of a leaf that can be flat)."""
    nn = ints[0]
    KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN = \
        blocks(nn)
    nmax = 0
    qmax = 2
    for i in range(nn):
        nmax = max(nmax, ints[DIM + i])
        if ints[KIND + i] == ELLIPSOID:
            qmax = max(qmax, int(f[ints[PSTART + i] + 1]))
    return (nn + 1) * nmax * nmax, nmax, qmax


@borrowing
def same_piece(ints, wa, wb):
    """Whether two witnesses name the same smooth piece (see the module docstring)."""
    nn = ints[0]
    KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN = \
        blocks(nn)
    for i in range(nn):
        k = ints[KIND + i]
        if k == ORIGIN_EMBED:
            w = ints[WSTART + i]
            if (wa[w] != 0.0) != (wb[w] != 0.0):
                return False
            continue
        if k >= HULL:
            continue
        w = ints[WSTART + i]
        if (wa[w] != 0.0) != (wb[w] != 0.0):
            return False
        if wa[w] == 0.0:
            continue
        if k == POLYTOPE:
            if wa[w + 1] != wb[w + 1]:
                return False
        elif k == BOX:
            for a in range(ints[DIM + i]):
                if wa[w + 1 + a] != wb[w + 1 + a]:
                    return False
        elif k == TRUNCATED_CONE:   # the disk, by the sign of the point's z
            if (wa[w + 3] > 0.0) != (wb[w + 3] > 0.0):
                return False
    return True


def _ellipsoid_piece_of(fixed_n, fixed_k):
    """The piece of an ellipsoid leaf {c + S x : ||x|| <= 1}, compiled for the given sizes or,
    when they are None, for any (as `_kernel._ellipsoid_of`: loops of known length unroll)."""
    @njit(cache=True, inline='always')
    def piece(f, p, d, o, wit, w, J, j0, n=fixed_n, kk=fixed_k):
        s0 = p + 2 + n
        rho2 = 0.0
        ss = 0.0
        uu = 0.0
        for a in range(n):
            uu += f[d + a] * f[d + a]
        for b in range(kk):
            y = 0.0
            for a in range(n):
                sab = f[s0 + a * kk + b]
                y += sab * f[d + a]
                ss += sab * sab
            wit[w + 1 + b] = y
            rho2 += y * y
        if rho2 <= KINK_TOL * KINK_TOL * ss * uu:
            return np.nan
        rho = np.sqrt(rho2)
        inv = 1.0 / rho
        for b in range(kk):
            wit[w + 1 + b] *= inv
        h = rho
        for a in range(n):
            sx = 0.0
            for b in range(kk):
                sx += f[s0 + a * kk + b] * wit[w + 1 + b]
            f[o + a] = f[p + 2 + a] + sx
            h += f[p + 2 + a] * f[d + a]
        # J = (S S^T - (S x)(S x)^T) / rho, S x = s - c
        for a in range(n):
            sxa = f[o + a] - f[p + 2 + a]
            for a2 in range(n):
                v = -sxa * (f[o + a2] - f[p + 2 + a2])
                for b in range(kk):
                    v += f[s0 + a * kk + b] * f[s0 + a2 * kk + b]
                J[j0 + a * n + a2] = v * inv
        return h
    return piece


# the contact wrench sets of eq. (14) and 3-D bodies, as in _kernel
_ellipsoid_piece = _ellipsoid_piece_of(None, None)
_ellipsoid_6_3_piece = _ellipsoid_piece_of(6, 3)
_ellipsoid_3_3_piece = _ellipsoid_piece_of(3, 3)


@njit(cache=True, inline='always')
def _disk_point(f, o, wit, w, x, y, z):
    """A truncated cone's point (x, y, z) in its frame, to f[o:o + 3] and its witness slot (as
    `_kernel`'s truncated cone writes it, spelled out there: a call inlined into the kernel's
    leaf code slowed every support call by ~5%, benchmarks/ab.py)."""
    f[o] = x
    f[o + 1] = y
    f[o + 2] = z
    wit[w + 1] = x
    wit[w + 2] = y
    wit[w + 3] = z


@njit(cache=True, inline='always')
def _disk_piece(f, p, d, o, wit, w, J, j0, top):
    """The top (or bottom) disk of a truncated cone: s = (R u_xy / ||u_xy||, +-height/2)."""
    rad = f[p + 1] if top else f[p]
    z = 0.5 * f[p + 2] if top else -0.5 * f[p + 2]
    ux = f[d]
    uy = f[d + 1]
    uz = f[d + 2]
    q = np.sqrt(ux * ux + uy * uy)
    for a in range(9):
        J[j0 + a] = 0.0
    if rad > 0.0:
        if q <= KINK_TOL * np.sqrt(q * q + uz * uz):
            return np.nan
        px = ux / q
        py = uy / q
        c = rad / q
        J[j0] = c * (1.0 - px * px)
        J[j0 + 1] = -c * px * py
        J[j0 + 3] = -c * px * py
        J[j0 + 4] = c * (1.0 - py * py)
        _disk_point(f, o, wit, w, rad * px, rad * py, z)
    else:
        _disk_point(f, o, wit, w, 0.0, 0.0, z)
    return rad * q + z * uz


@njit(cache=True, inline='always')
def _cap_piece(f, p, d, o, wit, w, J, j0):
    """Cone cap: its point from the kernel (`_kernel._cone_cap_support`), its curvature here. C^1
    across the cone's boundary, so one piece; J is that of the side the direction lies on:
    (I - s s^T) / ||y|| inside K (s = y / ||y||), sin(beta) (I - e e^T) / ||y_perp|| on the
    components 2..n outside (e = y_perp / ||y_perp||, the rim's circle)."""
    h = _cone_cap_support(f, p, d, o, wit, w)
    n, mu, y1, q2, q, ny = cap_direction(f, p, d)
    for a in range(n * n):
        J[j0 + a] = 0.0
    if y1 >= 0.0 and q <= mu * y1:
        if ny == 0.0:
            return np.nan
        for a in range(n):
            for b in range(n):
                J[j0 + a * n + b] = ((1.0 if a == b else 0.0) - f[o + a] * f[o + b]) / ny
    else:
        if q <= KINK_TOL * ny:
            return np.nan
        sb = mu / np.sqrt(1.0 + mu * mu)
        for a in range(1, n):
            for b in range(1, n):
                J[j0 + a * n + b] = sb * ((1.0 if a == b else 0.0)
                                          - f[d + a] * f[d + b] / q2) / q
    return h


@njit(cache=True, inline='always')
def local_size(k, f, p):
    """Entries of a flat leaf's local point: an ellipsoid's x (k), a disk's (x, y)."""
    return int(f[p + 1]) if k == ELLIPSOID else 2


@njit(cache=True, inline='always')
def _flat_point(k, f, p, d, o, pw, w, n):
    """A flat leaf's point c + S x (x at pw[w + 1:]) to f[o:], its value u^T (c + S x) returned.
    A disk's x is the point's (x, y) in the cone's frame, on the top disk if pw[w + 3] > 0."""
    if k == ELLIPSOID:
        kk = int(f[p + 1])
        s0 = p + 2 + n
        for a in range(n):
            s = f[p + 2 + a]
            for b in range(kk):
                s += f[s0 + a * kk + b] * pw[w + 1 + b]
            f[o + a] = s
    else:
        f[o] = pw[w + 1]
        f[o + 1] = pw[w + 2]
        f[o + 2] = 0.5 * f[p + 2] if pw[w + 3] > 0.0 else -0.5 * f[p + 2]
    h = 0.0
    for a in range(n):
        h += f[o + a] * f[d + a]
    return h


@borrowing
def flat_radius2(ints, f, leaf, pw):
    """||x||^2 / (its bound)^2 of a flat leaf's local point: <= 1 when the point is in the leaf."""
    nn = ints[0]
    KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN = \
        blocks(nn)
    p = ints[PSTART + leaf]
    w = ints[WSTART + leaf]
    if ints[KIND + leaf] == ELLIPSOID:
        s = 0.0
        for b in range(int(f[p + 1])):
            s += pw[w + 1 + b] * pw[w + 1 + b]
        return s
    rad = f[p + 1] if pw[w + 3] > 0.0 else f[p]
    s = pw[w + 1] * pw[w + 1] + pw[w + 2] * pw[w + 2]
    return s / (rad * rad) if rad > 0.0 else (0.0 if s == 0.0 else np.inf)


@borrowing
def flat_columns(ints, f, leaf, T, off, C, C2):
    """T[:, off:off + q] = L S for a flat leaf (module docstring); returns q, or -1 when T has
    not q columns left. C, C2: (nmax, qmax) work (`jacobian_size`)."""
    nn = ints[0]
    KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN = \
        blocks(nn)
    k = ints[KIND + leaf]
    p = ints[PSTART + leaf]
    nl = ints[DIM + leaf]
    q = local_size(k, f, p)
    if off + q > T.shape[1]:
        return -1
    for a in range(nl):
        for b in range(q):
            if k == ELLIPSOID:
                C[a, b] = f[p + 2 + nl + a * q + b]
            else:
                C[a, b] = 1.0 if a == b else 0.0
    node = leaf
    rows = nl
    while node != 0:
        parent = 0
        for i in range(nn):
            if ints[KIND + i] >= HULL:
                c0 = CHILDREN + ints[CSTART + i]
                for c in range(ints[CCOUNT + i]):
                    if ints[c0 + c] == node:
                        parent = i
        if ints[KIND + parent] == AFFINE:
            m = ints[DIM + parent]
            M0 = ints[PSTART + parent] + 2
            for a in range(m):
                for b in range(q):
                    s = 0.0
                    for c in range(rows):
                        s += f[M0 + a * rows + c] * C[c, b]
                    C2[a, b] = s
            for a in range(m):
                for b in range(q):
                    C[a, b] = C2[a, b]
            rows = m
        elif ints[KIND + parent] == EMBED or ints[KIND + parent] == ORIGIN_EMBED:
            # x -> (0, x) + t: L gains the embedding's leading zero rows
            m = ints[DIM + parent]
            lead = m - rows
            for a in range(m - 1, -1, -1):
                for b in range(q):
                    C[a, b] = C[a - lead, b] if a >= lead else 0.0
            rows = m
        node = parent
    for a in range(rows):
        for b in range(q):
            T[a, off + b] = C[a, b]
    return q


def _affine_jacobian_of(fixed_m, fixed_n):
    """J = M J_c M^T through an affine node (M (m, n) row-major at f[M0:]; J_c at jw[jc:], J to
    jw[j0:], jw[tmp:] holds J_c M^T), compiled for the given sizes or, when None, for any."""
    @njit(cache=True, inline='always')
    def jacobian(f, M0, jw, jc, j0, tmp, m=fixed_m, n=fixed_n):
        for b in range(n):
            for a in range(m):
                s = 0.0
                for c in range(n):
                    s += jw[jc + b * n + c] * f[M0 + a * n + c]
                jw[tmp + b * m + a] = s
        for a in range(m):
            for a2 in range(m):
                s = 0.0
                for b in range(n):
                    s += f[M0 + a * n + b] * jw[tmp + b * m + a2]
                jw[j0 + a * m + a2] = s
    return jacobian


# the poses of 3-D bodies unroll, as in _kernel
_affine_jacobian = _affine_jacobian_of(None, None)
_affine_3_3_jacobian = _affine_jacobian_of(3, 3)


@borrowing
def piece_support(ints, f, u, pw, point, wit, J, jw, nmax):
    """h_P(u) (returned; NaN at a kink of the piece), s_P(u) into `point`, its witness into
    `wit` and J_P(u) = ds_P/du into J (n, n), for the piece P named by the witness `pw`.
    jw: work of `jacobian_size(ints, f)[0]` entries. Uses the program's scratch like `support`."""
    nn = ints[0]
    KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN = \
        blocks(nn)
    nsq = nmax * nmax
    # the nodes of the piece: the leaves its witness flags and their ancestors
    for i in range(nn - 1, -1, -1):
        k = ints[KIND + i]
        if k < HULL:
            ints[ACTIVE + i] = 1 if pw[ints[WSTART + i]] != 0.0 else 0
            continue
        act = 0
        for c in range(ints[CCOUNT + i]):
            ch = ints[CHILDREN + ints[CSTART + i] + c]
            if ints[ACTIVE + ch] != 0:
                act = 1
                ints[CHOICE + i] = ch
        if k == ORIGIN_EMBED and pw[ints[WSTART + i]] != 0.0:
            act = 1
            ints[CHOICE + i] = -1
        ints[ACTIVE + i] = act
    for i in range(nn):
        k = ints[KIND + i]
        if k < HULL:
            wit[ints[WSTART + i]] = ints[ACTIVE + i]
        elif k == ORIGIN_EMBED:
            w = ints[WSTART + i]
            wit[w] = 1.0 if ints[ACTIVE + i] != 0 and ints[CHOICE + i] < 0 else 0.0
            wit[w + 1] = 0.0
    n0 = ints[DIM]
    d0 = ints[DSTART]
    for a in range(n0):
        f[d0 + a] = u[a]
    for i in range(nn):
        if ints[KIND + i] == AFFINE and ints[ACTIVE + i] != 0:
            ch = ints[CHILDREN + ints[CSTART + i]]
            _affine_pull(f, ints[PSTART + i] + 2, ints[DSTART + i], ints[DSTART + ch],
                         ints[DIM + i], ints[DIM + ch])
    for i in range(nn - 1, -1, -1):
        if ints[ACTIVE + i] == 0:
            continue
        k = ints[KIND + i]
        oi = ints[OSTART + i]
        ni = ints[DIM + i]
        p = ints[PSTART + i]
        di = ints[DSTART + i]
        j0 = i * nsq
        if k < HULL:
            w = ints[WSTART + i]
            if pw[w] == FLAT:
                h = _flat_point(k, f, p, di, oi, pw, w, ni)
                for a in range(ni * ni):
                    jw[j0 + a] = 0.0
                for a in range(1, local_size(k, f, p) + 1):
                    wit[w + a] = pw[w + a]
                if k == TRUNCATED_CONE:
                    wit[w + 3] = f[oi + 2]
            elif k == ELLIPSOID:
                ne = int(f[p])
                ke = int(f[p + 1])
                if ne == 6 and ke == 3:
                    h = _ellipsoid_6_3_piece(f, p, di, oi, wit, w, jw, j0)
                elif ne == 3 and ke == 3:
                    h = _ellipsoid_3_3_piece(f, p, di, oi, wit, w, jw, j0)
                else:
                    h = _ellipsoid_piece(f, p, di, oi, wit, w, jw, j0, ne, ke)
            elif k == POLYTOPE or k == BOX:
                h = 0.0
                for a in range(ni):
                    x = f[p + 2 + int(pw[w + 1]) * ni + a] if k == POLYTOPE else pw[w + 1 + a]
                    f[oi + a] = x
                    h += x * f[di + a]
                    if k == BOX:
                        wit[w + 1 + a] = x
                if k == POLYTOPE:
                    wit[w + 1] = pw[w + 1]
                for a in range(ni * ni):
                    jw[j0 + a] = 0.0
            elif k == CONE_CAP:
                h = _cap_piece(f, p, di, oi, wit, w, jw, j0)
            else:
                h = _disk_piece(f, p, di, oi, wit, w, jw, j0, pw[w + 3] > 0.0)
            if h != h:
                wit[w] = KINK
                return np.nan
        elif k == HULL:
            ch = ints[CHOICE + i]
            oc = ints[OSTART + ch]
            for a in range(ni + 1):
                f[oi + a] = f[oc + a]
            for a in range(ni * ni):
                jw[j0 + a] = jw[ch * nsq + a]
            h = f[oi + ni]
        elif k == SUM:
            h = 0.0
            for a in range(ni):
                f[oi + a] = 0.0
            for a in range(ni * ni):
                jw[j0 + a] = 0.0
            for c in range(ints[CCOUNT + i]):
                ch = ints[CHILDREN + ints[CSTART + i] + c]
                oc = ints[OSTART + ch]
                h += f[oc + ni]
                for a in range(ni):
                    f[oi + a] += f[oc + a]
                for a in range(ni * ni):
                    jw[j0 + a] += jw[ch * nsq + a]
        elif k == EMBED or k == ORIGIN_EMBED:
            # x -> (0, x) + t: s = (0, s_c) + t, h = h_c + t^T u, J = [[0, 0], [0, J_c]]; an
            # origin embedding's origin: s = t, h = t^T u, J = 0
            ch = ints[CHILDREN + ints[CSTART + i]]
            oc = ints[OSTART + ch]
            nc = ints[DIM + ch]
            lead = ni - nc
            child = k == EMBED or ints[CHOICE + i] >= 0
            h = f[oc + nc] if child else 0.0
            for a in range(ni):
                f[oi + a] = f[p + 3 + a] + (f[oc + a - lead] if a >= lead and child else 0.0)
                h += f[p + 3 + a] * f[di + a]
            for a in range(ni):
                for a2 in range(ni):
                    jw[j0 + a * ni + a2] = (jw[ch * nsq + (a - lead) * nc + a2 - lead]
                                            if a >= lead and a2 >= lead and child else 0.0)
        else:
            # x -> M x + t: s = M s_c + t, h = h_c + t^T u, J = M J_c M^T
            ch = ints[CHILDREN + ints[CSTART + i]]
            oc = ints[OSTART + ch]
            nc = ints[DIM + ch]
            M0 = p + 2
            t0 = M0 + ni * nc
            h = f[oc + nc]
            for a in range(ni):
                s = f[t0 + a]
                for b in range(nc):
                    s += f[M0 + a * nc + b] * f[oc + b]
                f[oi + a] = s
                h += f[t0 + a] * f[di + a]
            if ni == 3 and nc == 3:
                _affine_3_3_jacobian(f, M0, jw, ch * nsq, j0, nn * nsq)
            else:
                _affine_jacobian(f, M0, jw, ch * nsq, j0, nn * nsq, ni, nc)
        f[oi + ni] = h
    o0 = ints[OSTART]
    for a in range(n0):
        point[a] = f[o0 + a]
        for b in range(n0):
            J[a, b] = jw[a * n0 + b]
    return f[o0 + n0]
