"""IE's singular case (section 3.2): the ray crosses the inner polytope through a face of
dimension < n - 1, so IE must work with a collection of facets around that face. Rays through
vertices and edge midpoints of random polytopes put b_k on such faces; the paper guarantees
convergence there, checked against an LP."""
import numpy as np
import pytest
from scipy.optimize import linprog

import graspforce as gf


def lp_ray_shoot(V, r):
    """max t s.t. t r = V^T lam, lam >= 0, sum lam = 1 (scipy HiGHS)."""
    m, n = V.shape
    c = np.zeros(m + 1)
    c[0] = -1.0
    A_eq = np.zeros((n + 1, m + 1))
    A_eq[:n, 0] = r
    A_eq[:n, 1:] = -V.T
    A_eq[n, 1:] = 1.0
    lp = linprog(c, A_eq=A_eq, b_eq=np.r_[np.zeros(n), 1.0], bounds=[(0, None)] * (m + 1),
                 method="highs")
    assert lp.status == 0
    return lp.x[0]


@pytest.mark.parametrize("n", [2, 3, 4, 6])
def test_ie_converges_through_low_dimensional_faces(n):
    rng = np.random.default_rng(n)
    singular = 0
    for _ in range(40):
        V = rng.standard_normal((4 * n, n))
        V -= V.mean(axis=0)
        order = np.argsort(V @ rng.standard_normal(n))
        for r in (V[order[-1]], 0.5 * (V[order[-1]] + V[order[-2]])):
            t_true = lp_ray_shoot(V, r)
            res = gf.ray_shoot(gf.Polytope(V), r, method="ie")
            assert res.status == "hit"
            assert abs(res.t - t_true) <= 1e-12 * t_true, (r, res.t, t_true)
            assert (res.t_upper - res.t) <= 1e-9 * res.t
            assert np.linalg.norm(res.weights @ res.vertices - res.point) <= 1e-12
            singular += res.singular_steps > 0
    # the construction does reach the singular case, in every dimension
    assert singular >= 3
