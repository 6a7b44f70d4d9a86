"""gf.Grasp: minimal contact forces (section 5) and force closure on the exact friction cones."""
import math

import numpy as np

from .._core import (BAD_WRENCH, FULL_SET, HIT, MISS, ZERO_WRENCH, min_force_call,
                     min_force_method, shoot_and_read_forces)
from ..geometry._start_table import UNSEEN, start_table
from .._validate import check_choice, finite_array, finite_scalar, finite_vector
from .contact import Contact
from .quality import facet_expansion, grasp_quality
from ..shooting.ray_shoot import METHODS, check_tolerances
from ..records.results import MinForce, MinForceBatch
from .wrench_space import (MAGNITUDES, NORMS, WrenchSpace, contact_matrices, contact_set,
                           grasp_values)


# min_force's default tolerances: a call that keeps them skips their check
EPS, MAX_ITER = 1e-9, 10000

# the objectives on whose wrench sets min_force's "zc-ie" runs the Newton finish's general path
# (zc-ie-newton's): the smooth path takes no piece of them, and the general path is 5-35% faster
# than the paper's steps there, its p90 lower too (docs/design.md)
GENERAL_FINISH = {("L1", "full")}

# a given length may differ from the contacts' own by at most this factor: far outside it, the
# torques over it overflow or vanish against the forces, and the tolerances mean nothing
LENGTH_RANGE = 1e6


class Grasp:
    """m contacts on one object (a hand's fingertips, a robot's feet), in one frame.

    matrix: the grasp map [G_1 ... G_m] of eq. (11), (6, 4m); a wrench is (force, torque about
    the frame's origin); contact_matrices: the G_i stacked, (m, 6, 4). Wrench sets are built on
    first use and cached per (norm, magnitude).

    length: the grasp's characteristic length L (in the unit of the positions, within a factor
    LENGTH_RANGE of the default): min_force shoots the wrench set in the units (force,
    torque / L), where its tolerances hold whatever the unit of length (docs/grasp-api.md,
    "Units"). By default the power of two nearest to 2
    times the RMS over the contacts of sqrt(|p_i|^2 + mu_si^2), their lever arms about the
    frame's origin (1 if all are 0): a power of two scales without rounding, and the factor 2 is
    measured (docs/design.md, "The unit of length").
    """

    def __init__(self, contacts, length=None):
        contacts = tuple(contacts)
        if not contacts:
            raise ValueError("contacts: a grasp needs at least one contact")
        for c in contacts:
            if not isinstance(c, Contact):
                raise TypeError(f"contacts: expected gf.Contact, got {type(c).__name__}")
        self.contacts = contacts
        if length is not None:
            if not (type(length) is float and 0.0 < length < math.inf):
                length = finite_scalar(length, "length", minimum=0.0, exclusive=True)
            own = self._own_length()
            if not own / LENGTH_RANGE <= length <= own * LENGTH_RANGE:
                raise ValueError(f"length: must be within a factor {LENGTH_RANGE:g} of the "
                                 f"contacts' own length {own:g} (the default), got {length!r}")
        self._length = length
        # what the wrench sets are made of, G_i first
        # (graspforce.grasping.wrench_space.grasp_values): one array for all, from the entries each
        # contact computed when it was made
        self._values = grasp_values(contacts)
        self._spaces = {}
        self._calls = {}
        self._compiled = {}

    def __len__(self):
        return len(self.contacts)

    def __getstate__(self):
        # the wrench spaces are caches built on first use, and hold compiled entry points that do
        # not pickle
        return {**self.__dict__, "_spaces": {}, "_calls": {}, "_compiled": {}}

    @property
    def length(self):
        """The characteristic length L (class docstring), derived on first read if not given."""
        if self._length is None:
            self._length = self._own_length()
        return self._length

    def _own_length(self):
        """The default length (class docstring) of these contacts."""
        arms = 0.0
        for c in self.contacts:
            arms += c._arm2     # ||p||^2 + mu_s^2, computed when the contact was made
        if arms == 0.0:
            return 1.0
        fraction, exponent = math.frexp(2.0 * math.sqrt(arms / len(self.contacts)))
        return math.ldexp(1.0, exponent - (fraction < math.sqrt(0.5)))

    @property
    def contact_matrices(self):
        """The G_i stacked, (m, 6, 4): a view of the grasp's values."""
        return contact_matrices(self._values, len(self.contacts))

    @property
    def matrix(self):
        """[G_1 ... G_m] of eq. (11), (6, 4m): maps the stacked local forces to the resultant."""
        return np.hstack(self.contact_matrices)

    def contact_sets(self, magnitude="normal"):
        """[W_1, ..., W_m]: each contact's wrenches at unit force magnitude (eq. 14)."""
        check_choice(magnitude, MAGNITUDES, "magnitude")
        return [contact_set(c, magnitude)[0] for c in self.contacts]

    def wrench_set(self, norm="L1", magnitude="normal"):
        """W_L1 or W_Linf of eq. (14) (NOTES.md item 2 for Linf) as a convex set in R^6."""
        return self._space(norm, magnitude).set

    def _space(self, norm, magnitude):
        key = (check_choice(norm, NORMS, "norm"), check_choice(magnitude, MAGNITUDES, "magnitude"))
        space = self._spaces.get(key)
        if space is None:
            space = self._spaces[key] = WrenchSpace(self.contacts, norm, magnitude, self._values,
                                                    self.length)
            space.shoot = shoot_and_read_forces
        return space

    def min_force(self, w_ext, norm="L1", magnitude="normal", method="zc-ie", eps=EPS,
                  max_iter=MAX_ITER):
        """Contact forces in the friction cones that resist w_ext with the least overall magnitude.

        w_ext: the external wrench (force, torque about the frame's origin), (6,); the contacts
        must supply -w_ext (eq. 11). norm "L1" minimizes the sum over contacts, "Linf" the
        maximum; magnitude "normal" measures a contact by its normal force f_1 (eq. 13), "full" by
        ||f|| (eq. 15). The minimum is 1/t for the farthest point t r of W (eq. 14) on the ray
        R(r), r = -w_ext, found by `method` (any of gf.METHODS) to relative accuracy eps; the
        forces are read off the witnesses of Z_W(r). For Linf, IE and ZC-IE shoot the ray (0, r)
        at W_Linf's lift in R^(m + 5) (graspforce.grasping.wrench_space), where IE needs half the
        steps; ZC-IE on contacts that all have friction (normal magnitude, wrenches spanning R^6)
        shoots W_Linf itself, with a Newton finish on the contacts' states
        (core/shooting/sum_finish.hpp). On two soft fingers (L1, normal magnitude) ZC-IE's first
        point on the ray is followed by the exit in closed form (core/shooting/pair_exit.hpp). A
        grasp whose wrenches span only R^k, k < 6 (two point contacts), is shot in that span
        (the set Q^T W, the ray Q^T r); a load outside it, or a shot there that ends
        uncertified, at the full-dimensional set.
        """
        # The common call (these tolerances' defaults, and a compiled call made below for its
        # settings) does not come here: the method standing for this one in the class answers
        # it with that compiled call (core/python/min_force_method.hpp, min_force_call.hpp)
        key = (norm, magnitude, method)
        if (eps is EPS or type(eps) is float and eps == EPS) and (
                max_iter is MAX_ITER or type(max_iter) is int and max_iter == MAX_ITER):
            eps, max_iter = EPS, MAX_ITER   # the defaults' values need no check below
        try:
            call = self._calls.get(key)
        except TypeError:          # an unhashable argument: _call names it
            call = None
        if call is None:
            call = self._call(norm, magnitude, method)
        space, code, shoot, args, A, size, extra, t_scale, ray_dims = call
        if eps is not EPS or max_iter is not MAX_ITER:   # the defaults need no check
            eps, max_iter = check_tolerances(eps, max_iter)
        start = start_table(A, ray_dims)
        if (start is A._start_table and eps is EPS and max_iter is MAX_ITER
                and key not in self._compiled):
            # the table settled (built, or none to build): later calls of these settings take
            # the compiled call
            self._compiled[key] = min_force_call(
                MinForce, (norm, magnitude, method, "optimal", "max_iter", "infeasible"),
                (A, extra, space), code, EPS, MAX_ITER, size, start, *args, t_scale,
                len(self.contacts))
        packed = np.empty(size)
        # the common call, a float64 (6,) array, goes straight to the compiled code, which
        # checks it too; anything else (which the compiled code does not take: a TypeError), or
        # a refused wrench, is converted or refused here
        try:
            head = shoot(w_ext, code, eps, max_iter, packed, start, *args)
        except TypeError:
            head = None
        if head is None or head[0] == BAD_WRENCH:
            # a new C-contiguous float64 array: the type the compiled code takes
            w_ext = np.array(finite_vector(w_ext, "w_ext", 6)[0])
            head = shoot(w_ext, code, eps, max_iter, packed, start, *args)
        status = head[0]
        if status == FULL_SET:
            # a load beyond the span of a rank-deficient grasp's wrenches, or a shot in it that
            # did not certify: the full-dimensional set answers (as it does without a span)
            space, code, shoot, args, A, size, extra, t_scale, ray_dims = (
                self._calls.get((norm, magnitude, method, True))
                or self._call(norm, magnitude, method, True))
            packed = np.empty(size)
            head = shoot(w_ext, code, eps, max_iter, packed, start_table(A, ray_dims), *args)
            status = head[0]
        if status == ZERO_WRENCH:
            return self._without_forces(space, "optimal", 0.0, method, None)
        sigma = packed.item(0)
        ray = (A, w_ext, head, packed, extra, space)
        if status == MISS:
            # a separating hyperplane (or a ray that leaves W at the origin): no finite forces
            return self._without_forces(space, "infeasible", math.inf, method, ray, t_scale)
        if sigma == math.inf:
            return self._without_forces(space, "max_iter", math.inf, method, ray, t_scale)
        # "optimal" only with the certificate the compiled call checked (core/grasping/forces.hpp)
        return MinForce.from_packed("optimal" if status == HIT else "max_iter", sigma,
                                    1.0 / (t_scale * head[2]), norm, magnitude, method, ray,
                                    len(self.contacts))

    def min_force_batch(self, wrenches, norm="L1", magnitude="normal", method="zc-ie", eps=EPS,
                        max_iter=MAX_ITER, forces=False):
        """min_force for each row of `wrenches` (k, 6): a MinForceBatch of sigma, sigma_lower,
        status, feasible and iterations per wrench (and the (k, m, 4) local forces if `forces`),
        with summary statistics. The rows are one compiled parallel loop (gf.batch.min_force);
        each entry equals min_force(wrenches[i], ...) on a grasp shot before (its start table
        built)."""
        from ..batch.forces import min_force as min_force_rows
        W = finite_array(wrenches, "wrenches", ndim=2)
        if W.shape[1] != 6:
            raise ValueError(f"wrenches: expected shape (k, 6), got {W.shape}")
        res = min_force_rows(self, W, norm, magnitude, method, eps, max_iter, forces)
        return MinForceBatch(res.sigma, res.sigma_lower, res.status_names.tolist(), res.feasible,
                             res.iterations, res.forces, norm, magnitude, method)

    def reset_start_tables(self):
        """Return the grasp's wrench sets to their never-shot state: the next min_force (or
        min_force_batch) answers exactly as a new Grasp of the same contacts would. A set's
        start table, built at its second shot (docs/core-api.md, "Repeated shots"), changes
        the path to an answer and so its last digits, within eps. The service calls this
        before every answer from a cached grasp, so that an answer depends on its request
        alone and equals the library's first call."""
        self._compiled.clear()
        for space in self._spaces.values():
            for target in space._targets.values():
                target.set._start_table = UNSEEN

    def _call(self, norm, magnitude, method, full=False):
        """What min_force needs of one (norm, magnitude, method), checked and gathered once: the
        wrench space, the method's code, the compiled entry point and its constant arguments,
        and of the target (graspforce.grasping.wrench_space.Target) its set, packed size, extra
        entries, t_scale and ray dimensions. One lookup a call instead of four and their attributes:
        with the slotted MinForce, the Python around the compiled call went from ~1.9 to ~1.4 us.
        full: the target in R^6 even when the grasp's wrenches span less (for loads outside
        the span), kept under the key (norm, magnitude, method, True)."""
        code = METHODS[check_choice(method, METHODS, "method")]
        space = self._space(norm, magnitude)
        if method == "zc-ie" and (space.norm, space.magnitude) in GENERAL_FINISH:
            code = METHODS["zc-ie-newton"]
        target = space.target(method, full)
        key = (norm, magnitude, method, True) if full else (norm, magnitude, method)
        call = self._calls[key] = (
            space, code, space.shoot, target.compiled_args, target.set, target.packed_size,
            target.extra, target.t_scale, target.ray_dims)
        return call

    def _without_forces(self, space, status, sigma, method, ray, t_scale=1):
        """The record of a zero wrench (sigma 0), an infeasible one or an undecided one (inf);
        t_scale: the shot set's (graspforce.grasping.wrench_space.Target)."""
        m = len(self.contacts)
        lower = sigma
        if ray is not None and status == "max_iter":
            t_up = ray[2][2]
            lower = 1.0 / (t_scale * t_up) if t_up > 0.0 else 0.0
        return MinForce.without_forces(sigma == 0.0, status, sigma, lower, space.norm,
                                       space.magnitude, method, ray, m)

    def is_force_closure(self, tol=1e-9, max_iter=2000):
        """Whether the contacts can resist every wrench: the origin is interior to W (eq. 14).

        Certified either way (graspforce.grasping.quality): True once a polytope of support points
        of W holds the origin strictly inside; False once a direction u with h_W(u) <= tol * size(W)
        is found (the wrench -u cannot be resisted, or needs unbounded force). The answer does
        not depend on the norm or magnitude (the cones are the same); W_L1 is the cheapest.
        False too if max_iter steps decide neither (the origin within about tol of W's boundary).
        """
        W = self.wrench_set("L1", "normal")
        return bool(facet_expansion(W, 0.0, tol, max_iter, stop_at_closure=True)[0])

    def quality(self, norm="L1", magnitude="normal", eps=1e-3, tol=1e-9, max_iter=500):
        """The Ferrari-Canny quality: the largest Q such that every wrench of norm <= Q is resisted
        by contact forces of overall magnitude <= 1 (measured by norm and magnitude, eq. 13/15),
        i.e. the radius of the largest origin-centred ball in W. Bracketed to relative eps by
        facet expansion (graspforce.grasping.quality); 0 when the grasp is not force-closure. In R^6
        a polytope inside a curved W needs ~eps^(-5/2) points to come within eps of it, so tight
        brackets are expensive (1e-4: ~1 s on a 3-finger grasp); after max_iter steps the
        current, still certified, bracket is returned.
        """
        return grasp_quality(self.wrench_set(norm, magnitude), norm, magnitude, eps, tol,
                             max_iter)

    def __repr__(self):
        return f"Grasp({len(self.contacts)} contacts)"


# A reused grasp's min_force with the default tolerances calls its compiled call from a method
# written in C, without the Python method's frame (~0.2 us of a ~7 us call); every other call
# reaches the Python method above with its own arguments (core/python/min_force_method.hpp)
Grasp.min_force = min_force_method(Grasp, Grasp.min_force)
