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

min_force with IE or ZC-IE on up to LIFT_MAX_CONTACTS contacts does not shoot at the sum itself
but at its lift, one dimension per contact up (the Cayley embedding of the summands
A_i = CH({0} U W_i)):

    C = CH( {e_1} x A_1  U ... U  {e_m} x A_m ) - (c, 0),   c = (1/m, ..., 1/m),

with the first m - 1 of the coordinates e kept (they sum to 1). A point of C with e-part 0 is
(1/m) sum_i a_i with a_i in A_i, so the ray (0, r) leaves C at t' with t = m t' on W_Linf. IE's
facets in C combine the contacts' support points freely, where a facet of the sum is made of n
sums of m points each: a cutting-plane model of each summand instead of one of their sum. On the
ingot grasp IE needs 28 steps on C (R^9) against 63 on the sum (R^6) at eps = 1e-9
(BENCHMARKS.md, "The Linf lift"). A vertex of C is one contact's wrench (or the origin), so the
forces are read off as for W_L1: f_i = sum_k (lam_k / t') u_ki over the vertices of contact i,
whose weights sum to 1/m.
"""
import numpy as np

from ._core import capacity, extra_size
from ._forces import force_reader
from .sets import ConeCap, Ellipsoid, Polytope, affine, hull, minkowski_sum

NORMS = ("L1", "Linf")
MAGNITUDES = ("normal", "full")


def contact_set(contact, magnitude):
    """(W_i, base, local_map): the wrench set of one contact and how its leaf's witness maps to a
    unit contact force, f = base + local_map @ local."""
    if magnitude == "normal":
        # the ellipse's axes: only the friction components this contact has
        axes = [(1, contact.mu), (2, contact.mu)] if contact.mu > 0.0 else []
        if contact.mu_spin > 0.0:
            axes.append((3, contact.mu_spin))
        local_map = np.zeros((4, len(axes)))
        for col, (row, coefficient) in enumerate(axes):
            local_map[row, col] = coefficient
        base = np.array([1.0, 0.0, 0.0, 0.0])
        W_i = Ellipsoid(contact.matrix[:, 0], contact.matrix @ local_map)
    else:
        # full magnitude: g = D f lives in the cone of the contact's own dimension
        size = 4 if contact.mu_spin > 0.0 else 3
        local_map = np.zeros((4, size))
        local_map[:3, :3] = np.eye(3)
        if size == 4:
            local_map[3, 3] = contact.mu_spin / contact.mu       # D^{-1}
        base = np.zeros(4)
        W_i = affine(contact.matrix @ local_map, ConeCap(contact.mu, size))
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
# the Newton finish takes more time there, not less (BENCHMARKS.md, "The Linf lift").
LIFTED_METHODS = ("ie", "zc-ie")
# ... and only for a few contacts: an IE step's algebra grows as (m + 5)^2 and the lift's steps
# stop halving (grasps on a sphere, lift over sum per call: m = 2 0.71, 4 0.60, 6 0.84, 8 0.99
# since the lift's contact sets are embeddings, benchmarks/results/linf_lift.md; 0.73, 0.71,
# 1.02, 1.28 before)
LIFT_MAX_CONTACTS = 6


class Target:
    """One set that min_force shoots at, compiled, with the table that reads contact forces off
    its witnesses (`graspforce._forces`): W itself, or W_Linf's lift, whose t is `t_scale`
    (= m) times W_Linf's. maps: id(leaf) -> (contact, base, map) for the leaves of the
    contacts' sets (the others are origins: no force)."""

    def __init__(self, shot_set, maps, t_scale, contact_matrices, linf, full, spin_weight,
                 friction):
        self.set = shot_set
        self.t_scale = t_scale
        table, forces_map = self._table(maps)
        m = contact_matrices.shape[0]
        # entries of the array a min_force call fills: the forces, then the shot's arrays
        self.extra = extra_size(m)
        self.packed_size = self.extra + capacity(self.set.dim, self.set.witness_size)
        # what every min_force call passes to the compiled code after its own arguments
        # (graspforce._forces.SIGNATURE), gathered once: ~1 us a call saved
        ints, floats = self.set.program
        self.compiled_args = (ints, floats, force_reader(self.set.witness_size, linf, full,
                                                         contact_matrices, table, forces_map,
                                                         spin_weight, friction))

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


class WrenchSpace:
    """W (eq. 14) for a list of contacts; contact_matrices: the contacts' G_i, (m, 6, 4).
    `set` is W in R^6; `target(method)` the compiled set min_force shoots at with that method
    (W, or W_Linf's lift for LIFTED_METHODS), built on first use."""

    def __init__(self, contacts, norm, magnitude, contact_matrices):
        self.norm = norm
        self.magnitude = magnitude
        self._contacts = contacts
        self._matrices = contact_matrices
        # the weight of f_4^2 in ||f||^2 of eq. (15); point contacts have no f_4
        self.spin_weight = np.array([(c.mu / c.mu_spin) ** 2 if c.mu_spin > 0.0 else 0.0
                                     for c in contacts])
        self.friction = np.array([(c.mu, c.mu_spin) for c in contacts], dtype=float)
        self._targets = {}
        self._by_method = {}
        self.set = self._target(False).set

    def target(self, method):
        """The Target that min_force shoots at with `method` (a name of gf.METHODS)."""
        target = self._by_method.get(method)
        if target is None:
            target = self._by_method[method] = self._target(
                self.norm == "Linf" and 1 < len(self._contacts) <= LIFT_MAX_CONTACTS
                and method in LIFTED_METHODS)
        return target

    def _target(self, lifted):
        """The Target on W, or on W_Linf's lift; built once."""
        target = self._targets.get(lifted)
        if target is None:
            m = len(self._contacts)
            lift = lift_rows(m) if lifted else None
            maps = {}
            parts = []
            for i, contact in enumerate(self._contacts):
                W_i, base, local_map = contact_set(contact, self.magnitude)
                for leaf in W_i.leaves():
                    maps[id(leaf)] = (i, base, local_map)
                parts.append(lift_summand(W_i, lift[i]) if lifted else W_i)
            linf = self.norm == "Linf"
            if linf and not lifted:
                shot_set = minkowski_sum(*[hull(Polytope(np.zeros((1, 6))), W_i)
                                           for W_i in parts])
            else:
                shot_set = hull(*parts)
            target = self._targets[lifted] = Target(
                shot_set, maps, m if lifted else 1, self._matrices, linf,
                self.magnitude == "full", self.spin_weight, self.friction)
        return target
