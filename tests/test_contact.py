"""gf.Contact: the grasp map of eq. (11), its frame, the friction cone of eq. (12) and its input
checks."""
import math

import numpy as np
import pytest
from grasp_cases import grasp_map

import graspforce as gf

RNG_CASES = range(12)


def random_contact(seed):
    rng = np.random.default_rng(seed)
    p = rng.normal(0.0, 0.1, 3)
    n = rng.normal(size=3)
    mu = rng.uniform(0.2, 1.0)
    mu_s = (0.0, rng.uniform(0.005, 0.05))[seed % 2]
    return gf.Contact(p, n, mu, mu_s), p, n / np.linalg.norm(n)


@pytest.mark.parametrize("seed", RNG_CASES)
def test_default_frame_is_orthonormal_and_right_handed(seed):
    c, _, n = random_contact(seed)
    o, t = c.tangents
    # a few ulps of the unit vectors' rounding
    assert np.allclose(c.normal, n, rtol=0, atol=4e-16)
    F = np.column_stack((c.normal, o, t))
    assert np.allclose(F.T @ F, np.eye(3), rtol=0, atol=1e-15)
    assert np.allclose(np.cross(o, t), c.normal, rtol=0, atol=1e-15)       # n = o x t
    assert np.linalg.det(F) == pytest.approx(1.0, abs=1e-15)


@pytest.mark.parametrize("normal", [[0, 0, 1], [0, 0, -1], [1, 0, 0], [0, -1, 0], [1e-9, 0, -3]])
def test_default_frame_on_axis_normals(normal):
    c = gf.Contact([0.0, 0.0, 0.0], normal, 0.5)
    o, t = c.tangents
    assert np.allclose(np.cross(o, t), c.normal, rtol=0, atol=1e-15)
    assert abs(o @ c.normal) <= 1e-15 and abs(np.linalg.norm(o) - 1) <= 1e-15


@pytest.mark.parametrize("seed", RNG_CASES)
def test_matrix_is_eq11(seed):
    c, p, _ = random_contact(seed)
    # entries are products of O(0.1 m) and O(1) numbers: a few ulps apart at most
    G = c.matrix
    assert G.shape == (6, 4)
    assert np.allclose(G, grasp_map(p, c.normal, c.tangents), rtol=0, atol=1e-16)
    # the wrench of a force F at p, torque about the origin p x F, plus the spin moment along n
    f = np.array([2.0, 0.3, -0.4, 0.01])
    force = f[0] * c.normal + f[1] * c.tangents[0] + f[2] * c.tangents[1]
    wrench = np.concatenate((force, np.cross(p, force) + f[3] * c.normal))
    assert np.allclose(G @ f, wrench, rtol=0, atol=1e-15)


def test_given_tangents_are_used():
    n = np.array([0.0, 0.0, 1.0])
    o = np.array([math.cos(0.3), math.sin(0.3), 0.0])
    t = np.cross(n, o)
    c = gf.Contact([0.1, 0.2, 0.3], n, 0.4, 0.01, tangents=(o, t))
    assert np.array_equal(c.tangents[0], o) and np.array_equal(c.tangents[1], t)
    assert np.allclose(c.matrix, grasp_map([0.1, 0.2, 0.3], n, (o, t)), rtol=0, atol=1e-16)


def test_kind():
    assert gf.Contact([0, 0, 0], [0, 0, 1], 0.5, 0.01).kind == "soft"
    assert gf.Contact([0, 0, 0], [0, 0, 1], 0.5).kind == "point"
    assert gf.Contact([0, 0, 0], [0, 0, 1], 0.0).kind == "frictionless"


@pytest.mark.parametrize("mu, mu_s", [(0.5, 0.02), (0.5, 0.0), (0.0, 0.0)])
def test_contains_against_eq12(mu, mu_s):
    # forces on a grid of radii around the cone boundary: inside by 1e-6 or outside by 1e-6
    # relative must be decided exactly as eq. (12) says (tol 1e-12 is far below that margin)
    c = gf.Contact([0, 0, 0], [0, 0, 1], mu, mu_s)
    rng = np.random.default_rng(7)
    for _ in range(200):
        f1 = rng.uniform(0.1, 10.0)
        d = rng.normal(size=3)
        if mu == 0.0:
            d[:] = 0.0
        elif mu_s == 0.0:
            d[2] = 0.0
        d /= max(np.linalg.norm(d), 1e-300)
        for factor, inside in ((1 - 1e-6, True), (1 + 1e-6, False)):
            if not d.any():
                if not inside:
                    continue
                f = np.array([f1, 0.0, 0.0, 0.0])
            else:
                # boundary point: (f2/mu, f3/mu, f4/mu_s) on the sphere of radius f1
                g = factor * f1 * d
                f = np.array([f1, mu * g[0], mu * g[1], mu_s * g[2]])
            assert c.contains(f, tol=1e-12) == inside, (f, inside)
    assert not c.contains([-1e-3, 0, 0, 0], tol=1e-12)
    assert c.contains([0, 0, 0, 0], tol=1e-12)
    if mu_s == 0.0:
        assert not c.contains([1.0, 0, 0, 1e-3], tol=1e-12)     # a point contact has no spin
    if mu == 0.0:
        assert not c.contains([1.0, 1e-3, 0, 0], tol=1e-12)


@pytest.mark.parametrize("kwargs, field", [
    ({"position": [0, 0], "normal": [0, 0, 1], "mu": 0.5}, "position"),
    ({"position": [0, np.nan, 0], "normal": [0, 0, 1], "mu": 0.5}, "position"),
    ({"position": [0, 0, 0], "normal": [0, 0, 1, 0], "mu": 0.5}, "normal"),
    ({"position": [0, 0, 0], "normal": [0, np.inf, 1], "mu": 0.5}, "normal"),
    ({"position": [0, 0, 0], "normal": [0, 0, 0], "mu": 0.5}, "normal"),
    ({"position": [0, 0, 0], "normal": [0, 0, 1], "mu": -0.1}, "mu"),
    ({"position": [0, 0, 0], "normal": [0, 0, 1], "mu": np.nan}, "mu"),
    ({"position": [0, 0, 0], "normal": [0, 0, 1], "mu": 0.5, "mu_spin": -0.01}, "mu_spin"),
    ({"position": [0, 0, 0], "normal": [0, 0, 1], "mu": 0.0, "mu_spin": 0.01}, "mu_spin"),
    ({"position": [0, 0, 0], "normal": [0, 0, 1], "mu": 0.5, "tangents": [[1, 0, 0], [0, 2, 0]]},
     "tangents"),
    ({"position": [0, 0, 0], "normal": [0, 0, 1], "mu": 0.5, "tangents": [[0, 1, 0], [1, 0, 0]]},
     "tangents"),                                          # left-handed: o x t = -n
    ({"position": [0, 0, 0], "normal": [0, 0, 1], "mu": 0.5, "tangents": [[1, 0, 0], [1, 0, 0]]},
     "tangents"),
    ({"position": [0, 0, 0], "normal": [0, 0, 1], "mu": 0.5, "tangents": [[1, 0, 0]]}, "tangents"),
])
def test_bad_input_names_the_field(kwargs, field):
    with pytest.raises(ValueError, match=field):
        gf.Contact(**kwargs)


@pytest.mark.parametrize("seed", range(5))
def test_squared_arm_is_the_positions_and_spin_coefficients(seed):
    # a grasp's default length sums the contacts' ||p||^2 + mu_s^2, computed when each is made
    # (in C for the default tangents, in Python for given ones): the same floats as from p
    rng = np.random.default_rng(seed)
    p, n = rng.normal(size=3), rng.normal(size=3)
    o = np.cross(n, rng.normal(size=3))
    o /= np.linalg.norm(o)
    t = np.cross(n / np.linalg.norm(n), o)
    mu_s = float(rng.uniform(0.0, 0.05))
    x, y, z = p.tolist()
    expected = x * x + y * y + z * z + mu_s * mu_s
    assert gf.Contact(p, n, 0.5, mu_s)._arm2 == expected
    assert gf.Contact(p, n, 0.5, mu_s, tangents=(o, t))._arm2 == expected
    assert gf.Contact(p.tolist(), n, 0.5, mu_s)._arm2 == expected
