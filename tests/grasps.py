"""Grasps shared by the grasp tests (plain constructions, no solving)."""
import math

import numpy as np

import graspforce as gf

G_WEIGHT = 10.0
MU = 0.2


def sphere_grasp(lam, mu_spin=0.0):
    """NOTES.md item 1: four contacts on a unit sphere at elevation (1 - lam) atan(mu)."""
    alpha = (1.0 - lam) * math.atan(MU)
    contacts = []
    for az in np.deg2rad([0.0, 90.0, 180.0, 270.0]):
        p = np.array([math.cos(alpha) * math.cos(az), math.cos(alpha) * math.sin(az),
                      math.sin(alpha)])
        contacts.append(gf.Contact(p, -p, MU, mu_spin))
    return gf.Grasp(contacts)


def sphere_sigma_l1(lam):
    """G / (mu cos a - sin a) of NOTES.md item 1, written without cancellation:
    mu cos a - sin a = sqrt(1 + mu^2) sin(lam atan mu)."""
    return G_WEIGHT / (math.sqrt(1.0 + MU * MU) * math.sin(lam * math.atan(MU)))


def box_grasp():
    """Four soft fingers on the x faces of a 10 cm box: force-closure."""
    points = [([0.05, 0.01, 0.0], [-1, 0, 0]), ([0.05, -0.01, 0.01], [-1, 0, 0]),
              ([-0.05, 0.01, 0.0], [1, 0, 0]), ([-0.05, -0.01, -0.01], [1, 0, 0])]
    return gf.Grasp(gf.Contact(p, n, 0.5, 0.01) for p, n in points)


def two_finger_pinch():
    """Two point contacts facing each other: cannot resist a torque about the line through them."""
    return gf.Grasp([gf.Contact([0.05, 0, 0], [-1, 0, 0], 0.5),
                     gf.Contact([-0.05, 0, 0], [1, 0, 0], 0.5)])


def random_wrenches(k, seed, force=3.0, torque=0.05):
    rng = np.random.default_rng(seed)
    return np.hstack([rng.normal(0, force, (k, 3)), rng.normal(0, torque, (k, 3))])


def random_grasp(rng, m, kinds=("soft", "point", "frictionless")):
    """m contacts on a random ellipsoidal object (semi-axes 3-10 cm), normals along the inward
    surface normal; kinds drawn from `kinds`, mu in [0.2, 1], mu_spin in [0.005, 0.05] m."""
    axes = rng.uniform(0.03, 0.1, 3)
    contacts = []
    for _ in range(m):
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        p = d / np.sqrt(np.sum((d / axes) ** 2))                   # on the ellipsoid surface
        normal = -p / axes ** 2                                    # inward surface normal
        kind = kinds[rng.integers(len(kinds))]
        mu = 0.0 if kind == "frictionless" else rng.uniform(0.2, 1.0)
        mu_spin = rng.uniform(0.005, 0.05) if kind == "soft" else 0.0
        contacts.append(gf.Contact(p, normal, mu, mu_spin))
    return gf.Grasp(contacts)
