"""Result records. Each carries the bounds that certify it, so it can be checked without
trusting the code that made it."""
import math
from dataclasses import dataclass, field, fields
from functools import cached_property

import numpy as np

from .._core import HEAD, HIT, LIMIT, MISS
from ._forces import force_views
from ._packed import unpack

_STATUS = {HIT: "hit", MISS: "miss", LIMIT: "max_iter"}


def _num(x):
    """A float for JSON: None stands for an infinite value (JSON has no inf) or, in a
    baseline's record, NaN (no certified bound)."""
    x = float(x)
    return x if math.isfinite(x) else None


def _inf(x, sign=1.0):
    """The float of a JSON number; None reads back as +inf (or -inf with sign -1)."""
    return sign * math.inf if x is None else float(x)


def _array(x, shape=None):
    a = np.array(x, dtype=float)
    return a.reshape(shape) if shape is not None else a


def _witness_to_json(witness):
    return [[j, local if isinstance(local, int) else np.asarray(local).tolist()]
            for j, local in witness]


def _witness_from_json(items):
    return tuple((int(j), local if isinstance(local, int) else np.array(local, dtype=float))
                 for j, local in items)


class RayShot:
    """The answer to the ray-shooting problem of section 2.1 for A and R(r).

    point = z_A(r) = t r is the convex combination `weights` of `vertices` = Z_A(r), points of A
    (each with its `witnesses`). The hyperplane {x : normal^T x = support_value}, with
    support_value = h_A(normal), supports A and meets the ray at t_upper r, so the true z_A(r)
    lies between t r and t_upper r and ||z_A(r) - point|| <= error_bound = (t_upper - t) ||r||.
    On a miss, normal^T r > 0 >= support_value certifies that the ray and A do not meet
    (support_value is exactly 0 only for a ray grazing CO(A) to rounding).
    singular_steps counts the iterations in which the ray crossed the inner polytope through a
    face of dimension < n - 1: IE's facet-collection steps, ZC-IE's hand-overs to ZC-based
    iterations (section 3.2, 3.4.2); 0 for the other methods.
    The arrays are views of the one array the compiled shooter filled (graspforce.records._packed),
    taken when first read: a caller who needs only t pays for none of them. Read-only.
    """

    def __init__(self, convex_set, r, method, hit, status, head, packed, extra=0):
        self.convex_set = convex_set
        self.r = r
        self.method = method
        self.hit = hit
        self.status = status
        _, self.t, self.t_upper, self.support_value, self.iterations, self.support_calls, \
            self.singular_steps, self._k = head
        self._packed = packed
        self._extra = extra

    @classmethod
    def from_packed(cls, A, r, method, head, packed, extra=0):
        """The RayShot of a compiled result: `head` its scalars (graspforce._core.HEAD of them),
        `packed` its arrays after `extra` entries of the caller's."""
        return cls(A, r, method, head[0] == HIT, _STATUS[head[0]], head, packed, extra)

    @cached_property
    def _arrays(self):
        self._packed.flags.writeable = False
        return unpack(self._packed, self._extra, self.r.shape[0], self.convex_set.witness_size,
                      self._k)

    @property
    def normal(self):
        return self._arrays[0]

    @property
    def weights(self):
        return self._arrays[1]

    @property
    def vertices(self):
        return self._arrays[2]

    @property
    def witness_rows(self):
        """Raw witness vectors, one row per vertex."""
        return self._arrays[3]

    @cached_property
    def point(self):
        return self.t * self.r

    @property
    def error_bound(self):
        return (self.t_upper - self.t) * float(np.sqrt(self.r @ self.r)) if self.hit else np.inf

    @cached_property
    def witnesses(self):
        """One decoded witness per vertex: ((leaf_index, local), ...)."""
        return tuple(self.convex_set.decode_witness(w) for w in self.witness_rows)

    def to_dict(self):
        """The record as JSON-ready values (lists, numbers, None for an infinite number), what
        the service sends; RayShot.from_dict reads it back."""
        return {"hit": bool(self.hit), "status": self.status, "method": self.method,
                "r": np.asarray(self.r, dtype=float).tolist(), "t": _num(self.t),
                "t_upper": _num(self.t_upper), "point": self.point.tolist(),
                "support_value": _num(self.support_value), "normal": self.normal.tolist(),
                "vertices": self.vertices.tolist(), "weights": self.weights.tolist(),
                "witnesses": [_witness_to_json(w) for w in self.witnesses],
                "witness_rows": self.witness_rows.tolist(),
                "iterations": int(self.iterations), "support_calls": int(self.support_calls),
                "singular_steps": int(self.singular_steps)}

    @classmethod
    def from_dict(cls, d, convex_set=None):
        """The record of `to_dict`'s output; `convex_set` (the set shot at) is kept if given."""
        record = cls.__new__(cls)
        record.convex_set = convex_set
        record.r = _array(d["r"])
        n = record.r.shape[0]
        record.method, record.hit, record.status = d["method"], bool(d["hit"]), d["status"]
        record.t, record.t_upper = _inf(d["t"]), _inf(d["t_upper"])
        record.support_value = _inf(d["support_value"])
        record.iterations, record.support_calls = int(d["iterations"]), int(d["support_calls"])
        record.singular_steps = int(d["singular_steps"])
        weights = _array(d["weights"])
        record._k = k = weights.shape[0]
        rows = _array(d["witness_rows"])
        # cached properties read from the instance dict: the arrays are the sent ones
        record.__dict__["_arrays"] = (_array(d["normal"]), weights,
                                      _array(d["vertices"], (k, n)),
                                      rows.reshape(k, rows.size // k if k else 0))
        record.__dict__["witnesses"] = tuple(_witness_from_json(w) for w in d["witnesses"])
        record.__dict__["point"] = _array(d["point"])
        record._packed, record._extra = None, 0
        return record

    def __repr__(self):
        return (f"RayShot(hit={self.hit}, status={self.status!r}, method={self.method!r}, "
                f"t={self.t!r}, t_upper={self.t_upper!r}, iterations={self.iterations})")


@dataclass(frozen=True)
class ClosestPoint:
    """d_A(b) and v_A(b) of eq. (3) from GJK (section 2.2). `point` = weights @ vertices; the
    hyperplane with normal (b - point)/distance through s_A(normal) supports A, so the true
    distance is at least distance - gap."""
    distance: float
    point: np.ndarray
    vertices: np.ndarray
    weights: np.ndarray
    witnesses: tuple
    gap: float
    status: str
    iterations: int
    support_calls: int


@dataclass(frozen=True)
class ConeDistance:
    """d_CO(A)(b) and v_CO(A)(b) from ZC (section 2.3). `point` = coefficients @ vertices with
    linearly independent vertices and positive coefficients. When b is outside, h_A(normal)
    = support_value and the true distance is at least distance - support_value."""
    distance: float
    point: np.ndarray
    vertices: np.ndarray
    coefficients: np.ndarray
    witnesses: tuple
    normal: np.ndarray
    support_value: float
    status: str
    iterations: int
    support_calls: int


_NO_SHOT = (0, 0.0, 0.0, 0.0, 0, 0, 0, 0)   # the head of a call that shot nothing (a zero wrench)
_HEAD_INTS = (0, 4, 5, 6, 7)                # the head's integer entries (status, counts, k)


def _packed_array(packed):
    """A packed answer as an array: the compiled call's bytes (read-only, not copied), or the
    array itself."""
    return np.frombuffer(packed) if type(packed) is bytes else packed


def _force_array(index, doc):
    """A MinForce array, read from the packed answer on first access."""
    return property(lambda record: record._arrays()[index], doc=doc)


class MinForce:
    """Minimal contact forces that resist an external wrench (section 5.1, eq. 11-15).

    `sigma` is the objective (eq. 13 or 15: sum or max of the contacts' normal forces, or of their
    full magnitudes) of `forces`, which lie in their friction cones and whose resultant is
    -w_ext. The true minimum lies in [sigma_lower, sigma]: with z = t r (r = -w_ext) the point of
    the ray in the wrench set W found by ray shooting and t_upper from its supporting hyperplane,
    sigma = 1/t and sigma_lower = 1/t_upper (eq. 14 scales W by sigma; for Linf, t = m t' of
    the shot at W_Linf's lift, `shot`). Baselines report their solver's dual bound, or NaN when
    it certifies none (graspforce.grasping.baselines).
    status: "optimal" (sigma / sigma_lower - 1 <= eps), "infeasible" (no forces in the cones
    resist w_ext: the wrench part n of `shot.normal` satisfies h_W(n) <= 0 < n^T r, a
    separating hyperplane),
    "max_iter" (feasible: `forces` resist w_ext, but the bracket did not close to eps).
    forces: (m, 4) local (f_1, f_2, f_3, f_4) = (normal force, two tangential, spin moment),
    read off the witnesses of the final simplex Z_W(r), not re-solved. world_forces: (m, 3) the
    force vectors in the world frame; wrenches: (m, 6) G_i f_i; resultant: sum of the wrenches.
    Infinite sigma and zero forces when infeasible. `shot` is the underlying RayShot.
    The force arrays of a ray-shooting answer are views of the one array the compiled code
    filled (graspforce.records._packed), taken when first read; read-only.
    """

    # slots: min_force builds one record per call, and slot stores cost about half a dict's
    # (0.1-0.3 us of a ~8 us call, timed over a pass of 1000 wrenches); _forces and _shot are
    # left unset until first read. A reused grasp's compiled call (core/python/min_force_call.hpp)
    # writes the slots that from_packed sets, found by name: a slot from_packed sets is one it
    # must set too
    __slots__ = ("feasible", "status", "sigma", "sigma_lower", "norm", "magnitude", "method",
                 "iterations", "support_calls", "_ray", "_contacts", "_forces", "_shot")

    def __init__(self, feasible, status, sigma, sigma_lower, forces, world_forces, wrenches,
                 resultant, norm, magnitude, method, iterations, support_calls, ray=None):
        self.feasible, self.status, self.sigma, self.sigma_lower = (feasible, status, sigma,
                                                                    sigma_lower)
        self.norm, self.magnitude, self.method = norm, magnitude, method
        self.iterations, self.support_calls = iterations, support_calls
        self._ray = ray
        self._forces = (forces, world_forces, wrenches, resultant)

    @property
    def ray(self):
        """(W, w_ext, head, packed, extra, wrench space) of the shot (graspforce.records._packed;
        the space's length, Grasp.length, is the unit the shot at W was made in); None for a
        zero wrench or a baseline's answer. The compiled call (core/python/min_force_call.hpp)
        leaves head None and packed a bytes object [packed, head], decoded here when first
        read."""
        ray = self._ray
        if ray is not None and ray[2] is None:
            packed = _packed_array(ray[3])
            head = packed[-HEAD:].tolist()
            for i in _HEAD_INTS:
                head[i] = int(head[i])
            ray = self._ray = (ray[0], ray[1], tuple(head), packed, ray[4], ray[5])
        return ray

    @classmethod
    def from_packed(cls, status, sigma, sigma_lower, norm, magnitude, method, ray, m,
                    feasible=True, head=None):
        """The answer of a ray shot whose packed array holds the forces of m contacts
        (graspforce.records._forces); the arrays are read on first use. head: the shot's (ray's
        own by default)."""
        head = ray[2] if head is None else head
        record = cls.__new__(cls)
        record.feasible = feasible
        record.status = status
        record.sigma = sigma
        record.sigma_lower = sigma_lower
        record.norm = norm
        record.magnitude = magnitude
        record.method = method
        record.iterations = head[4]
        record.support_calls = head[5]
        record._ray = ray
        record._contacts = m
        return record

    @classmethod
    def without_forces(cls, feasible, status, sigma, sigma_lower, norm, magnitude, method, ray,
                       m):
        """An answer without contact forces (a zero wrench: no ray; an infeasible or undecided
        one) for m contacts: its force arrays are zeros, made on first use."""
        record = cls.from_packed(status, sigma, sigma_lower, norm, magnitude, method, ray, m,
                                 feasible, _NO_SHOT if ray is None else ray[2])
        record._forces = None
        return record

    def _arrays(self):
        try:
            forces = self._forces
        except AttributeError:
            packed = _packed_array(self._ray[3])
            packed.flags.writeable = False
            forces, wrenches, resultant = force_views(packed, self._contacts)
            self._forces = (forces, wrenches[:, :3], wrenches, resultant)
            return self._forces
        if forces is None:
            m = self._contacts
            forces = self._forces = (np.zeros((m, 4)), np.zeros((m, 3)), np.zeros((m, 6)),
                                     np.zeros(6))
        return forces

    forces = _force_array(0, "(m, 4) local (normal force, two tangential forces, spin moment)")
    world_forces = _force_array(1, "(m, 3) the contact forces in the world frame")
    wrenches = _force_array(2, "(m, 6) each contact's wrench G_i f_i (eq. 11)")
    resultant = _force_array(3, "(6,) the sum of the contacts' wrenches, -w_ext")

    @property
    def shot(self):
        """The RayShot that certifies this answer (built on first use; None for a zero wrench):
        on W(norm, magnitude) and R(-w_ext), or for Linf on W_Linf's lift C (R^(m + 5),
        graspforce.grasping.wrench_space) and the ray (0, -w_ext), where sigma = 1 / (m t). The
        wrench part u of the lift's normal (mu, u) is a normal of W_Linf: h_W(u) = sum_i h_Ai(u) <=
        m h_C(mu, u) since the lift's rows sum to zero, so u alone certifies sigma_lower (and a
        miss). The compiled shot is in the units (force, torque / L) (Grasp.length); here it is
        mapped back, its torque coordinates times L and its normal's divided by L (t, t_upper
        and the support value do not change). For a grasp whose wrenches span only R^k, k < 6,
        and a load in that span, the shot is on the image P A of that set A (W or C, in the
        grasp's units) and the ray P (0, -w_ext), with P = Q^T D on W and block-diag(I, Q^T D)
        on C (`shot.convex_set.matrix`; Q an orthonormal basis of the span in the units (force,
        torque / L), D their scaling); h_PA(n) = h_A(P^T n), so P^T n is a normal of A.
        """
        try:
            return self._shot
        except AttributeError:
            self._shot = None
            if self.ray is not None:
                W, w_ext, head, packed, extra, space = self.ray
                length = space.length
                # a shot in the span of a rank-deficient grasp is on the only affine root
                # (graspforce.grasping.wrench_space.projection)
                P = getattr(W, "matrix", None)
                n = W.dim if P is None else P.shape[1]
                r = np.zeros(n)
                r[n - 6:] = -np.asarray(w_ext, dtype=float)
                if P is not None:
                    if length != 1.0:
                        W = space.image_in_units(W)
                    r = W.matrix @ r
                elif length != 1.0:
                    W = space._target(n > 6, 1.0).set
                    packed = packed.copy()
                    normal, _, vertices, _ = unpack(packed, extra, n, W.witness_size, head[7])
                    normal[n - 3:] /= length
                    vertices[:, n - 3:] *= length
                self._shot = RayShot.from_packed(W, r, self.method, head, packed, extra)
            return self._shot

    def to_dict(self):
        """The record as JSON-ready values (None for an infinite sigma), what the service
        sends; MinForce.from_dict reads it back (without `shot`)."""
        return {"feasible": bool(self.feasible), "status": self.status, "sigma": _num(self.sigma),
                "sigma_lower": _num(self.sigma_lower), "norm": self.norm,
                "magnitude": self.magnitude, "method": self.method,
                "iterations": int(self.iterations), "support_calls": int(self.support_calls),
                "forces": self.forces.tolist(), "world_forces": self.world_forces.tolist(),
                "wrenches": self.wrenches.tolist(), "resultant": self.resultant.tolist()}

    @classmethod
    def from_dict(cls, d):
        """The record of `to_dict`'s output; its `shot` is None."""
        record = cls(feasible=bool(d["feasible"]), status=d["status"], sigma=_inf(d["sigma"]),
                     sigma_lower=_inf(d["sigma_lower"]), forces=_array(d["forces"]),
                     world_forces=_array(d["world_forces"]), wrenches=_array(d["wrenches"]),
                     resultant=_array(d["resultant"]), norm=d["norm"], magnitude=d["magnitude"],
                     method=d["method"], iterations=int(d["iterations"]),
                     support_calls=int(d["support_calls"]))
        record._shot = None
        return record

    def __repr__(self):
        return (f"MinForce(feasible={self.feasible}, status={self.status!r}, "
                f"sigma={self.sigma!r}, sigma_lower={self.sigma_lower!r}, norm={self.norm!r}, "
                f"magnitude={self.magnitude!r}, method={self.method!r}, "
                f"iterations={self.iterations})")


@dataclass(frozen=True)
class GraspQuality:
    """Force closure and the Ferrari-Canny quality of a grasp on its exact wrench set W.

    value = the radius of the largest origin-centred ball inside W = min over unit u of h_W(u),
    bracketed: lower <= value <= upper. `lower` is the inradius of a polytope of support points
    inside W, `upper` = h_W(direction) for the unit `direction` in which W is thinnest. Not force
    closure (the origin is not interior to W) gives value = lower = upper = 0 and a `direction`
    with h_W(direction) <= tolerance (the wrench -direction cannot be resisted, or only just).
    """
    force_closure: bool
    value: float
    lower: float
    upper: float
    direction: np.ndarray
    norm: str
    magnitude: str
    iterations: int
    support_calls: int

    def to_dict(self):
        """The record as JSON-ready values; GraspQuality.from_dict reads it back."""
        d = {f.name: getattr(self, f.name) for f in fields(self)}
        d.update(force_closure=bool(self.force_closure), value=float(self.value),
                 lower=float(self.lower), upper=float(self.upper),
                 direction=np.asarray(self.direction, dtype=float).tolist(),
                 iterations=int(self.iterations), support_calls=int(self.support_calls))
        return d

    @classmethod
    def from_dict(cls, d):
        return cls(**{**{f.name: d[f.name] for f in fields(cls)},
                      "direction": _array(d["direction"])})


@dataclass
class GrowthDistanceResult:
    """The growth distance g(A, B) of eq. (9)-(10) and the contact of A(sigma) and B(sigma).

    With Delta = R_A(A_0) - R_B(B_0), r = p_B - p_A and t r <= z_Delta(r) <= t_upper r the
    shooter's bracket: g lies in [sigma_lower, sigma_upper] = [1/t_upper, 1/t], whose relative
    width is at most eps, and sigma is its midpoint. status, with tol = touching_tol:
    "touching" when the bracket widened by tol contains 1 (sigma_lower - tol <= 1 <=
    sigma_upper + tol), else "separated" (g > 1) or "penetrating" (g < 1), each certified by the
    bracket; "max_iter" when the bracket did not close (sigma = the method's last estimate,
    uncertified, possibly inf; sigma_lower = 0, sigma_upper = inf). Coincident reference points:
    sigma = 0, "penetrating".
    point_a, point_b and normal are derived from Z_Delta(r) on first access (the derivation is
    in graspforce.growth.growth's docstring); coincident points or max_iter give point_a = p_A,
    point_b = p_B and a zero normal. Never NaN.
    """
    sigma: float
    sigma_lower: float
    sigma_upper: float
    status: str
    method: str
    iterations: int
    support_calls: int
    _raw: tuple = field(repr=False)     # (the GrowthDistance, its query's code, packed)

    @cached_property
    def shot(self):
        """The RayShot on Delta and R(p_B - p_A) that certifies the bracket (None if the
        reference points coincide)."""
        return self._raw[0].shot_of(self)

    @cached_property
    def _contact(self):
        return self._raw[0].contact_of(self)

    @property
    def point_a(self):
        """The point of A(sigma) where it touches B(sigma) (on A(sigma)'s boundary)."""
        return self._contact[0]

    @property
    def point_b(self):
        """The point of B(sigma) where it touches A(sigma); within eps/2 |p_B - p_A| of
        point_a."""
        return self._contact[1]

    @property
    def normal(self):
        """Unit normal of the plane separating A(sigma) and B(sigma) at the contact, from A to B."""
        return self._contact[2]

    def to_dict(self):
        """The record as JSON-ready values (None for an infinite bound), with the contact;
        GrowthDistanceResult.from_dict reads it back (without `shot`)."""
        return {"sigma": _num(self.sigma), "sigma_lower": _num(self.sigma_lower),
                "sigma_upper": _num(self.sigma_upper), "status": self.status,
                "method": self.method, "iterations": int(self.iterations),
                "support_calls": int(self.support_calls), "point_a": self.point_a.tolist(),
                "point_b": self.point_b.tolist(), "normal": self.normal.tolist()}

    @classmethod
    def from_dict(cls, d):
        record = cls(_inf(d["sigma"]), _inf(d["sigma_lower"]), _inf(d["sigma_upper"]),
                     d["status"], d["method"], int(d["iterations"]), int(d["support_calls"]),
                     None)
        record.__dict__["_contact"] = (_array(d["point_a"]), _array(d["point_b"]),
                                       _array(d["normal"]))
        record.__dict__["shot"] = None
        return record


class MinForceBatch:
    """min_force for one grasp and many wrenches (Grasp.min_force_batch): one entry per wrench,
    in order. sigma, sigma_lower (k,) as MinForce's (inf where infeasible or undecided),
    status (k,) strings, feasible (k,) bools, iterations (k,); forces (k, m, 4) local contact
    forces, or None unless asked for. `summary` counts the statuses and describes sigma over
    the feasible wrenches."""

    def __init__(self, sigma, sigma_lower, status, feasible, iterations, forces, norm, magnitude,
                 method, wrenches=None):
        self.sigma, self.sigma_lower = np.asarray(sigma, float), np.asarray(sigma_lower, float)
        self.status = tuple(status)
        self.feasible = np.asarray(feasible, bool)
        self.iterations = np.asarray(iterations, np.int64)
        self.forces = forces
        self.norm, self.magnitude, self.method = norm, magnitude, method
        self.wrenches = wrenches

    def __len__(self):
        return len(self.status)

    @property
    def summary(self):
        """{count, feasible, statuses: {status: count}, sigma_min, sigma_median, sigma_mean,
        sigma_max (over the feasible wrenches; None if there are none), iterations_mean}."""
        finite = self.sigma[self.feasible]
        counts = {}
        for s in self.status:
            counts[s] = counts.get(s, 0) + 1
        stat = (lambda f: float(f(finite))) if finite.size else (lambda f: None)
        return {"count": len(self), "feasible": int(self.feasible.sum()),
                "statuses": dict(sorted(counts.items())), "sigma_min": stat(np.min),
                "sigma_median": stat(np.median), "sigma_mean": stat(np.mean),
                "sigma_max": stat(np.max),
                "iterations_mean": float(self.iterations.mean()) if len(self) else 0.0}

    def to_dict(self):
        """JSON-ready values (None for an infinite sigma); MinForceBatch.from_dict reads them."""
        return {"norm": self.norm, "magnitude": self.magnitude, "method": self.method,
                "sigma": [_num(x) for x in self.sigma.tolist()],
                "sigma_lower": [_num(x) for x in self.sigma_lower.tolist()],
                "status": list(self.status), "feasible": self.feasible.tolist(),
                "iterations": self.iterations.tolist(),
                "forces": None if self.forces is None else self.forces.tolist(),
                "wrenches": None if self.wrenches is None else self.wrenches.tolist(),
                "summary": self.summary}

    @classmethod
    def from_dict(cls, d):
        return cls([_inf(x) for x in d["sigma"]], [_inf(x) for x in d["sigma_lower"]],
                   d["status"], d["feasible"], d["iterations"],
                   None if d.get("forces") is None else _array(d["forces"]), d["norm"],
                   d["magnitude"], d["method"],
                   None if d.get("wrenches") is None else _array(d["wrenches"]))

    def __repr__(self):
        return f"MinForceBatch({len(self)} wrenches, {self.summary['statuses']})"
