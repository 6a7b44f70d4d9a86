"""The fraction of a wrench set that a grasp resists within a force budget, with a confidence
interval for sampled wrenches: the Wilson score interval.

Wilson rather than Clopper-Pearson: its coverage is close to the nominal level on average where
Clopper-Pearson's is conservative (wider than needed), it needs no beta quantiles, and it stays
inside [0, 1] and non-degenerate at 0 or N successes, where the plain normal interval collapses.
"""
import math
from statistics import NormalDist

import numpy as np

from .._validate import finite_scalar
from .forces import min_force
from .result import BAD_WRENCH


class Coverage:
    """fraction = resisted / total of the finite wrenches (bad rows are left out and counted in
    `bad`), interval = the Wilson interval at `confidence`, budget: the overall force limit in
    the grasp's norm; `result`: the BatchForces behind it (None when built from arrays)."""

    __slots__ = ("fraction", "resisted", "total", "bad", "interval", "budget", "confidence",
                 "result")

    def __init__(self, resisted, total, bad, budget, confidence, result=None):
        self.resisted, self.total, self.bad = int(resisted), int(total), int(bad)
        self.budget, self.confidence, self.result = budget, confidence, result
        self.fraction = self.resisted / self.total if self.total else math.nan
        self.interval = wilson_interval(self.resisted, self.total, confidence)

    def __repr__(self):
        lo, hi = self.interval
        return (f"Coverage(resists {100 * self.fraction:.1f} % of {self.total} wrenches within "
                f"{self.budget:g}; {100 * self.confidence:g} % interval "
                f"[{100 * lo:.1f}, {100 * hi:.1f}] %)")


def wilson_interval(successes, n, confidence=0.95):
    """(low, high) of the Wilson score interval for a binomial proportion; (nan, nan) for n = 0."""
    if n == 0:
        return (math.nan, math.nan)
    z = NormalDist().inv_cdf(0.5 + 0.5 * confidence)
    p = successes / n
    z2n = z * z / n
    centre = (p + 0.5 * z2n) / (1.0 + z2n)
    half = z * math.sqrt(p * (1.0 - p) / n + 0.25 * z2n / n) / (1.0 + z2n)
    return (max(0.0, centre - half), min(1.0, centre + half))


def check_confidence(confidence):
    c = finite_scalar(confidence, "confidence")
    if not 0.0 < c < 1.0:
        raise ValueError(f"confidence: must be in (0, 1), got {confidence!r}")
    return c


def coverage_of(sigma, status, budget, confidence=0.95, result=None):
    """Coverage from a batch's sigma and status arrays: a wrench counts as resisted when forces
    of overall magnitude sigma <= budget were found (every finite sigma is that of actual
    forces, so this never overcounts; a max_iter row's sigma may be above the minimum)."""
    budget = finite_scalar(budget, "budget", minimum=0.0)
    confidence = check_confidence(confidence)
    sigma = np.asarray(sigma)
    bad = np.asarray(status) == BAD_WRENCH
    resisted = np.count_nonzero((sigma <= budget) & ~bad)
    return Coverage(resisted, sigma.shape[0] - np.count_nonzero(bad), np.count_nonzero(bad),
                    budget, confidence, result)


def coverage(grasp, wrenches, budget, norm="L1", magnitude="normal", method="zc-ie", eps=1e-9,
             confidence=0.95, threads=None, client=None, chunk_size=None):
    """The fraction of the rows of wrenches (N, 6) that the grasp resists with overall force
    <= budget (measured by norm and magnitude as in Grasp.min_force), with its Wilson interval:
    valid for wrenches sampled independently from the distribution of interest."""
    budget = finite_scalar(budget, "budget", minimum=0.0)
    confidence = check_confidence(confidence)
    result = min_force(grasp, wrenches, norm=norm, magnitude=magnitude, method=method, eps=eps,
                       threads=threads, client=client, chunk_size=chunk_size)
    return coverage_of(result.sigma, result.status, budget, confidence, result)


def coverage_curve(sigma, status, budgets):
    """The fraction resisted at each budget (for plots): sorted sigma, one search."""
    finite = np.sort(np.asarray(sigma)[np.asarray(status) != BAD_WRENCH])
    if finite.size == 0:
        return np.full(len(budgets), np.nan)
    return np.searchsorted(finite, np.asarray(budgets, float), side="right") / finite.size
