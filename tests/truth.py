"""Independent reference solvers for the graspforce test suite.

Nothing here imports graspforce. A convex set is described by a small tree of plain tuples
(a *description*), from which the tests build the graspforce object (conftest.build) and from
which this module computes the truth with generic solvers (scipy's HiGHS LP, scipy's NNLS,
Clarabel's conic interior point method) or closed forms:

    ("poly", V)                      CH of the rows of V (m, n)
    ("ell", c, S)                    {c + S x : ||x|| <= 1}, S (n, k) of any rank
    ("box", half, center, R)         {center + R x : |x_i| <= half_i}
    ("tcone", rb, rt, h)             3-D truncated cone, axis +z, bottom disk (radius rb) at -h/2
    ("capsule", radius, length)      3-D segment [-L/2, L/2] e_z swept by a ball
    ("hull", [children])             convex hull of the union
    ("sum", [children])              Minkowski sum
    ("affine", M, t, child)          {M a + t : a in child}

Leaves (for witnesses) are poly, ell, box and tcone, numbered depth-first.
"""
import numpy as np
import scipy.optimize
import scipy.sparse as sp

import clarabel

from benchmarks.grasp_sets import cone_outside

LEAF_KINDS = ("poly", "ell", "box", "tcone")


# ----------------------------------------------------------------------------------------------
# descriptions: helpers
# ----------------------------------------------------------------------------------------------
def poly(V):
    return ("poly", np.asarray(V, dtype=float))


def ell(c, S):
    c = np.asarray(c, dtype=float)
    S = np.asarray(S, dtype=float)
    if S.ndim == 1:
        S = S[:, None]
    return ("ell", c, S)


def ball(c, radius):
    c = np.asarray(c, dtype=float)
    return ("ell", c, radius * np.eye(c.size))


def box(half, center=None, R=None):
    half = np.asarray(half, dtype=float)
    n = half.size
    center = np.zeros(n) if center is None else np.asarray(center, dtype=float)
    R = np.eye(n) if R is None else np.asarray(R, dtype=float)
    return ("box", half, center, R)


def tcone(rb, rt, h):
    return ("tcone", float(rb), float(rt), float(h))


def capsule(radius, length):
    return ("capsule", float(radius), float(length))


def hull(*children):
    return ("hull", list(children))


def msum(*children):
    return ("sum", list(children))


def affine(M, child, t=None):
    M = np.asarray(M, dtype=float)
    t = np.zeros(M.shape[0]) if t is None else np.asarray(t, dtype=float)
    return ("affine", M, t, child)


def neg(child):
    n = dim(child)
    return ("affine", -np.eye(n), np.zeros(n), child)


def dim(d):
    k = d[0]
    if k == "poly":
        return d[1].shape[1]
    if k == "ell":
        return d[1].size
    if k == "box":
        return d[1].size
    if k in ("tcone", "capsule"):
        return 3
    if k in ("hull", "sum"):
        return dim(d[1][0])
    if k == "affine":
        return d[1].shape[0]
    raise ValueError(k)


def leaves(d):
    """Leaf descriptions in depth-first order."""
    k = d[0]
    if k in LEAF_KINDS:
        return [d]
    if k in ("hull", "sum"):
        out = []
        for c in d[1]:
            out += leaves(c)
        return out
    if k == "affine":
        return leaves(d[3])
    raise ValueError(k)


def scale_of(d):
    """A bound on max ||a|| over the set (used only to scale absolute round-off tolerances)."""
    n = dim(d)
    return float(max(support(d, e) for e in np.vstack([np.eye(n), -np.eye(n)])) * np.sqrt(n))


# ----------------------------------------------------------------------------------------------
# support function (closed forms, plain numpy)
# ----------------------------------------------------------------------------------------------
def support(d, u):
    """h_A(u) = max_{a in A} u.a."""
    u = np.asarray(u, dtype=float)
    k = d[0]
    if k == "poly":
        return float(np.max(d[1] @ u))
    if k == "ell":
        return float(d[1] @ u + np.linalg.norm(d[2].T @ u))
    if k == "box":
        half, center, R = d[1], d[2], d[3]
        return float(center @ u + np.sum(half * np.abs(R.T @ u)))
    if k == "tcone":
        rb, rt, h = d[1], d[2], d[3]
        q = np.hypot(u[0], u[1])
        return float(max(0.5 * h * u[2] + rt * q, -0.5 * h * u[2] + rb * q))
    if k == "capsule":
        radius, length = d[1], d[2]
        return float(abs(u[2]) * length / 2 + radius * np.linalg.norm(u))
    if k == "hull":
        return max(support(c, u) for c in d[1])
    if k == "sum":
        return float(sum(support(c, u) for c in d[1]))
    if k == "affine":
        M, t, child = d[1], d[2], d[3]
        return float(support(child, M.T @ u) + t @ u)
    raise ValueError(k)


# ----------------------------------------------------------------------------------------------
# witnesses, evaluated independently (also checks that the leaf-local pre-image is feasible)
# ----------------------------------------------------------------------------------------------
class WitnessError(AssertionError):
    pass


def _leaf_point(leaf, local, tol):
    k = leaf[0]
    if k == "poly":
        V = leaf[1]
        idx = int(local)
        if idx != local or not 0 <= idx < V.shape[0]:
            raise WitnessError(f"bad vertex index {local!r}")
        return V[idx].copy()
    if k == "ell":
        c, S = leaf[1], leaf[2]
        x = np.asarray(local, dtype=float).reshape(-1)
        if x.size != S.shape[1]:
            raise WitnessError(f"ellipsoid witness of size {x.size}, expected {S.shape[1]}")
        if np.linalg.norm(x) > 1 + tol:
            raise WitnessError("ellipsoid witness outside the unit ball: "
                               f"||x|| = {np.linalg.norm(x)!r}")
        return c + S @ x
    if k == "box":
        half, center, R = leaf[1], leaf[2], leaf[3]
        x = np.asarray(local, dtype=float).reshape(-1)
        if x.size != half.size or np.any(np.abs(x) > half * (1 + tol)):
            raise WitnessError(f"box witness {x!r} outside half extents {half!r}")
        return center + R @ x
    if k == "tcone":
        rb, rt, h = leaf[1], leaf[2], leaf[3]
        x = np.asarray(local, dtype=float).reshape(-1)
        s = x[2] / h + 0.5
        if x.size != 3 or not (-tol <= s <= 1 + tol):
            raise WitnessError(f"truncated-cone witness {x!r} outside the slab")
        rad = rb + (rt - rb) * min(max(s, 0.0), 1.0)
        if np.hypot(x[0], x[1]) > rad + tol * max(rb, rt, h):
            raise WitnessError(f"truncated-cone witness {x!r} outside the lateral surface")
        return x.copy()
    raise ValueError(k)


def witness_point(d, witness, tol=1e-12):
    """Map a witness ((leaf_index, local), ...) to a point of the set described by d.

    Raises WitnessError when the witness is malformed (wrong leaves for a hull/sum, infeasible
    leaf-local pre-image)."""
    wit = {}
    for pair in witness:
        li, local = pair
        li = int(li)
        if li in wit:
            raise WitnessError(f"leaf {li} appears twice in the witness")
        wit[li] = local
    counter = [0]

    def rec(node):
        k = node[0]
        if k in LEAF_KINDS:
            i = counter[0]
            counter[0] += 1
            if i in wit:
                return _leaf_point(node, wit.pop(i), tol)
            return None
        if k == "hull":
            pts = [rec(c) for c in node[1]]
            got = [p for p in pts if p is not None]
            if len(got) > 1:
                raise WitnessError("more than one child of a hull in the witness")
            return got[0] if got else None
        if k == "sum":
            pts = [rec(c) for c in node[1]]
            if all(p is None for p in pts):
                return None
            if any(p is None for p in pts):
                raise WitnessError("a summand of a Minkowski sum is missing from the witness")
            return np.sum(pts, axis=0)
        if k == "affine":
            p = rec(node[3])
            return None if p is None else node[1] @ p + node[2]
        if k == "capsule":
            raise ValueError("capsule: use capsule_contains")
        raise ValueError(k)

    p = rec(d)
    if wit:
        raise WitnessError(f"unknown leaves in the witness: {sorted(wit)}")
    if p is None:
        raise WitnessError("empty witness")
    return p


def capsule_contains(radius, length, p, tol=1e-12):
    p = np.asarray(p, dtype=float)
    z = min(max(p[2], -length / 2), length / 2)
    return np.linalg.norm(p - np.array([0.0, 0.0, z])) <= radius + tol * max(radius, length, 1.0)


# ----------------------------------------------------------------------------------------------
# polytope ray shooting: HiGHS LP, polished on the optimal face
# ----------------------------------------------------------------------------------------------
HIGHS = dict(primal_feasibility_tolerance=1e-10, dual_feasibility_tolerance=1e-10)


def ray_shoot_lp(V, r):
    """max t s.t. t r = V^T lam, lam >= 0, sum lam = 1, t >= 0.  Returns (hit, t, lam).

    HiGHS is accurate to ~1e-10; the answer is then polished: the active vertices (lam > 0) span
    the optimal face, and (t, lam_active) is re-solved exactly from the linear equations with
    numpy least squares (unique when the ray crosses the face transversally; otherwise the HiGHS
    value is kept)."""
    V = np.asarray(V, dtype=float)
    r = np.asarray(r, dtype=float)
    m, n = V.shape
    c = np.zeros(m + 1)
    c[0] = -1.0
    A_eq = np.zeros((n + 1, m + 1))
    A_eq[:n, 0] = r
    A_eq[:n, 1:] = -V.T
    A_eq[n, 1:] = 1.0
    b_eq = np.zeros(n + 1)
    b_eq[n] = 1.0
    bounds = [(0, None)] * (m + 1)        # t >= 0: the ray starts at the origin
    res = scipy.optimize.linprog(c, A_eq=A_eq, b_eq=b_eq, bounds=bounds, method="highs",
                                 options=HIGHS)
    if res.status == 2:
        return False, 0.0, None
    assert res.status == 0, res.message
    t = float(res.x[0])
    lam = res.x[1:]
    active = np.flatnonzero(lam > 1e-9)
    # polish: on the active face, t r = v0 + sum_i mu_i (v_i - v0) (mu_0 = 1 - sum mu_i); solve
    # [r, -(v_i - v0)] [t, mu] = v0 with unit-norm columns (scale invariance), then verify.
    W = V[active]
    v0 = W[0]
    M = np.column_stack([r] + [-(w - v0) for w in W[1:]])
    cs = np.linalg.norm(M, axis=0)
    if np.all(cs > 0) and np.linalg.matrix_rank(M / cs) == M.shape[1]:
        z, *_ = np.linalg.lstsq(M / cs, v0, rcond=None)
        z /= cs
        mu = np.r_[1.0 - z[1:].sum(), z[1:]]
        resid = np.linalg.norm(z[0] * r - mu @ W)
        if np.all(mu >= -1e-12) and resid <= 1e-14 * max(np.abs(W).max(), 1e-300) * W.shape[0] \
                and abs(z[0] - t) <= 1e-8 * abs(t):
            t = float(z[0])
            lam = np.zeros(m)
            lam[active] = mu
    return True, t, lam


def contains_lp(V, b):
    """Is b in CH(V)?  (feasibility LP)."""
    V = np.asarray(V, dtype=float)
    m, n = V.shape
    A_eq = np.vstack([V.T, np.ones((1, m))])
    b_eq = np.r_[b, 1.0]
    res = scipy.optimize.linprog(np.zeros(m), A_eq=A_eq, b_eq=b_eq, bounds=[(0, None)] * m,
                                 method="highs", options=HIGHS)
    return res.status == 0


# ----------------------------------------------------------------------------------------------
# ellipsoid ray shooting: closed form
# ----------------------------------------------------------------------------------------------
def _largest_root(w, e):
    """Largest t with ||t w - e|| = 1, or None.  Stable quadratic formula."""
    ww = w @ w
    beta = w @ e
    gamma = e @ e - 1.0
    D = beta * beta - ww * gamma
    if D < 0:
        return None
    sq = np.sqrt(D)
    if beta >= 0:
        return (beta + sq) / ww
    return gamma / (beta - sq)


def ray_shoot_ellipsoid(c, S, r, in_plane=None):
    """Farthest t >= 0 with t r in {c + S x : ||x|| <= 1}, any rank of S.  Returns (hit, t).

    With S = U diag(s) W^T (rank k'), t r - c must lie in range(U). If the ray direction has a
    component p = (I - U U^T) r off the plane, t is fixed by the linear equation t p = (I - UU^T) c
    and the hit is decided by ||diag(1/s) U^T (t r - c)|| <= 1. Otherwise (ray parallel to the
    plane) the plane must contain the origin and t is the largest root of
    ||diag(1/s) U^T (t r - c)|| = 1.  `in_plane` overrides the numerical decision of which case
    applies (for constructions where it is known exactly)."""
    c = np.asarray(c, dtype=float)
    S = np.asarray(S, dtype=float)
    r = np.asarray(r, dtype=float)
    U, s, _ = np.linalg.svd(S, full_matrices=False)
    keep = s > 1e-12 * s.max()
    U, s = U[:, keep], s[keep]
    p = r - U @ (U.T @ r)
    q = c - U @ (U.T @ c)
    if in_plane is None:
        in_plane = np.linalg.norm(p) <= 1e-10 * np.linalg.norm(r)
    if not in_plane:
        t = float(p @ q / (p @ p))
        if np.linalg.norm(q - t * p) > 1e-10 * max(1.0, np.linalg.norm(c)):
            return False, 0.0
        x = (U.T @ (t * r - c)) / s
        if t < 0 or np.linalg.norm(x) > 1.0:
            return False, 0.0
        return True, t
    if np.linalg.norm(q) > 1e-10 * max(1.0, np.linalg.norm(c)):
        return False, 0.0
    w = (U.T @ r) / s
    e = (U.T @ c) / s
    t = _largest_root(w, e)
    if t is None or t < 0:
        return False, 0.0
    return True, float(t)


# ----------------------------------------------------------------------------------------------
# conic programs with Clarabel (hulls, sums, anything describable)
# ----------------------------------------------------------------------------------------------
class _Conic:
    """Collects linear equalities, inequalities (expr >= 0) and second-order cones over scalar
    variables. An affine expression is a pair (dict var -> coef, constant)."""

    def __init__(self):
        self.nvar = 0
        self.eq = []
        self.ge = []
        self.soc = []

    def new(self, k):
        idx = list(range(self.nvar, self.nvar + k))
        self.nvar += k
        return [({i: 1.0}, 0.0) for i in idx]

    @staticmethod
    def lin(terms, const=0.0):
        """sum coef * expr over (coef, expr) + const."""
        out = {}
        c0 = const
        for coef, (d, c) in terms:
            if coef == 0.0:
                continue
            for i, v in d.items():
                out[i] = out.get(i, 0.0) + coef * v
            c0 += coef * c
        return (out, c0)

    def member(self, desc, x, th):
        """Constrain the vector expression x to lie in th * A (th a scalar expression >= 0)."""
        k = desc[0]
        L = self.lin
        n = len(x)
        if k == "poly":
            V = desc[1]
            lam = self.new(V.shape[0])
            for l in lam:
                self.ge.append(l)
            self.eq.append(L([(1.0, l) for l in lam] + [(-1.0, th)]))
            for a in range(n):
                self.eq.append(L([(1.0, x[a])] + [(-V[j, a], lam[j]) for j in range(V.shape[0])]))
        elif k == "ell":
            c, S = desc[1], desc[2]
            y = self.new(S.shape[1])
            self.soc.append([th] + y)
            for a in range(n):
                self.eq.append(L([(1.0, x[a]), (-c[a], th)]
                                 + [(-S[a, b], y[b]) for b in range(S.shape[1])]))
        elif k == "box":
            half, center, R = desc[1], desc[2], desc[3]
            y = self.new(n)
            for b in range(n):
                self.ge.append(L([(1.0, th), (-1.0, y[b])]))
                self.ge.append(L([(1.0, th), (1.0, y[b])]))
            for a in range(n):
                self.eq.append(L([(1.0, x[a]), (-center[a], th)]
                                 + [(-R[a, b] * half[b], y[b]) for b in range(n)]))
        elif k == "tcone":
            rb, rt, h = desc[1], desc[2], desc[3]
            e2 = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
            self.member(("hull", [("ell", np.array([0, 0, -h / 2]), rb * e2),
                                  ("ell", np.array([0, 0, h / 2]), rt * e2)]), x, th)
        elif k == "capsule":
            radius, length = desc[1], desc[2]
            self.member(("sum", [("poly", np.array([[0, 0, -length / 2], [0, 0, length / 2]])),
                                 ("ell", np.zeros(3), radius * np.eye(3))]), x, th)
        elif k == "hull":
            ths = self.new(len(desc[1]))
            for t_ in ths:
                self.ge.append(t_)
            self.eq.append(L([(1.0, t_) for t_ in ths] + [(-1.0, th)]))
            parts = [self.new(n) for _ in desc[1]]
            for a in range(n):
                self.eq.append(L([(1.0, x[a])] + [(-1.0, p[a]) for p in parts]))
            for child, p, t_ in zip(desc[1], parts, ths):
                self.member(child, p, t_)
        elif k == "sum":
            parts = [self.new(n) for _ in desc[1]]
            for a in range(n):
                self.eq.append(L([(1.0, x[a])] + [(-1.0, p[a]) for p in parts]))
            for child, p in zip(desc[1], parts):
                self.member(child, p, th)
        elif k == "affine":
            M, t, child = desc[1], desc[2], desc[3]
            y = self.new(M.shape[1])
            for a in range(n):
                self.eq.append(L([(1.0, x[a]), (-t[a], th)]
                                 + [(-M[a, b], y[b]) for b in range(M.shape[1])]))
            self.member(child, y, th)
        else:
            raise ValueError(k)

    def solve(self, objective, tol=1e-12):
        """minimize objective (an affine expression). Returns (status, x, obj, z) with z the dual
        variables, the equalities first in the order of self.eq."""
        rows, cols, vals, b, cones = [], [], [], [], []
        r = 0

        def put(expr, sign):
            nonlocal r
            d, c = expr
            for i, v in d.items():
                rows.append(r)
                cols.append(i)
                vals.append(sign * v)
            b.append(-sign * c)
            r += 1

        for e in self.eq:
            put(e, 1.0)                   # A x + s = b, s = 0:  A x = -const
        if self.eq:
            cones.append(clarabel.ZeroConeT(len(self.eq)))
        for e in self.ge:
            put(e, -1.0)                  # s = b - A x = expr >= 0
        if self.ge:
            cones.append(clarabel.NonnegativeConeT(len(self.ge)))
        for blk in self.soc:
            for e in blk:
                put(e, -1.0)
            cones.append(clarabel.SecondOrderConeT(len(blk)))
        A = sp.csc_matrix((vals, (rows, cols)), shape=(r, self.nvar))
        q = np.zeros(self.nvar)
        for i, v in objective[0].items():
            q[i] += v
        P = sp.csc_matrix((self.nvar, self.nvar))
        st = clarabel.DefaultSettings()
        st.verbose = False
        st.max_iter = 500
        st.tol_gap_abs = tol
        st.tol_gap_rel = tol
        st.tol_feas = tol
        st.tol_ktratio = min(1e-8, 100 * tol)
        solver = clarabel.DefaultSolver(P, q, A, np.array(b), cones, st)
        sol = solver.solve()
        return str(sol.status), np.array(sol.x), sol.obj_val + objective[1], np.array(sol.z)


def _status_ok(status):
    return status in ("Solved", "AlmostSolved")


def _status_infeasible(status):
    return status in ("PrimalInfeasible", "AlmostPrimalInfeasible")


def ray_shoot_socp(desc, r):
    """max t s.t. t r in A (A given by a description).  Returns (hit, t, t_upper).

    Clarabel's tolerances are set to 1e-12 (relaxed to 1e-11, 1e-10 when it stops without
    converging: it sometimes reports InsufficientProgress at 1e-12). The answer is certified: the
    dual variables y of the n equalities t r = x give a normal n = y with n.r > 0, and by weak
    duality t_true <= t_upper = h_A(n)/(n.r), evaluated with the exact support function above. The
    returned t_upper is that certified upper bound; (t_upper - t)/t is the truth's own error (the
    primal t is feasible up to ~tol)."""
    r = np.asarray(r, dtype=float)
    best = None
    for tol in (1e-12, 1e-11, 1e-10):
        P = _Conic()
        (t,) = P.new(1)
        P.ge.append(t)                        # t >= 0: the ray starts at the origin
        x = [({0: float(ra)}, 0.0) for ra in r]
        P.member(desc, x, ({}, 1.0))
        status, sol, obj, z = P.solve(({0: -1.0}, 0.0), tol=tol)
        if _status_infeasible(status):
            return False, 0.0, 0.0
        rows = [i for i, (dct, _) in enumerate(P.eq) if 0 in dct]
        assert len(rows) == r.size
        nrm = z[rows]
        if nrm @ r < 0:
            nrm = -nrm
        t_val = float(sol[0])
        t_up = support(desc, nrm) / (nrm @ r) if nrm @ r > 0 else np.inf
        if status == "Solved":
            return True, t_val, float(t_up)
        if best is None or t_up - t_val < best[2] - best[1]:
            best = (True, t_val, float(t_up))
    assert best is not None and (best[2] - best[1]) <= 1e-9 * best[1], (status, best)
    return best


def closest_point_socp(desc, b):
    """min ||x - b|| over x in A.  Returns (distance, x)."""
    b = np.asarray(b, dtype=float)
    n = b.size
    P = _Conic()
    x = P.new(n)
    (s,) = P.new(1)
    P.member(desc, x, ({}, 1.0))
    P.soc.append([s] + [P.lin([(1.0, x[a])], -b[a]) for a in range(n)])
    status, sol, obj, _ = P.solve(s)
    assert _status_ok(status), status
    xv = np.array([sol[next(iter(e[0]))] for e in x])
    return float(sol[n]), xv


def cone_distance_socp(desc, b):
    """min ||x - b|| over x in CO(A) = {th a : th >= 0, a in A}.  Returns (distance, x)."""
    b = np.asarray(b, dtype=float)
    n = b.size
    P = _Conic()
    x = P.new(n)
    (s,) = P.new(1)
    (th,) = P.new(1)
    P.ge.append(th)
    P.member(desc, x, th)
    P.soc.append([s] + [P.lin([(1.0, x[a])], -b[a]) for a in range(n)])
    status, sol, obj, _ = P.solve(s)
    assert _status_ok(status), status
    xv = np.array([sol[next(iter(e[0]))] for e in x])
    return float(sol[n]), xv


# ----------------------------------------------------------------------------------------------
# closest points
# ----------------------------------------------------------------------------------------------
def closest_point_polytope(V, b):
    """Exact projection of b onto CH(V): Clarabel SOCP for the optimal face, then the projection
    onto the affine hull of the active vertices solved exactly (KKT system) and verified
    (weights >= 0 and every vertex on the far side of the supporting hyperplane).
    Returns (distance, point)."""
    V = np.asarray(V, dtype=float)
    b = np.asarray(b, dtype=float)
    m, n = V.shape
    d0, x0 = closest_point_socp(("poly", V), b)
    scale = max(1.0, np.abs(V).max(), np.linalg.norm(b))
    # active face: vertices (numerically) on the supporting hyperplane through x0
    g = b - x0
    if np.linalg.norm(g) <= 1e-9 * scale:
        return 0.0, b.copy()
    nrm = g / np.linalg.norm(g)
    for tol in (1e-8, 1e-7, 1e-6, 1e-5):
        act = np.flatnonzero(V @ nrm >= nrm @ x0 - tol * scale)
        W = V[act]
        k = W.shape[0]
        # min ||W^T mu - b||^2  s.t. sum mu = 1
        K = np.zeros((k + 1, k + 1))
        K[:k, :k] = W @ W.T
        K[:k, k] = 1.0
        K[k, :k] = 1.0
        rhs = np.r_[W @ b, 1.0]
        sol, *_ = np.linalg.lstsq(K, rhs, rcond=None)
        mu = sol[:k]
        x = mu @ W
        gg = b - x
        dd = np.linalg.norm(gg)
        if dd == 0:
            continue
        nn = gg / dd
        ok = (np.all(mu >= -1e-12) and np.max(V @ nn) - nn @ x <= 1e-13 * scale
              and abs(dd - d0) <= 1e-6 * scale)
        if ok:
            return float(dd), x
    raise AssertionError("could not polish the polytope projection")


def closest_point_ellipsoid(c, S, b):
    """Exact projection of b onto a full-rank ellipsoid {c + S y : ||y|| <= 1}: the trust-region
    subproblem min ||S y - (b - c)|| s.t. ||y|| <= 1, solved through its secular equation
    ||(S^T S + mu I)^{-1} S^T (b - c)|| = 1 by bracketing root finding (brentq).
    Returns (distance, point)."""
    c = np.asarray(c, dtype=float)
    S = np.asarray(S, dtype=float)
    g = np.asarray(b, dtype=float) - c
    U, s, Wt = np.linalg.svd(S, full_matrices=False)
    assert S.shape[0] == S.shape[1] and s.min() > 1e-8 * s.max(), "square, full rank only"
    beta = U.T @ g                   # S^T g = W diag(s) beta
    if np.linalg.norm(beta / s) <= 1.0:
        return 0.0, np.asarray(b, dtype=float).copy()

    def phi(mu):
        return np.linalg.norm(s * beta / (s * s + mu)) - 1.0

    hi = 1.0
    while phi(hi) > 0:
        hi *= 2.0
    mu = scipy.optimize.brentq(phi, 0.0, hi, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=500)
    yw = s * beta / (s * s + mu)
    yw /= np.linalg.norm(yw)
    x = c + U @ (s * yw)
    return float(np.linalg.norm(np.asarray(b) - x)), x


def cone_distance_nnls(V, b):
    """Distance from b to the cone of the rows of V (scipy NNLS).
    Returns (distance, point, coef)."""
    V = np.asarray(V, dtype=float)
    b = np.asarray(b, dtype=float)
    coef, rnorm = scipy.optimize.nnls(V.T, b, maxiter=50 * V.shape[0])
    x = V.T @ coef
    return float(np.linalg.norm(b - x)), x, coef


# ----------------------------------------------------------------------------------------------
# grasps (section 5): a contact is a plain triple (G (6, 4) of eq. 11, mu, mu_s); mu_s = 0 is a
# point contact (f_4 = 0), mu = 0 a frictionless one (f_2 = f_3 = f_4 = 0)
# ----------------------------------------------------------------------------------------------
def soc_projection_norm(y, mu):
    """||Pi_K(y)|| for K = {g : ||g_2:n|| <= mu g_1} (mu >= 0), by the three cases of the
    projection onto a second-order cone: y in K, y in the polar cone {mu ||y_2:n|| <= -y_1},
    else the projection onto the boundary ray in the plane of e_1 and y, whose length is the
    component of y along that ray's unit vector (1, mu y_perp/||y_perp||)/sqrt(1 + mu^2)."""
    y = np.asarray(y, dtype=float)
    y1, q = y[0], float(np.linalg.norm(y[1:]))
    if y1 >= 0.0 and q <= mu * y1:        # (y1 >= 0: with mu = 0, -0.0 >= 0 holds)
        return float(np.linalg.norm(y))
    if mu * q <= -y1:
        return 0.0
    return float((y1 + mu * q) / np.sqrt(1.0 + mu * mu))


def _contact_dims(mu, mu_s):
    """The local components a contact uses: f_1; f_2, f_3 with friction; f_4 if soft."""
    return [0] if mu == 0.0 else ([0, 1, 2, 3] if mu_s > 0.0 else [0, 1, 2])


def contact_support(G, mu, mu_s, u, magnitude):
    """Support in direction u of {G f : f in F (eq. 12), measure(f) <= 1}, the origin included.

    normal: the unit-normal-force cross-section is the ellipse {f_1 = 1, ...} (NOTES.md item 3),
    h = max(0, y_1 + sqrt(mu^2 (y_2^2 + y_3^2) + mu_s^2 y_4^2)), y = G^T u.
    full (eq. 15): h = ||Pi_K(D^{-1} y)||, D = diag(1, 1, 1, mu/mu_s) on the contact's components.
    """
    y = np.asarray(G, dtype=float).T @ np.asarray(u, dtype=float)
    if magnitude == "normal":
        return max(0.0, float(y[0] + np.sqrt(mu * mu * (y[1] ** 2 + y[2] ** 2)
                                             + mu_s * mu_s * y[3] ** 2)))
    yl = y[_contact_dims(mu, mu_s)]
    if yl.size == 4:
        yl = yl * np.array([1.0, 1.0, 1.0, mu_s / mu])
    return soc_projection_norm(yl, mu)


def grasp_support(contacts, u, norm, magnitude):
    """h_W(u) for W = CH({0} U W_1 U ... U W_m) (L1) or sum_i CH({0} U W_i) (Linf): the minimum
    overall force resisting w_ext is >= (u.r) / h_W(u) for every u with u.r > 0, r = -w_ext."""
    h = [contact_support(G, mu, ms, u, magnitude) for G, mu, ms in contacts]
    return float(max(h)) if norm == "L1" else float(sum(h))


def contact_objective(forces, contacts, norm, magnitude):
    """sigma of eq. (13) or (15) for local forces (m, 4)."""
    values = []
    for f, (_, mu, mu_s) in zip(np.asarray(forces, dtype=float), contacts):
        if magnitude == "normal":
            values.append(f[0])
        else:
            spin = (mu / mu_s) ** 2 * f[3] ** 2 if mu_s > 0.0 else 0.0
            values.append(np.sqrt(f[0] ** 2 + f[1] ** 2 + f[2] ** 2 + spin))
    return float(sum(values) if norm == "L1" else max(values))


def min_force_socp(contacts, w_ext, norm, magnitude, equal=False, tol=1e-11):
    """min sigma (eq. 13 or 15) s.t. sum_i G_i f_i = -w_ext, f_i in F_i, with Clarabel.

    equal=True adds f_i1 = tau for every contact (norm "Linf", magnitude "normal"): the literal
    CH(W_1 + ... + W_m) of eq. (14), in which every contact pushes with the same normal force.
    Variables: f_1..f_m (4 each), then s_1..s_m (full magnitude), then tau (Linf).
    Returns (status, sigma, forces (m, 4), u) with status "optimal" or "infeasible" (anything else
    raises) and u the dual of the equilibrium rows, oriented so that u.r = the dual objective
    (a direction for the certificate sigma >= u.r / h_W(u), r = -w_ext).
    """
    m = len(contacts)
    w = np.asarray(w_ext, dtype=float)
    full = magnitude == "full"
    ns = 4 * m
    nt = ns + (m if full else 0)
    nvar = nt + (1 if norm == "Linf" else 0)
    blocks = []                    # (cone, rows of A as dicts {var: coef}, b)

    def block(cone, rows, b):
        blocks.append((cone, rows, b))

    # equilibrium, then the components a contact does not have, then the literal-eq.-14 rows
    eq_rows = [{4 * i + b: G[a, b] for i, (G, _, _) in enumerate(contacts) for b in range(4)
                if G[a, b] != 0.0} for a in range(6)]
    eq_b = list(-w)
    for i, (_, mu, ms) in enumerate(contacts):
        for b in sorted(set(range(4)) - set(_contact_dims(mu, ms))):
            eq_rows.append({4 * i + b: 1.0})
            eq_b.append(0.0)
        if equal:
            eq_rows.append({4 * i: 1.0, nt: -1.0})
            eq_b.append(0.0)
    block(clarabel.ZeroConeT(len(eq_rows)), eq_rows, eq_b)
    for i, (_, mu, ms) in enumerate(contacts):
        dims = _contact_dims(mu, ms)
        if len(dims) == 1:
            block(clarabel.NonnegativeConeT(1), [{4 * i: -1.0}], [0.0])
        else:
            # (mu f_1, f_2, f_3, (mu/mu_s) f_4): eq. (12) times mu, well scaled for small mu_s
            scale = [mu, 1.0, 1.0, mu / ms if ms > 0.0 else 0.0]
            block(clarabel.SecondOrderConeT(len(dims)),
                  [{4 * i + b: -scale[b]} for b in dims], [0.0] * len(dims))
        if full:
            weight = [1.0, 1.0, 1.0, mu / ms if ms > 0.0 else 0.0]
            block(clarabel.SecondOrderConeT(1 + len(dims)),
                  [{ns + i: -1.0}] + [{4 * i + b: -weight[b]} for b in dims],
                  [0.0] * (1 + len(dims)))
    if norm == "Linf":
        value = [(4 * i) if not full else (ns + i) for i in range(m)]
        block(clarabel.NonnegativeConeT(m), [{k: 1.0, nvar - 1: -1.0} for k in value], [0.0] * m)
    q = np.zeros(nvar)
    if norm == "Linf":
        q[nvar - 1] = 1.0
    elif full:
        q[ns:ns + m] = 1.0
    else:
        q[0:ns:4] = 1.0

    rows, cols, vals, b, cones = [], [], [], [], []
    for cone, brows, bb in blocks:
        for row in brows:
            for col, v in row.items():
                rows.append(len(b))
                cols.append(col)
                vals.append(v)
            b.append(0.0)
        b[len(b) - len(brows):] = bb
        cones.append(cone)
    A = sp.csc_matrix((vals, (rows, cols)), shape=(len(b), nvar))
    # Clarabel sometimes stops (InsufficientProgress, NumericalError) at the tightest
    # tolerances on nearly infeasible grasps (forces ~400 |w|): retry with tighter iterative
    # refinement, shorter steps, then looser tolerances (the comparisons allow 1e-6)
    refine = {"iterative_refinement_reltol": 1e-14, "iterative_refinement_abstol": 1e-14,
              "iterative_refinement_max_iter": 50}
    attempts = [(tol, {}), (tol, refine), (tol, {"max_step_fraction": 0.9}), (1e-9, refine),
                (1e-8, {})]
    for tol_used, options in attempts:
        st = clarabel.DefaultSettings()
        st.verbose = False
        st.max_iter = 500
        st.tol_gap_abs = st.tol_gap_rel = st.tol_feas = tol_used
        st.tol_ktratio = min(1e-8, 100 * tol_used)
        for key, value in options.items():
            setattr(st, key, value)
        sol = clarabel.DefaultSolver(sp.csc_matrix((nvar, nvar)), q, A, np.array(b), cones,
                                     st).solve()
        status = str(sol.status)
        if _status_infeasible(status):
            return "infeasible", np.inf, None, None
        if _status_ok(status):
            break
    else:
        raise AssertionError(f"Clarabel: {status}")
    x = np.array(sol.x)
    forces = x[:ns].reshape(m, 4)
    # dual objective -b^T z = w^T z_eq: with r = -w, u = -z_eq gives u.r = the dual value
    u = -np.array(sol.z)[:6]
    return "optimal", float(sol.obj_val), forces, u


# ----------------------------------------------------------------------------------------------
# resistibility with a margin: which wrenches a grasp resists at all, whatever the forces' size
# ----------------------------------------------------------------------------------------------
def _solve_blocks(nvar, q, blocks, tol=1e-10):
    """Clarabel on b - A x in the cones of `blocks` [(cone, rows as dicts {var: coef}, b)],
    minimizing q^T x. Returns (status, x)."""
    rows, cols, vals, b, cones = [], [], [], [], []
    for cone, brows, bb in blocks:
        for row, bv in zip(brows, bb):
            for col, v in row.items():
                rows.append(len(b))
                cols.append(col)
                vals.append(v)
            b.append(bv)
        cones.append(cone)
    A = sp.csc_matrix((vals, (rows, cols)), shape=(len(b), nvar))
    st = clarabel.DefaultSettings()
    st.verbose = False
    st.max_iter = 500
    st.tol_gap_abs = st.tol_gap_rel = st.tol_feas = tol
    sol = clarabel.DefaultSolver(sp.csc_matrix((nvar, nvar)), np.asarray(q, dtype=float), A,
                                 np.array(b), cones, st).solve()
    return str(sol.status), np.array(sol.x)


def _absent_components(contacts):
    """Equality rows f_ib = 0 for the components a contact does not have."""
    rows = []
    for i, (_, mu, ms) in enumerate(contacts):
        for b in sorted(set(range(4)) - set(_contact_dims(mu, ms))):
            rows.append({4 * i + b: 1.0})
    return rows


def cone_excess(contact, f):
    """How far the local force f lies outside F_i of eq. (12), relative to f_1 (<= 0 inside),
    from the contact's mu and mu_spin alone (not Contact's own checks)."""
    return cone_outside(contact, f) / max(f[0], 1e-300)


def cone_slack(f, mu, mu_s):
    """The radius of the largest ball, in the contact's own components, around f inside F_i of
    eq. (12) (negative outside): for the circular cone of half-angle atan(mu), the distance to
    its boundary is (mu f_1 - ||f_t||) / sqrt(1 + mu^2); a soft finger's cone is circular in
    g = (f_1, f_2, f_3, (mu / mu_s) f_4), and a ball of radius s in f maps into one of radius
    s max(1, mu / mu_s) in g."""
    if mu == 0.0:
        return float(f[0])
    if mu_s == 0.0:
        return float((mu * f[0] - np.hypot(f[1], f[2])) / np.sqrt(1.0 + mu * mu))
    g = np.array([f[0], f[1], f[2], f[3] * mu / mu_s])
    return float((mu * g[0] - np.linalg.norm(g[1:])) / np.sqrt(1.0 + mu * mu)
                 / max(1.0, mu / mu_s))


FORCE_CAP = 1e3   # resist_depth's bound on the sum of normal forces, for a unit wrench
POLAR_TOL = 1e-12   # h_{W_i}(u) <= this (||u|| = 1, G_i of unit size): u is in K's polar cone


def resist_depth(contacts, x):
    """A lower bound on the depth of x inside K = {sum_i G_i f_i : f_i in F_i}, the cone of
    wrenches the contacts produce: the radius of a ball around x inside K, or a negative number
    when none is proven. Forces f with sum_i G_i f_i = x and every f_i inside F_i with slack s
    (a ball of radius s in its own components: `cone_slack`) absorb any change v of x with
    ||v|| <= s sigma_min(G_c) (G_c: the grasp map on the components the contacts have), so that
    is a depth; the forces maximize s (capped at 1: force closure makes it unbounded) in an SOCP,
    their normal forces summing to at most FORCE_CAP (so that the residual recomputed here from
    them, and the rounding of that, stay meaningful), and a grasp map of numerical rank < 6 (a
    pinch transmits no torque about its axis) has no interior: no depth."""
    m = len(contacts)
    s = 4 * m
    eq = [{4 * i + b: G[a, b] for i, (G, _, _) in enumerate(contacts) for b in range(4)
           if G[a, b] != 0.0} for a in range(6)]
    eqb = list(x)
    absent = _absent_components(contacts)
    blocks = [(clarabel.ZeroConeT(6 + len(absent)), eq + absent, eqb + [0.0] * len(absent)),
              (clarabel.NonnegativeConeT(2), [{s: 1.0}, {4 * i: 1.0 for i in range(m)}],
               [1.0, FORCE_CAP])]
    for i, (_, mu, ms) in enumerate(contacts):
        dims = _contact_dims(mu, ms)
        if len(dims) == 1:
            blocks.append((clarabel.NonnegativeConeT(1), [{4 * i: -1.0, s: 1.0}], [0.0]))
            continue
        c = np.sqrt(1.0 + mu * mu) * (max(1.0, mu / ms) if ms > 0.0 else 1.0)
        scale = [mu, 1.0, 1.0, mu / ms if ms > 0.0 else 0.0]
        rows = [{4 * i: -mu, s: c}] + [{4 * i + b: -scale[b]} for b in dims[1:]]
        blocks.append((clarabel.SecondOrderConeT(len(dims)), rows, [0.0] * len(dims)))
    q = np.zeros(s + 1)
    q[s] = -1.0
    status, sol = _solve_blocks(s + 1, q, blocks)
    if not _status_ok(status):
        return -np.inf
    forces = sol[:s].reshape(m, 4)
    for i, (_, mu, ms) in enumerate(contacts):
        forces[i, [b for b in range(4) if b not in _contact_dims(mu, ms)]] = 0.0
    Gc = np.hstack([G[:, _contact_dims(mu, ms)] for G, mu, ms in contacts])
    sv = np.linalg.svd(Gc, compute_uv=False)
    if Gc.shape[1] < 6 or sv[5] <= 1e-10 * sv[0]:
        return 0.0
    wrenches = np.array([G @ f for (G, _, _), f in zip(contacts, forces)])
    residual = np.linalg.norm(wrenches.sum(axis=0) - x)
    rounding = 1e-14 * np.linalg.norm(wrenches, axis=1).sum()
    slack = min(cone_slack(f, mu, ms) for f, (_, mu, ms) in zip(forces, contacts))
    return float(slack * sv[5] - residual - rounding)


def cone_polar_excess(contacts, u):
    """max_i h_{W_i}(u) over the contacts' sets at unit normal force (NOTES.md item 3): <= 0
    iff u^T w <= 0 for every wrench w the contacts produce."""
    return float(max(G[:, 0] @ u + np.sqrt(mu * mu * ((G[:, 1] @ u) ** 2 + (G[:, 2] @ u) ** 2)
                                           + ms * ms * (G[:, 3] @ u) ** 2)
                     for G, mu, ms in contacts))


def polar_polish(contacts, u, steps=30, tol=1e-14):
    """u moved into the polar cone {u : h_{W_i}(u) <= 0 for every contact} (to tol, relative
    to ||u|| = 1) by Newton steps on the contacts' supports h_{W_i}(u) = y_1 + ||D y_t||,
    y = G_i^T u, whose gradient is G_i (1, D^2 y_t / ||D y_t||) (the support point of W_i):
    the shortest step that zeroes every support not clearly negative, by least squares (one
    contact at a time stalls where two cones meet at a small angle, a pinch's wedge); None if
    that fails. A conic solver's dual direction violates the cone by ~1e-8, which a pinch's
    internal forces (unbounded along a line) would make worthless as a certificate."""
    u = np.asarray(u, dtype=float) / np.linalg.norm(u)
    for _ in range(steps):
        rows, hs = [], []
        for G, mu, ms in contacts:
            y = G.T @ u
            d2 = np.array([0.0, mu * mu, mu * mu, ms * ms])
            q = np.sqrt(np.sum(d2 * y * y))
            h = y[0] + q
            if h > -1e-6:
                rows.append(G @ (np.r_[1.0, 0.0, 0.0, 0.0] + (d2 * y / q if q > 0.0 else 0.0)))
                hs.append(h + 1e-15)
        if not hs or max(hs) <= tol:
            return u
        step = np.linalg.lstsq(np.array(rows), -np.array(hs), rcond=None)[0]
        u = u + step
        u = u / np.linalg.norm(u)
    return u if cone_polar_excess(contacts, u) <= POLAR_TOL else None


def resist_projection(contacts, x):
    """(p, u): the wrench p of K nearest x (an SOCP) and the unit u = (x - p) / ||x - p||
    (None when x is in K to the solver's accuracy)."""
    m = len(contacts)
    tau = 4 * m
    absent = _absent_components(contacts)
    blocks = [(clarabel.ZeroConeT(len(absent)), absent, [0.0] * len(absent))] if absent else []
    for i, (_, mu, ms) in enumerate(contacts):
        dims = _contact_dims(mu, ms)
        if len(dims) == 1:
            blocks.append((clarabel.NonnegativeConeT(1), [{4 * i: -1.0}], [0.0]))
        else:
            scale = [mu, 1.0, 1.0, mu / ms if ms > 0.0 else 0.0]
            blocks.append((clarabel.SecondOrderConeT(len(dims)),
                           [{4 * i + b: -scale[b]} for b in dims], [0.0] * len(dims)))
    rows = [{tau: -1.0}] + [{4 * i + b: G[a, b] for i, (G, _, _) in enumerate(contacts)
                             for b in range(4) if G[a, b] != 0.0} for a in range(6)]
    blocks.append((clarabel.SecondOrderConeT(7), rows, [0.0] + list(x)))
    q = np.zeros(tau + 1)
    q[tau] = 1.0
    status, sol = _solve_blocks(tau + 1, q, blocks)
    forces = sol[:tau].reshape(m, 4)
    p = sum(G @ f for (G, _, _), f in zip(contacts, forces))
    g = np.asarray(x, dtype=float) - p
    dist = np.linalg.norm(g)
    return p, (g / dist if dist > 0.0 else None)


def resist_margin(contacts, w_ext):
    """Whether the contacts resist w_ext (some forces in the cones of eq. 12 give
    sum_i G_i f_i = -w_ext, eq. 11), with a margin, for x = -w_ext / ||w_ext||: the depth of x
    in K (> 0: `resist_depth`), or minus its distance from K (< 0: a unit u with
    h_{W_i}(u) <= 0 for every contact, so that u^T w <= 0 on K, and u^T x > 0, a distance
    recomputed here with truth's support after `polar_polish`, or the direction of x off the
    grasp map's span), or 0 when neither is proven (x on K's boundary to
    the solvers' accuracy). Independent of the objective: K is the same for every norm and
    magnitude."""
    x = -np.asarray(w_ext, dtype=float)
    x = x / np.linalg.norm(x)
    depth = resist_depth(contacts, x)
    if depth > 0.0:
        return depth
    distance = 0.0
    # x off the span of the grasp map (a pinch transmits no torque about its axis): the
    # residual's direction u has G_i^T u = 0, h_{W_i}(u) = 0 to rounding, whatever the forces
    Gc = np.hstack([G[:, _contact_dims(mu, ms)] for G, mu, ms in contacts])
    coef = np.linalg.lstsq(Gc, x, rcond=1e-10)[0]
    off = x - Gc @ coef
    if np.linalg.norm(off) > 0.0:
        u = off / np.linalg.norm(off)
        if cone_polar_excess(contacts, u) <= POLAR_TOL:
            distance = max(distance, float(u @ x))
    _, u = resist_projection(contacts, x)
    u = None if u is None else polar_polish(contacts, u)
    if u is not None:
        distance = max(distance, float(u @ x))
    return -distance
