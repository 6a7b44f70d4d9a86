"""The arrays a batch returns: one entry per wrench (or pose), in the input's order."""
import numpy as np

from .._core import batch as _codes

# a row's status, indexed by its code (core/python/batch.hpp)
STATUSES = ("optimal", "infeasible", "max_iter", "bad_wrench")
OPTIMAL, INFEASIBLE, MAX_ITER, BAD_WRENCH = (_codes.OPTIMAL, _codes.INFEASIBLE, _codes.MAX_ITER,
                                             _codes.BAD_WRENCH)
assert STATUSES.index("bad_wrench") == BAD_WRENCH and STATUSES.index("max_iter") == MAX_ITER


class BatchForces:
    """min_force over N wrenches: sigma (N,), sigma_lower (N,), status (N,) int8 codes of
    STATUSES, iterations (N,) and forces (N, m, 4) or None. A row's fields are those of
    Grasp.min_force for that wrench; a bad wrench (NaN, inf, or a squared norm that overflows)
    has status "bad_wrench" and sigma NaN instead of raising."""

    __slots__ = ("sigma", "sigma_lower", "status", "iterations", "forces")

    def __init__(self, sigma, sigma_lower, status, iterations, forces=None):
        self.sigma = sigma
        self.sigma_lower = sigma_lower
        self.status = status
        self.iterations = iterations
        self.forces = forces

    def __len__(self):
        return len(self.sigma)

    @property
    def feasible(self):
        """(N,) bool: finite forces were found (sigma < inf)."""
        return np.isfinite(self.sigma)

    @property
    def status_names(self):
        """(N,) the statuses as strings."""
        return np.array(STATUSES)[self.status]

    def counts(self):
        """{status name: rows with it}."""
        found = np.bincount(self.status, minlength=len(STATUSES))
        return {name: int(k) for name, k in zip(STATUSES, found)}

    def columns(self):
        """{name: array} of the per-row scalars, as written to a file."""
        return {"sigma": self.sigma, "sigma_lower": self.sigma_lower, "status": self.status,
                "iterations": self.iterations}

    @classmethod
    def concatenate(cls, parts):
        parts = list(parts)
        forces = None if parts[0].forces is None else np.concatenate([p.forces for p in parts])
        return cls(*(np.concatenate([getattr(p, f) for p in parts])
                     for f in ("sigma", "sigma_lower", "status", "iterations")), forces)

    def __repr__(self):
        return f"BatchForces({len(self)} wrenches: {self.counts()})"


class BatchGrowth:
    """growth_distance over N pose pairs: sigma, sigma_lower, sigma_upper (N,), status (N,)
    strings of graspforce.GrowthDistanceResult's statuses plus "bad_pose" (a pose that is not
    finite or not a proper rotation; sigma NaN), iterations (N,)."""

    __slots__ = ("sigma", "sigma_lower", "sigma_upper", "status", "iterations")

    def __init__(self, sigma, sigma_lower, sigma_upper, status, iterations):
        self.sigma = sigma
        self.sigma_lower = sigma_lower
        self.sigma_upper = sigma_upper
        self.status = status
        self.iterations = iterations

    def __len__(self):
        return len(self.sigma)

    @classmethod
    def concatenate(cls, parts):
        parts = list(parts)
        return cls(*(np.concatenate([getattr(p, f) for p in parts]) for f in cls.__slots__))

    def __repr__(self):
        names, k = np.unique(self.status, return_counts=True)
        return f"BatchGrowth({len(self)} poses: {dict(zip(names.tolist(), k.tolist()))})"
