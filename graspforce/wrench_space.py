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
"""
import numpy as np

from ._forces import extra_size
from ._packed import capacity
from .sets import ConeCap, Ellipsoid, Polytope, affine, hull, minkowski_sum

NORMS = ("L1", "Linf")
MAGNITUDES = ("normal", "full")


def contact_set(contact, magnitude):
    """(W_i, base, local_map): the wrench set of one contact and how its leaf's witness maps to a
    unit contact force, f = base + local_map @ local."""
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
        return Ellipsoid(G[:, 0].copy(), G @ local_map), base, local_map
    # full magnitude: g = D f lives in the cone of the contact's own dimension
    size = 4 if contact.mu_spin > 0.0 else 3
    local_map = np.zeros((4, size))
    local_map[:3, :3] = np.eye(3)
    if size == 4:
        local_map[3, 3] = contact.mu_spin / contact.mu       # D^{-1}
    return affine(G @ local_map, ConeCap(contact.mu, size)), np.zeros(4), local_map


class WrenchSpace:
    """W (eq. 14) for a list of contacts, compiled once, with the table that reads contact
    forces off a witness (`graspforce._forces`); contact_matrices: the contacts' G_i, (m, 6, 4)."""

    def __init__(self, contacts, norm, magnitude, contact_matrices):
        self.norm = norm
        self.magnitude = magnitude
        maps = {}                                   # id(leaf) -> (contact index, base, map)
        parts = []
        for i, contact in enumerate(contacts):
            W_i, base, local_map = contact_set(contact, magnitude)
            for leaf in W_i.leaves():
                maps[id(leaf)] = (i, base, local_map)
            parts.append(W_i)
        if norm == "L1":
            self.set = hull(*parts)
        else:
            origin = np.zeros((1, 6))
            self.set = minkowski_sum(*[hull(Polytope(origin), W_i) for W_i in parts])
        self._table(maps)
        # the weight of f_4^2 in ||f||^2 of eq. (15); point contacts have no f_4
        self.spin_weight = np.array([(c.mu / c.mu_spin) ** 2 if c.mu_spin > 0.0 else 0.0
                                     for c in contacts])
        # entries of the array a min_force call fills: the forces, then the shot's arrays
        self.extra = extra_size(len(contacts))
        self.packed_size = self.extra + capacity(6, self.set.witness_size)
        # what every min_force call on this space passes to the compiled code after its own
        # arguments (graspforce._forces.SIGNATURE), gathered once: ~1 us a call saved
        ints, floats = self.set.program
        self.compiled_args = (ints, floats, self.set.witness_size, contact_matrices, self.table,
                              self.maps, norm == "Linf", magnitude == "full", self.spin_weight)

    def _table(self, maps):
        """table (4, leaves): per leaf its contact (-1 for the origin of CH({0} U W_i)), the
        start of its witness slot, its local size and the offset of [base, map] in `maps`."""
        self.set.program                   # compiles the set, which fills its witness slots
        leaves = self.set.leaves()
        slots = self.set._witness_slots
        self.table = np.zeros((4, len(leaves)), np.int64)
        blocks = []
        offset = 0
        for j, (leaf, (start, size)) in enumerate(zip(leaves, slots)):
            origin = (-1, np.zeros(4), np.zeros((4, size - 1)))
            contact, base, local_map = maps.get(id(leaf), origin)
            self.table[:, j] = (contact, start, size - 1, offset)
            blocks.append(np.concatenate((base, local_map.ravel())))
            offset += len(blocks[-1])
        self.maps = np.concatenate(blocks)
