"""The wrench sets of eq. (14) built from the contacts' analytic support maps, and the table that
turns a support point's witness back into contact forces.

For one contact, U_i is a set of unit contact forces and W_i = G_i(U_i) its wrenches:
- magnitude "normal" (eq. 13): U_i = {f_1 = 1, (f_2^2 + f_3^2)/mu^2 + f_4^2/mu_s^2 <= 1}, the
  friction cone cut at unit normal force; W_i is the degenerate ellipsoid {c_i + S_i x : ||x|| <= 1}
  with c_i = G_i e_1 and S_i = G_i [mu e_2, mu e_3, mu_s e_4] (NOTES.md item 3).
- magnitude "full" (eq. 15): U_i = {f in F_i : ||f|| = 1} with ||f||^2 = f_1^2 + f_2^2 + f_3^2 +
  (mu/mu_s)^2 f_4^2. With g = D f, D = diag(1, 1, 1, mu/mu_s), F_i becomes the circular cone
  K = {||(g_2, g_3, g_4)|| <= mu g_1} and ||f|| = ||g||, so U_i = D^{-1}(unit vectors of K) and
  W_i = G_i D^{-1} (ConeCap(mu)). CH({0} U U_i) is the cone cut by the unit ball, whose support in
  direction y is ||Pi_K(D^{-1} y)|| (`ConeCap`).
Point contacts drop f_4, frictionless contacts keep only f_1.

Then (eq. 14 and NOTES.md item 2)
    W_L1   = CH(W_1 U ... U W_m)                   min sum_i |f_i|  = 1 / t,
    W_Linf = CH({0} U W_1) + ... + CH({0} U W_m)   min max_i |f_i|  = 1 / t,
where z = t r is the farthest point of W on the ray R(r), r = -w_ext. The literal W_Linf of
eq. (14), CH(W_1 + ... + W_m), makes every contact push with the same magnitude and is the minimum
only for symmetric grasps such as the paper's sphere.

min_force with IE or ZC-IE on up to LIFT_MAX_CONTACTS contacts (ZC-IE only where its finish on
the sum does not apply: a frictionless contact, the full magnitude, a grasp shot in its span;
`WrenchSpace._sum_finish`) does not shoot at the sum itself but at its lift, one dimension per
contact up (the Cayley embedding of the summands A_i = CH({0} U W_i)):

    C = CH( {e_1} x A_1  U ... U  {e_m} x A_m ) - (c, 0),   c = (1/m, ..., 1/m),

with the first m - 1 of the coordinates e kept (they sum to 1). A point of C with e-part 0 is
(1/m) sum_i a_i with a_i in A_i, so the ray (0, r) leaves C at t' with t = m t' on W_Linf. IE's
facets in C combine the contacts' support points freely, where a facet of the sum is made of n
sums of m points each: a cutting-plane model of each summand instead of one of their sum. On the
ingot grasp IE needs 28 steps on C (R^9) against 63 on the sum (R^6) at eps = 1e-9
(docs/design.md, "W_Linf's lift"). A vertex of C is one contact's wrench (or the origin), so the
forces are read off as for W_L1: f_i = sum_k (lam_k / t') u_ki over the vertices of contact i,
whose weights sum to 1/m.

A grasp whose wrenches do not span R^6 (two point contacts make no torque about the line through
them: rank 5) has a flat W, which gets no start table and on which IE and ZC take more steps.
min_force then shoots at the image Q^T W in R^k (or block-diag(I, Q^T) of the lift), Q an
orthonormal basis of the range of the contacts' maps (`wrench_span`), along Q^T r: the same t,
the forces read off the same witnesses (Q, the set and the ray in the units (force, torque / L)
of Grasp.length). A load farther than 1e-10 of its size from the range (core/grasping/forces.hpp,
SPAN_TOL), or one whose shot there ends without a certified hit or miss, is shot at the
full-dimensional set instead.
"""
import numpy as np

from .._core import capacity, extra_size, template_arrays
from .._core import grasp_values as _core_grasp_values
from ..records._forces import LENGTH, READER_HEAD, force_reader
from ..geometry._kernel import children, param_start
from ..geometry.sets import (Affine, ConeCap, Ellipsoid, Hull, MinkowskiSum, Polytope, affine,
                             hull, minkowski_sum)

NORMS = ("L1", "Linf")
MAGNITUDES = ("normal", "full")


def contact_set(contact, magnitude, G=None):
    """(W_i, base, local_map): the wrench set of one contact and how its leaf's witness maps to a
    unit contact force, f = base + local_map @ local. G: the contact's G_i in the units the set
    is made in (`torques_over`); its own by default."""
    if G is None:
        G = contact.matrix
    if magnitude == "normal":
        # the ellipse's axes: only the friction components this contact has
        axes = [(1, contact.mu), (2, contact.mu)] if contact.mu > 0.0 else []
        if contact.mu_spin > 0.0:
            axes.append((3, contact.mu_spin))
        local_map = np.zeros((4, len(axes)))
        for col, (row, coefficient) in enumerate(axes):
            local_map[row, col] = coefficient
        base = np.array([1.0, 0.0, 0.0, 0.0])
        W_i = Ellipsoid(G[:, 0], G @ local_map)
    else:
        # full magnitude: g = D f lives in the cone of the contact's own dimension
        size = 4 if contact.mu_spin > 0.0 else 3
        local_map = np.zeros((4, size))
        local_map[:3, :3] = np.eye(3)
        if size == 4:
            local_map[3, 3] = contact.mu_spin / contact.mu       # D^{-1}
        base = np.zeros(4)
        W_i = affine(G @ local_map, ConeCap(contact.mu, size))
    return W_i, base, local_map


def lift_summand(W_i, e):
    """{e} x CH({0} U W_i) in R^(k + 6), e with k entries: an embedding that the kernel evaluates
    as one node (`_kernel.ORIGIN_EMBED`: h_{W_i} in R^6, the origin where it is <= 0, e
    prepended)."""
    k = e.shape[0]
    return affine(np.vstack((np.zeros((k, 6)), np.eye(6))), hull(Polytope(np.zeros((1, 6))), W_i),
                  np.concatenate((e, np.zeros(6))))


def lift_rows(m):
    """The rows e_i - c of the lift (module docstring) without their last entry, (m, m - 1)."""
    return np.vstack((np.eye(m - 1), np.zeros((1, m - 1)))) - 1.0 / m


# the methods that shoot W_Linf's lift: IE's steps halve there. The distance-based ones gain
# nothing (ZC-based, Bi-GJK) or lose digits in R^(m + 5): GJK-based's final simplex on the
# paper's sphere at lambda = 1e-6 lies 1e-7 off the ray, read as forces 1e-7 off the minimum;
# zc-ie-newton's general Newton finish takes more time there, not less (docs/design.md, "W_Linf's
# lift"); zc-ie's smooth path takes fewer steps.
LIFTED_METHODS = ("ie", "zc-ie", "zc-ie-paper")
# ... and only for a few contacts: an IE step's algebra grows as (m + 5)^2 and the lift's IE steps
# stop halving (grasps on a sphere, lift over sum per call: m = 2 0.71, 4 0.60, 6 0.84, 8 0.99
# since the lift's contact sets are embeddings, benchmarks/results/linf_lift.md; 0.73, 0.71,
# 1.02, 1.28 before); zc-ie's smooth finish takes the lift up to 8 where it lifts (a humanoid's
# foot corners, before they took the sum: 74 -> 32 iterations, 50.9 -> 41.8 us, docs/design.md)
LIFT_MAX_CONTACTS = 8
# singular values of the contacts' maps below this fraction of the largest count as zero: an exact
# deficiency leaves ~1e-16 (the rounding of G_i); where the dropped part spoils an answer, its
# certificate in R^6 fails and the full-dimensional set answers
RANK_TOL = 1e-12
NO_SPAN = np.empty(0)      # the span argument of a set shot in R^6 (core/grasping/forces.hpp)
_UNKNOWN = object()        # a wrench space's span before it is first needed


def contact_kinds(contacts):
    """Per contact 0 frictionless, 1 point, 2 soft."""
    return tuple([(c.mu > 0.0) + (c.mu_spin > 0.0) for c in contacts])


def may_be_deficient(kinds):
    """Whether `wrench_span` examines a grasp of these contacts' kinds: at most two contacts, or
    fewer than six force components (1, 3 and 4 a contact of kind 0, 1 and 2; with three contacts
    or more, m + 2 sum(kinds) < 6 says that, kind 2 never fitting)."""
    return len(kinds) <= 2 or len(kinds) + 2 * sum(kinds) < 6


def wrench_span(kinds, values, length):
    """Q^T (k, 6), Q an orthonormal basis of the range of the contacts' maps (the columns of G_i
    each contact's cone uses: f_1, the tangential forces with friction, the spin moment of a soft
    finger; values: their `grasp_values`) in the units (force, torque / length), when its rank k
    is below 6; None otherwise. An SVD, ~20-30 us: only grasps that `may_be_deficient` are
    examined; a fresh grasp of other kinds pays one sum, and is shot in R^6 even when deficient
    (three collinear point contacts)."""
    matrices = torques_over(contact_matrices(values, len(kinds)), len(kinds), length)
    M = np.hstack([G[:, :(1, 3, 4)[kind]] for G, kind in zip(matrices, kinds)])
    U, s, _ = np.linalg.svd(M)
    k = int(np.count_nonzero(s > RANK_TOL * s[0]))
    return U[:, :k].T.copy() if k < 6 else None


def projection(span, m, lifted):
    """The map from the shot set's space to its image in the span: Q^T on W, block-diag(I, Q^T)
    on the lift (whose first m - 1 coordinates stay)."""
    if not lifted:
        return span
    k = span.shape[0]
    M = np.zeros((m - 1 + k, m + 5))
    M[:m - 1, :m - 1] = np.eye(m - 1)
    M[m - 1:, m - 1:] = span
    return M


class Target:
    """One set that min_force shoots at, compiled, with the table that reads contact forces off
    its witnesses (`graspforce.records._forces`): W itself, or W_Linf's lift, whose t is `t_scale`
    (= m) times W_Linf's, or either's image in the span Q^T (k, 6) of a rank-deficient grasp
    (`span`: Q^T by rows, NO_SPAN for a set in R^6), whose rays use its last `ray_dims` (k, else
    6) coordinates. maps: id(leaf) -> (contact, base, map) for the leaves of the contacts' sets
    (the others are origins: no force)."""

    def __init__(self, shot_set, maps, t_scale, contact_matrices, linf, full, spin_weight,
                 friction, length, span=None):
        self.set = shot_set
        self.t_scale = t_scale
        self.span = NO_SPAN if span is None else span.ravel()
        self.ray_dims = 6 if span is None else span.shape[0]
        table, forces_map = self._table(maps)
        m = contact_matrices.shape[0]
        # entries of the array a min_force call fills: the forces, then the shot's arrays
        self.extra = extra_size(m)
        self.packed_size = self.extra + capacity(self.set.dim, self.set.witness_size)
        # what every min_force call passes to the compiled code after its own arguments
        # (graspforce._core.shoot_and_read_forces), gathered once: ~1 us a call saved
        ints, floats = self.set.program
        self.compiled_args = (ints, floats, force_reader(self.set.witness_size, linf, full,
                                                         contact_matrices, table, forces_map,
                                                         spin_weight, friction, length),
                              self.span)

    def _table(self, maps):
        """(table (4, leaves), maps): per leaf its contact (-1 for an origin), the start of its
        witness slot, its local size and the offset of [base, map] in the returned maps."""
        self.set.program                   # compiles the set, which fills its witness slots
        leaves = self.set.leaves()
        slots = self.set._witness_slots
        table = np.zeros((4, len(leaves)), np.int64)
        blocks = []
        offset = 0
        for j, (leaf, (start, size)) in enumerate(zip(leaves, slots)):
            origin = (-1, np.zeros(4), np.zeros((4, size - 1)))
            contact, base, local_map = maps.get(id(leaf), origin)
            table[:, j] = (contact, start, size - 1, offset)
            blocks.append(np.concatenate((base, local_map.ravel())))
            offset += len(blocks[-1])
        return table, np.concatenate(blocks)


def contact_parts(contacts, magnitude, lifted, matrices):
    """(parts, maps): the root's children of a wrench space's shot set (W_i, or the lift's
    summands) made of the G_i `matrices` (m, 6, 4), and the force maps of their leaves
    (Target)."""
    lift = lift_rows(len(contacts)) if lifted else None
    maps = {}
    parts = []
    for i, contact in enumerate(contacts):
        W_i, base, local_map = contact_set(contact, magnitude, matrices[i])
        for leaf in W_i.leaves():
            maps[id(leaf)] = (i, base, local_map)
        parts.append(lift_summand(W_i, lift[i]) if lifted else W_i)
    return parts, maps


def _root_children(contacts, magnitude, lifted, linf, matrices):
    parts, maps = contact_parts(contacts, magnitude, lifted, matrices)
    if linf and not lifted:
        parts = [hull(Polytope(np.zeros((1, 6))), W_i) for W_i in parts]
    return parts, maps


_FACTORS = {}


def torques_over(values, m, length):
    """values whose first 24 m entries are the G_i (m, 6, 4) (a grasp's `grasp_values`, or the G_i
    themselves) in the units (force, torque / length): a copy with the G_i's torque rows times
    1 / length (the same array for length 1). One product with a cached array of factors: a
    strided division costs ~5 us a grasp, the product 0.7 (the default lengths are powers of
    two, few)."""
    if length == 1.0:
        return values
    key = (values.size, m, length)
    factors = _FACTORS.get(key)
    if factors is None:
        if len(_FACTORS) >= MAX_TEMPLATES:
            _FACTORS.pop(next(iter(_FACTORS)), None)
        factors = _FACTORS[key] = np.ones(values.size)
        factors[:24 * m].reshape(m, 6, 4)[:, 3:] = 1.0 / length
    return values * factors.reshape(values.shape)


def generic_target(contacts, norm, magnitude, contact_matrices, spin_weight, lifted, length=1.0,
                   span=None):
    """The Target of a wrench space built as a tree and compiled by the generic compiler
    (graspforce.geometry.sets): the reference that the templates below reproduce. The set is made in
    the units (force, torque / length) (`Grasp.length`); span: Q^T of a rank-deficient grasp in
    those units (`wrench_span`), whose image of the set is shot."""
    linf = norm == "Linf"
    matrices = torques_over(contact_matrices, len(contacts), length)
    parts, maps = _root_children(contacts, magnitude, lifted, linf, matrices)
    shot_set = minkowski_sum(*parts) if linf and not lifted else hull(*parts)
    if span is not None:
        shot_set = affine(projection(span, len(contacts), lifted), shot_set)
    friction = np.array([(c.mu, c.mu_spin) for c in contacts], dtype=float)
    return Target(shot_set, maps, len(contacts) if lifted else 1, matrices, linf,
                  magnitude == "full", spin_weight, friction, length, span)


class _ContactsRoot:
    """A shot set made by a template (below): its program is set when it is made, and the tree
    of leaves (for witnesses, pickling, queries other than min_force) is built on first read,
    by the same functions as the generic Target's."""

    @property
    def sets(self):
        sets = self.__dict__.get("_sets")
        if sets is None:
            sets = self._sets = tuple(_root_children(*self._made_of)[0])
        return sets

    def __repr__(self):
        return f"{type(self).__mro__[2].__name__}(dim={self.dim})"


class _ContactsHull(_ContactsRoot, Hull):
    pass


class _ContactsSum(_ContactsRoot, MinkowskiSum):
    pass


class _ContactsProjection(_ContactsRoot, Affine):
    """A template's image of the contacts' set in a rank-deficient grasp's span: `matrix` is
    set when it is made, the hull or sum it maps built on first read."""

    @property
    def inner(self):
        inner = self.__dict__.get("_inner")
        if inner is None:
            _, _, lifted, linf, _ = self._made_of
            inner = self._inner = (minkowski_sum if linf and not lifted else hull)(*self.sets)
        return inner


# a contact's entries in a grasp's values after the G_i (`grasp_values`)
_MU, _MU_SPIN, _D_INV, _SPIN_WEIGHT, _PER_CONTACT = 0, 1, 2, 3, 4
_G = 24           # ... and in a contact's entries after its G_i (Contact._g)


def grasp_values(contacts):
    """One array of what a grasp's wrench sets are made of: the G_i (m x 24, row-major), then per
    contact (mu, mu_s, mu_s / mu, (mu / mu_s)^2) (0 for the last two without spin), then 1.0,
    gathered from the entries each contact computed when it was made (Contact._g). A template
    (below) fills a program and its force reader from it by gathers."""
    return _core_grasp_values([c._g for c in contacts])


def contact_matrices(values, m):
    """The G_i of m contacts from their `grasp_values`, (m, 6, 4): a view."""
    return values[:24 * m].reshape(-1, 6, 4)


class _Template:
    """A wrench space's compiled Target for one structure (the contacts' kinds, the magnitude,
    the root's shape): the program's ints, witness slots and the force reader's table do not
    depend on the contacts' values, and their values sit at fixed offsets of the floats and the
    reader. Made once per structure from a generic Target (so the ints are the generic
    compiler's); each new grasp of that structure gets its Target by two copies and two
    gathers from its `grasp_values`: ~4 us for four contacts against ~100-250 us for the tree
    and its compile."""

    def __init__(self, target, kinds, magnitude, lifted, linf):
        ints, floats = target.set.program
        # a projected set (a rank-deficient grasp's) is the affine image of the contacts' root:
        # its map's entries are the grasp's own, written at each target
        self.projected = len(target.span) > 0
        root = children(ints, 0)[0] if self.projected else 0
        self.map_start = param_start(ints, 0) + 2
        reader = target.compiled_args[2]
        # copies taken before any shot: the kernel writes into ints (choice, active) and floats
        # (scratch)
        self.ints, self.floats, self.reader = ints.copy(), floats.copy(), reader.copy()
        self.slots = list(target.set._witness_slots)
        self.witness_size = target.set.witness_size
        self.dim = target.set.dim
        self.t_scale, self.extra, self.packed_size = (target.t_scale, target.extra,
                                                      target.packed_size)
        self.ray_dims = target.ray_dims
        self.made_of = (magnitude, lifted, linf)
        m = len(kinds)
        coef = lambda i, which: 24 * m + _PER_CONTACT * i + which      # noqa: E731
        unit = 24 * m + _PER_CONTACT * m
        # floats[dst] = values[src] * values[scale] + add: add is -0.0 for a copied entry (x +
        # -0.0 is x, zeros' signs included) and +0.0 for a matrix product's (whose zero is +0,
        # whatever the signs of its zero terms)
        dst, src, scale, add = [], [], [], []
        leaves = int(reader[4])
        table = reader[READER_HEAD:READER_HEAD + 4 * leaves].reshape(4, -1).astype(np.int64)
        g_start = READER_HEAD + 4 * leaves
        maps_start = g_start + 27 * m
        # the reader's G_i, spin weights and friction coefficients (mu, then mu_s), copied
        read_dst = list(range(g_start, maps_start))
        read_src = (list(range(24 * m)) + [coef(i, _SPIN_WEIGHT) for i in range(m)]
                    + [coef(i, _MU) for i in range(m)] + [coef(i, _MU_SPIN) for i in range(m)])
        for i, (part, kind) in enumerate(zip(children(ints, root), kinds)):
            # the contact's W_i: the root's child, or its child under a lift's embedding, or
            # the second child of a sum's hull of the origin and W_i
            node = part if not (lifted or linf) else children(ints, part)[-1]
            p = param_start(ints, node)
            axes = _axes(kind, magnitude)
            k = len(axes)
            g = 24 * i
            if magnitude == "normal":
                # [n, k, center (6), shape (6, k)]: center = G_i e_1, shape = G_i @ local_map
                dst += range(p + 2, p + 8)
                src += range(g, g + 24, 4)
                scale += [unit] * 6
                add += [-0.0] * 6
                shape = p + 8
            else:
                # the affine node [6, k, M (6, k), t]: M = G_i @ local_map; its cap [k, mu]
                dst.append(param_start(ints, children(ints, node)[0]) + 1)
                src.append(coef(i, _MU))
                scale.append(unit)
                add.append(-0.0)
                shape = p + 2
            for col, (row, which) in enumerate(axes):
                dst += range(shape + col, shape + 6 * k, k)
                src += range(g + row, g + 24, 4)
                scale += [unit if which is None else coef(i, which)] * 6
                add += [0.0] * 6
            # the reader's [base (4), local_map (4, k)] of this contact's leaf
            j = int(np.flatnonzero(table[0] == i)[0])
            block = maps_start + int(table[3, j]) + 4
            for col, (row, which) in enumerate(axes):
                if which is not None:
                    read_dst.append(block + row * k + col)
                    read_src.append(coef(i, which))
        as_index = lambda values: np.array(values, np.int64)       # noqa: E731
        self.dst, self.src, self.scale = as_index(dst), as_index(src), as_index(scale)
        self.add = np.array(add)
        self.read_dst, self.read_src = as_index(read_dst), as_index(read_src)

    def target(self, contacts, values, length, span=None):
        """The Target of these contacts (of this template's structure) in the units (force,
        torque / length), values their `grasp_values` in those units (`torques_over`); span:
        their Q^T (`wrench_span`) when the template's set is projected."""
        ints, floats, reader = template_arrays(values, self.ints, self.floats, self.reader,
                                               self.dst, self.src, self.scale, self.add,
                                               self.read_dst, self.read_src)
        reader[LENGTH] = length
        magnitude, lifted, linf = self.made_of
        if self.projected:
            cls = _ContactsProjection
            M = projection(span, len(contacts), lifted)
            floats[self.map_start:self.map_start + M.size] = M.ravel()
        else:
            cls = _ContactsSum if linf and not lifted else _ContactsHull
        root = cls.__new__(cls)
        if self.projected:
            root.matrix, root.offset = M, np.zeros(M.shape[0])
        root.dim = self.dim
        matrices = contact_matrices(values, len(contacts))
        root._made_of = (contacts, magnitude, lifted, linf, matrices)
        root._program = (ints, floats)
        root._witness_slots = self.slots
        root._witness_size = self.witness_size
        target = Target.__new__(Target)
        target.set = root
        target.t_scale, target.extra, target.packed_size = (self.t_scale, self.extra,
                                                            self.packed_size)
        target.span = NO_SPAN if span is None else span.ravel()
        target.ray_dims = self.ray_dims
        target.compiled_args = (ints, floats, reader, target.span)
        return target


def _axes(kind, magnitude):
    """[(row of G_i, coefficient)] of a contact's local_map columns (contact_set): kind 0
    frictionless, 1 point, 2 soft; a coefficient None is 1."""
    if magnitude == "normal":
        return [(1, _MU), (2, _MU), (3, _MU_SPIN)][:(0, 2, 3)[kind]]
    return [(0, None), (1, None), (2, None), (3, _D_INV)][:4 if kind == 2 else 3]


_TEMPLATES = {}
MAX_TEMPLATES = 256     # structures kept (a robot's contact sets, a service's grasp shapes)


class WrenchSpace:
    """W (eq. 14) for a list of contacts; values: their `grasp_values`. `set` is W in R^6;
    `target(method)` the compiled set min_force shoots at with that method (W, or W_Linf's lift
    for LIFTED_METHODS, or its image in the span of a rank-deficient grasp's wrenches) in the
    units (force, torque / length) (`Grasp.length`), built on first use."""

    def __init__(self, contacts, norm, magnitude, values, length=1.0):
        self.norm = norm
        self.magnitude = magnitude
        self.length = length
        self._contacts = contacts
        self._values = values
        self._targets = {}
        self._by_method = {}

    @property
    def spin_weight(self):
        """The weight of f_4^2 in ||f||^2 of eq. (15), per contact; point contacts have no
        f_4."""
        return np.array([c._g[_G + _SPIN_WEIGHT] for c in self._contacts])

    @property
    def set(self):
        """W in R^6 (built on first read: min_force on W_Linf's lift does not need it)."""
        return self._target(False, 1.0).set

    def image_in_units(self, shot_set):
        """A shot set in the span, P (D A) (`projection`; D the scaling to the units (force,
        torque / length)), as the same points' image of A in the grasp's units, (P D) A: the
        set of its shot's record (MinForce.shot)."""
        P = shot_set.matrix.copy()
        n = P.shape[1]
        P[:, n - 3:] /= self.length
        return affine(P, self._target(n > 6, 1.0).set)

    def target(self, method, full=False):
        """The Target that min_force shoots at with `method` (a name of gf.METHODS): in the span
        of a rank-deficient grasp's wrenches (`wrench_span`) unless `full`."""
        target = self._by_method.get((method, full))
        if target is None:
            lifted = (self.norm == "Linf" and 1 < len(self._contacts) <= LIFT_MAX_CONTACTS
                      and method in LIFTED_METHODS and not self._sum_finish(method))
            target = self._by_method[(method, full)] = self._target(lifted, self.length,
                                                                    not full)
        return target

    def _sum_finish(self, method):
        """Whether min_force with `method` shoots W_Linf itself, not its lift: zc-ie on contacts
        that all have friction, of the normal magnitude, whose wrenches span R^6: the sum of
        CH({0} U E_i) in R^6 whose Newton finish core/shooting/sum_finish.hpp takes. The lift in
        R^(m+5) has no start table from five contacts, and its IE steps cost (m + 5)^2; on the
        sum, soft fingers around a sphere take 9.7 against 11.3 us (three), 11.4 against 14.3
        (four), 12.8 against 21.9 (five), the ingot 11.2 against 10.4 (docs/design.md, "W_Linf's
        sum"). A grasp shot in its wrenches' span (two point contacts: R^5) keeps the lift, as
        the finish works in R^6."""
        return (method == "zc-ie" and self.magnitude == "normal"
                and min(contact_kinds(self._contacts)) > 0 and self.span is None)

    @property
    def span(self):
        """Q^T of the contacts' wrenches' span, in the units (force, torque / length), when it is
        not R^6 (`wrench_span`), else None; computed on first use."""
        kinds = contact_kinds(self._contacts)
        return self._span_of(kinds) if may_be_deficient(kinds) else None

    def _span_of(self, kinds):
        """`span` of a grasp that `may_be_deficient`, computed once."""
        span = self.__dict__.get("_span", _UNKNOWN)
        if span is _UNKNOWN:
            span = self._span = wrench_span(kinds, self._values, self.length)
        return span

    def _target(self, lifted, length, in_span=False):
        """The Target on W, or on W_Linf's lift, in the units (force, torque / length), or
        (in_span, at the space's length) on its image in the span of a rank-deficient grasp's
        wrenches; built once, from its structure's template (made by the generic compiler at the
        structure's first grasp)."""
        contacts = self._contacts
        kinds = contact_kinds(contacts)
        span = self._span_of(kinds) if in_span and may_be_deficient(kinds) else None
        target = self._targets.get((lifted, length, span is not None))
        if target is None:
            linf = self.norm == "Linf"
            # a projected structure is a template of its own, per dimension of the span
            key = (kinds, self.magnitude, lifted, linf, 6 if span is None else span.shape[0])
            template = _TEMPLATES.get(key)
            if template is not None:
                target = template.target(
                    contacts, torques_over(self._values, len(contacts), length), length, span)
            else:
                target = generic_target(contacts, self.norm, self.magnitude,
                                        contact_matrices(self._values, len(contacts)),
                                        self.spin_weight, lifted, length, span)
                if len(_TEMPLATES) >= MAX_TEMPLATES:
                    _TEMPLATES.pop(next(iter(_TEMPLATES)), None)
                _TEMPLATES[key] = _Template(target, kinds, self.magnitude, lifted, linf)
            self._targets[(lifted, length, span is not None)] = target
        return target
