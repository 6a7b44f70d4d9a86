"""Result records. Each carries the bounds that certify it, so it can be checked without
trusting the code that made it."""
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np


@dataclass
class RayShot:
    """The answer to the ray-shooting problem of section 2.1 for A and R(r).

    point = z_A(r) = t r is the convex combination `weights` of `vertices` = Z_A(r), points of A
    (each with its `witnesses`). The hyperplane {x : normal^T x = support_value}, with
    support_value = h_A(normal), supports A and meets the ray at t_upper r, so the true z_A(r)
    lies between t r and t_upper r and ||z_A(r) - point|| <= error_bound = (t_upper - t) ||r||.
    On a miss, normal^T r > 0 >= support_value certifies that the ray and A do not meet
    (support_value is exactly 0 only for a ray grazing CO(A) to rounding).
    A plain (not frozen) dataclass: freezing costs a microsecond per result on the hot path;
    treat it as read-only.
    singular_steps counts the iterations in which the ray crossed the inner polytope through a
    face of dimension < n - 1: IE's facet-collection steps, ZC-IE's hand-overs to ZC-based
    iterations (section 3.2, 3.4.2); 0 for the other methods.
    """
    hit: bool
    status: str
    method: str
    t: float
    t_upper: float
    point: np.ndarray
    vertices: np.ndarray
    weights: np.ndarray
    witness_rows: np.ndarray = field(repr=False)   # raw witness vectors, one row per vertex
    convex_set: object = field(repr=False)
    normal: np.ndarray
    support_value: float
    error_bound: float
    iterations: int
    support_calls: int
    singular_steps: int

    @cached_property
    def witnesses(self):
        """One decoded witness per vertex: ((leaf_index, local), ...) (decoded on first use, so
        that a caller who needs only t pays nothing for it)."""
        return tuple(self.convex_set.decode_witness(w) for w in self.witness_rows)


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
