"""IE's singular case (section 3.2): the ray crosses the inner polytope through a face of
dimension < n - 1, so IE must work with a collection of facets around that face. Rays through
vertices and edge midpoints of random polytopes put b_k on such faces; the paper guarantees
convergence there, checked against an LP."""
import numpy as np
import pytest
import graspforce as gf
import truth as T


@pytest.mark.parametrize("n", [2, 3, 4, 6])
def test_ie_converges_through_low_dimensional_faces(n):
    rng = np.random.default_rng(n)
    singular = 0
    for _ in range(40):
        V = rng.standard_normal((4 * n, n))
        V -= V.mean(axis=0)
        order = np.argsort(V @ rng.standard_normal(n))
        for r in (V[order[-1]], 0.5 * (V[order[-1]] + V[order[-2]])):
            hit, t_true, _ = T.ray_shoot_lp(V, r)
            assert hit
            res = gf.ray_shoot(gf.Polytope(V), r, method="ie")
            assert res.status == "hit"
            assert abs(res.t - t_true) <= 1e-12 * t_true, (r, res.t, t_true)
            assert (res.t_upper - res.t) <= 1e-9 * res.t
            assert np.linalg.norm(res.weights @ res.vertices - res.point) <= 1e-12
            singular += res.singular_steps > 0
    # the construction does reach the singular case, in every dimension
    assert singular >= 3
