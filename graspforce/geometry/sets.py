"""Compact convex sets known through their support maps.

Each set is a small tree: primitive leaves (polytope, ellipsoid, box, truncated cone) combined by
convex hull, Minkowski sum and affine maps. The tree compiles once to the flat support program
evaluated by the core's `support` (core/geometry/kernel.hpp), which returns h_A(u) and s_A(u) of eq.
(2) together with a witness: which leaves produced the point and their leaf-local pre-images.
"""
import numpy as np

from . import _kernel as K
from ._start_table import UNSEEN
from .._validate import finite_array, finite_scalar
from .._core import leaf_params


class ConvexSet:
    """A compact convex set in R^dim, given by its support map."""

    dim: int
    _start_table = UNSEEN      # graspforce.geometry._start_table: built at the set's second shot

    # -- the tree ---------------------------------------------------------------------------
    def _children(self):
        return ()

    def leaves(self):
        """Primitive sets in depth-first order; a witness's leaf index refers to this list."""
        out = []
        stack = [self]
        while stack:
            node = stack.pop()
            if isinstance(node, Leaf):
                out.append(node)
            stack.extend(reversed(node._children()))
        return out

    # -- compiled form ----------------------------------------------------------------------
    @property
    def program(self):
        """The support program (ints, floats) read by the compiled kernel
        (core/geometry/kernel.hpp)."""
        prog = self.__dict__.get("_program")
        if prog is None:
            prog, self._witness_slots = _compile(self)
            self._program = prog
        return prog

    @property
    def witness_size(self):
        """Length of a raw witness vector: one slot [active, local...] per leaf."""
        size = self.__dict__.get("_witness_size")
        if size is None:
            self.program
            size = self._witness_size = int(sum(size for _, size in self._witness_slots))
        return size

    def __getstate__(self):
        # what ray_shoot keeps on the set is rebuilt on demand: its compiled entry point does not
        # pickle, and a start table is built again after two shots
        # (graspforce.geometry._start_table)
        state = self.__dict__.copy()
        state.pop("_shot_layout", None)
        state.pop("_start_table", None)
        return state

    def support(self, u):
        """(h_A(u), s_A(u)) of eq. (2)."""
        h, point, _ = self._support(u)
        return h, point

    def support_witness(self, u):
        """(h_A(u), s_A(u), witness); the witness is decoded by `decode_witness`."""
        h, point, wit = self._support(u)
        return h, point, self.decode_witness(wit)

    def _support(self, u):
        u = finite_array(u, "u", shape=(self.dim,))
        prog = self.program
        point = np.empty(self.dim)
        wit = np.zeros(self.witness_size)
        h = K.support(prog[0], prog[1], u, point, wit)
        return h, point, wit

    def decode_witness(self, wit):
        """Turn a raw witness vector into ((leaf_index, local), ...) for the active leaves."""
        self.program
        out = []
        leaves = self.leaves()
        for j, (start, size) in enumerate(self._witness_slots):
            if wit[start] > 0.5:
                local = np.array(wit[start + 1:start + size])
                if isinstance(leaves[j], Polytope):
                    local = int(round(local[0]))
                out.append((j, local))
        return tuple(out)

    def witness_point(self, witness):
        """The point of A that a decoded witness stands for (pure Python, not the kernel)."""
        locals_ = dict(witness)
        counter = iter(range(len(self.leaves())))
        return _point_from_witness(self, locals_, counter)

    # -- operators --------------------------------------------------------------------------
    def __neg__(self):
        return Affine(-np.eye(self.dim), self)

    def __repr__(self):
        return f"{type(self).__name__}(dim={self.dim})"


class Leaf(ConvexSet):
    """A primitive set evaluated directly by the kernel."""

    kind: int

    def _param_parts(self):
        """The kernel's parameters of this leaf (core/geometry/kernel.hpp), as numbers and
        float64 arrays to be written one after the other."""
        raise NotImplementedError

    def _layout(self):
        """What fixes the leaf's program besides its kind: the sizes of its parameters."""
        raise NotImplementedError

    def _params(self):
        return leaf_params(self._param_parts())

    def _witness_len(self):
        raise NotImplementedError

    def local_to_point(self, local):
        raise NotImplementedError


class Polytope(Leaf):
    """CH(vertices): the convex hull of the rows of `vertices` (m, n)."""

    kind = K.POLYTOPE

    def __init__(self, vertices):
        v = finite_array(vertices, "vertices", ndim=2)
        if v.shape[0] < 1 or v.shape[1] < 1:
            raise ValueError("vertices: need at least one vertex of dimension >= 1, got shape "
                             f"{v.shape}")
        self.vertices = v
        self.dim = v.shape[1]

    def _param_parts(self):
        return (self.vertices.shape[0], self.dim, self.vertices)

    def _layout(self):
        return self.vertices.shape

    def _witness_len(self):
        return 1

    def local_to_point(self, local):
        return self.vertices[int(local)].copy()


class Ellipsoid(Leaf):
    """{center + shape @ x : ||x|| <= 1}, shape (n, k) of any rank (disks, segments, eq. 14)."""

    kind = K.ELLIPSOID

    def __init__(self, center, shape):
        c = finite_array(center, "center", ndim=1)
        s = finite_array(shape, "shape", ndim=2)
        if s.shape[0] != c.shape[0]:
            raise ValueError(f"shape: must have as many rows as center has entries ({c.shape[0]}),"
                             f" got {s.shape}")
        self.center = c
        self.shape = s
        self.dim = c.shape[0]

    def _param_parts(self):
        n, k = self.shape.shape
        return (n, k, self.center, self.shape)

    def _layout(self):
        return self.shape.shape

    def _witness_len(self):
        return self.shape.shape[1]

    def local_to_point(self, local):
        return self.center + self.shape @ np.asarray(local)


class Ball(Ellipsoid):
    """{x : ||x - center|| <= radius}."""

    def __init__(self, center, radius):
        c = finite_array(center, "center", ndim=1)
        r = finite_scalar(radius, "radius", minimum=0.0)
        super().__init__(c, r * np.eye(c.shape[0]))
        self.radius = r


class _AxisBox(Leaf):
    """{x : |x_i| <= half_i}, the leaf under `Box`."""

    kind = K.BOX

    def __init__(self, half):
        self.half = half
        self.dim = half.shape[0]

    def _param_parts(self):
        return (self.dim, self.half)

    def _layout(self):
        return self.dim

    def _witness_len(self):
        return self.dim

    def local_to_point(self, local):
        return np.asarray(local, dtype=float).copy()


class TruncatedCone(Leaf):
    """3-D hull of two coaxial disks: axis +z, radius `bottom_radius` at z = -height/2 and
    `top_radius` at z = +height/2. A cylinder (equal radii) and a cone (one radius 0) included."""

    kind = K.TRUNCATED_CONE
    dim = 3

    def __init__(self, bottom_radius, top_radius, height):
        self.bottom_radius = finite_scalar(bottom_radius, "bottom_radius", minimum=0.0)
        self.top_radius = finite_scalar(top_radius, "top_radius", minimum=0.0)
        self.height = finite_scalar(height, "height", minimum=0.0)

    def _param_parts(self):
        return (self.bottom_radius, self.top_radius, self.height)

    def _layout(self):
        return ()

    def _witness_len(self):
        return 3

    def local_to_point(self, local):
        return np.asarray(local, dtype=float).copy()


class ConeCap(Leaf):
    """CH{g in R^dim : ||g|| = 1, ||(g_2, ..., g_dim)|| <= mu g_1}: the unit vectors of a circular
    cone of half-angle atan(mu) about e_1. With the origin added (`hull(Polytope(zeros), cap)`) it
    is the cone cut by the unit ball, whose support is ||Pi_K(u)|| (NOTES.md item 3); mu = 0 is the
    single point e_1."""

    kind = K.CONE_CAP

    def __init__(self, mu, dim):
        self.mu = finite_scalar(mu, "mu", minimum=0.0)
        if not isinstance(dim, (int, np.integer)) or dim < 1:
            raise ValueError(f"dim: must be a positive integer, got {dim!r}")
        self.dim = int(dim)

    def _param_parts(self):
        return (self.dim, self.mu)

    def _layout(self):
        return self.dim

    def _witness_len(self):
        return self.dim

    def local_to_point(self, local):
        return np.asarray(local, dtype=float).copy()


class Hull(ConvexSet):
    """CH(A_1 U ... U A_m)."""

    def __init__(self, sets):
        self.sets = _same_dim(sets, "hull")
        self.dim = self.sets[0].dim

    def _children(self):
        return self.sets


class MinkowskiSum(ConvexSet):
    """A_1 + ... + A_m."""

    def __init__(self, sets):
        self.sets = _same_dim(sets, "minkowski_sum")
        self.dim = self.sets[0].dim

    def _children(self):
        return self.sets


class Affine(ConvexSet):
    """{M a + t : a in A}; M (m, n) may be non-square."""

    def __init__(self, matrix, inner, offset=None):
        if not isinstance(inner, ConvexSet):
            raise TypeError(f"A: expected a convex set, got {type(inner).__name__}")
        m = finite_array(matrix, "M", ndim=2)
        if m.shape[1] != inner.dim:
            raise ValueError(f"M: must have {inner.dim} columns (the set's dimension), got "
                             f"shape {m.shape}")
        t = np.zeros(m.shape[0]) if offset is None else finite_array(offset, "t",
                                                                      shape=(m.shape[0],))
        self.matrix = m
        self.offset = t
        self.inner = inner
        self.dim = m.shape[0]

    def _children(self):
        return (self.inner,)


def Box(half_extents, center=None, rotation=None):
    """{center + rotation @ x : |x_i| <= half_extents_i}."""
    half = finite_array(half_extents, "half_extents", ndim=1, minimum=0.0)
    box = _AxisBox(half)
    if center is None and rotation is None:
        return box
    n = half.shape[0]
    rot = np.eye(n) if rotation is None else _rotation(rotation, n, "rotation")
    return Affine(rot, box, None if center is None else finite_array(center, "center",
                                                                        shape=(n,)))


def Capsule(radius, length):
    """3-D segment from z = -length/2 to +length/2 swept by a ball of `radius`."""
    r = finite_scalar(radius, "radius", minimum=0.0)
    half = 0.5 * finite_scalar(length, "length", minimum=0.0)
    return MinkowskiSum([Polytope([[0.0, 0.0, -half], [0.0, 0.0, half]]), Ball(np.zeros(3), r)])


def hull(*sets):
    """Convex hull of the union of the sets."""
    return Hull(sets)


def minkowski_sum(*sets):
    """Minkowski sum of the sets."""
    return MinkowskiSum(sets)


def affine(M, A, t=None):
    """The image M A + t."""
    return Affine(M, A, t)


def pose(A, rotation, translation):
    """A 3-D body A (in its local frame) placed at rotation R and translation p: R A + p."""
    if not isinstance(A, ConvexSet) or A.dim != 3:
        raise ValueError("A: pose applies to a 3-D convex set")
    return Affine(_rotation(rotation, 3, "rotation"), A,
                  finite_array(translation, "translation", shape=(3,)))


# -- helpers ------------------------------------------------------------------------------------
def _rotation(rotation, n, name):
    rot = finite_array(rotation, name, shape=(n, n))
    if not np.allclose(rot.T @ rot, np.eye(n), atol=1e-9) or np.linalg.det(rot) < 0:
        raise ValueError(f"{name}: must be a proper rotation matrix (R^T R = I, det R = 1)")
    return rot


def _same_dim(sets, name):
    sets = tuple(sets)
    if not sets:
        raise ValueError(f"{name}: needs at least one set")
    for s in sets:
        if not isinstance(s, ConvexSet):
            raise TypeError(f"{name}: expected convex sets, got {type(s).__name__}")
    dims = {s.dim for s in sets}
    if len(dims) != 1:
        raise ValueError(f"{name}: all sets must have the same dimension, got {sorted(dims)}")
    return sets


def _point_from_witness(node, locals_, counter):
    """Evaluate the tree bottom-up from leaf-local points; None for a subtree with no witness."""
    if isinstance(node, Leaf):
        j = next(counter)
        return node.local_to_point(locals_[j]) if j in locals_ else None
    parts = [_point_from_witness(ch, locals_, counter) for ch in node._children()]
    if isinstance(node, Hull):
        found = [p for p in parts if p is not None]
        return found[0] if len(found) == 1 else None
    if isinstance(node, MinkowskiSum):
        return None if any(p is None for p in parts) else np.sum(parts, axis=0)
    return None if parts[0] is None else node.matrix @ parts[0] + node.offset


def _is_embedding(M):
    """Whether M is [0; I] with at least one zero row: the map x -> (0, x) that lifts a set into
    a space of more dimensions (min_force's lift of W_Linf, graspforce.grasping.wrench_space). It
    compiles to no product at all (`_kernel.EMBED`)."""
    m, n = M.shape
    return m > n and not M[:m - n].any() and np.array_equal(M[m - n:], np.eye(n))


def _origin_hull(node):
    """The set X when node is an embedding of CH({0} U X), written hull(Polytope([[0, ..]]), X):
    it compiles to one node (`_kernel.ORIGIN_EMBED`) whose value is t^T u + max(0, h_X), without
    the origin's leaf or the hull (W_Linf's lift, graspforce.grasping.wrench_space: 213 -> 189 ns a
    support call). The origin keeps its witness slot, so witnesses read as the tree says."""
    if not (isinstance(node, Affine) and _is_embedding(node.matrix)):
        return None
    inner = node.inner
    if not isinstance(inner, Hull) or len(inner.sets) != 2:
        return None
    origin, X = inner.sets
    if isinstance(origin, Polytope) and origin.vertices.shape[0] == 1 and \
            not origin.vertices.any():
        return X
    return None


def _compile(root):
    """Flatten the tree in pre-order into the arrays of the support kernel
    (graspforce.geometry._kernel)."""
    nodes = []   # (set, parent index)
    stack = [(root, -1)]
    while stack:
        node, parent = stack.pop()
        nodes.append((node, parent))
        me = len(nodes) - 1
        X = _origin_hull(node)
        stack.extend((ch, me) for ch in reversed((X,) if X is not None else node._children()))
    nn = len(nodes)
    kind = np.empty(nn, np.int64)
    dim = np.empty(nn, np.int64)
    pstart = np.zeros(nn, np.int64)
    cstart = np.zeros(nn, np.int64)
    ccount = np.zeros(nn, np.int64)
    wstart = np.full(nn, -1, np.int64)
    dstart = np.empty(nn, np.int64)
    ostart = np.empty(nn, np.int64)
    children_of = [[] for _ in range(nn)]
    for i, (_, parent) in enumerate(nodes):
        if parent >= 0:
            children_of[parent].append(i)
    params, children, slots = [], [], []
    pos = dpos = wpos = 0
    for i, (node, parent) in enumerate(nodes):
        dim[i] = node.dim
        # a hull or a sum hands its direction to its children unchanged: they read it in place;
        # an embedding's child reads its last entries
        if parent >= 0 and kind[parent] in (K.EMBED, K.ORIGIN_EMBED):
            dstart[i] = dstart[parent] + dim[parent] - node.dim
        elif parent >= 0 and kind[parent] != K.AFFINE:
            dstart[i] = dstart[parent]
        else:
            dstart[i] = dpos
            dpos += node.dim
        ostart[i] = dpos
        dpos += node.dim + 1
        if isinstance(node, Leaf):
            kind[i] = node.kind
            p = node._params()
            size = 1 + node._witness_len()
            wstart[i] = wpos
            slots.append((wpos, size))
            wpos += size
        else:
            kind[i] = (K.HULL if isinstance(node, Hull) else
                       K.SUM if isinstance(node, MinkowskiSum) else K.AFFINE)
            if isinstance(node, Affine):
                if _is_embedding(node.matrix):
                    kind[i] = K.EMBED
                    span = np.flatnonzero(node.offset)[-1] + 1 if node.offset.any() else 0
                    p = np.concatenate(([node.dim, node.inner.dim, span], node.offset))
                    if _origin_hull(node) is not None:
                        # the origin's slot [active, vertex 0], ahead of X's leaves as in
                        # `leaves()`
                        kind[i] = K.ORIGIN_EMBED
                        wstart[i] = wpos
                        slots.append((wpos, 2))
                        wpos += 2
                else:
                    p = np.concatenate(([node.dim, node.inner.dim], node.matrix.ravel(),
                                        node.offset))
            else:
                p = np.zeros(0)
            cstart[i] = len(children)
            ccount[i] = len(children_of[i])
            children.extend(children_of[i])
        pstart[i] = pos
        params.append(np.asarray(p, dtype=float))
        pos += len(p)
    nparams = pos
    plan = K.plan_of(kind, dim, params, children_of)
    ints = np.concatenate(([nn], kind, dim, pstart, cstart, ccount, wstart, dstart + nparams,
                           ostart + nparams, np.zeros(2 * nn, np.int64),
                           np.array(children, np.int64), [plan]))
    floats = np.concatenate(params + [np.zeros(dpos)])
    prog = (ints.astype(np.int64), floats)
    return prog, slots
