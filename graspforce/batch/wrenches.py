"""Seeded wrench generators: the same seed gives the same (N, 6) array on every machine
(numpy's PCG64 through default_rng)."""
import numpy as np

from .._validate import finite_array, finite_scalar, positive_int


def _rng(seed):
    if seed is None or isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed: expected an integer, got {seed!r}")
    return np.random.default_rng(int(seed))


def _scale(scale):
    """Per-component scale (6,) from a number or 6 numbers: a wrench space mixes N and N m, so
    a ball is taken in coordinates w / scale."""
    s = finite_array(scale, "scale")
    s = np.broadcast_to(s, (6,)) if s.ndim == 0 else s
    if s.shape != (6,) or np.any(s <= 0.0):
        raise ValueError(f"scale: must be a positive number or 6 positive numbers, got {scale!r}")
    return s


def ball(n, radius=1.0, scale=1.0, seed=0):
    """n wrenches uniform in the ball ||w / scale|| <= radius (scale: one or six positive
    numbers, e.g. (10, 10, 10, 0.5, 0.5, 0.5) for newtons and newton-metres)."""
    n = positive_int(n, "n")
    radius = finite_scalar(radius, "radius", minimum=0.0, exclusive=True)
    rng = _rng(seed)
    d = rng.normal(size=(n, 6))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return d * (radius * rng.random(n) ** (1.0 / 6.0))[:, None] * _scale(scale)


def ellipsoid(n, center, shape, seed=0):
    """n wrenches uniform in {center + shape @ x : ||x|| <= 1}, shape (6, 6) invertible or
    (6, k) for a flat ellipsoid in a k-dimensional slice."""
    n = positive_int(n, "n")
    c = finite_array(center, "center", shape=(6,))
    S = finite_array(shape, "shape", ndim=2)
    if S.shape[0] != 6:
        raise ValueError(f"shape: expected 6 rows, got {S.shape}")
    k = S.shape[1]
    rng = _rng(seed)
    d = rng.normal(size=(n, k))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    x = d * (rng.random(n) ** (1.0 / k))[:, None]
    return c + x @ S.T


def gaussian(n, mean=0.0, std=1.0, seed=0):
    """n wrenches with independent normal components: mean and std one or six numbers (a zero
    std keeps that component at its mean)."""
    n = positive_int(n, "n")
    m = np.broadcast_to(finite_array(mean, "mean"), (6,))
    s = finite_array(std, "std", minimum=0.0)
    s = np.broadcast_to(s, (6,)) if s.ndim == 0 else s
    if s.shape != (6,):
        raise ValueError(f"std: must be a number or 6 numbers, got shape {s.shape}")
    return m + _rng(seed).normal(size=(n, 6)) * s


def table5(n, seed=0):
    """The paper's protocol for Table 5 (benchmarks/grasp_sets.py random_wrenches): forces
    ~ N(0, 10 N) and torques ~ N(0, 0.5 N m) per component, forces first."""
    n = positive_int(n, "n")
    rng = _rng(seed)
    return np.hstack([rng.normal(0.0, 10.0, (n, 3)), rng.normal(0.0, 0.5, (n, 3))])


GENERATORS = {"ball": ball, "gaussian": gaussian, "table5": table5}
