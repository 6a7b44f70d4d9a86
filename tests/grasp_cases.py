"""Random grasps and plain-array views of them for the grasp tests (construction only: nothing
here solves anything; the truth is in truth.py)."""
import math

import numpy as np

import graspforce as gf

KINDS = ("soft", "point", "frictionless")


def grasp_map(position, normal, tangents):
    """G_i of eq. (11) written out: columns n, o, t, 0 over p x n, p x o, p x t, n."""
    p = np.asarray(position, dtype=float)
    n = np.asarray(normal, dtype=float)
    o, t = (np.asarray(v, dtype=float) for v in tangents)
    top = np.column_stack((n, o, t, np.zeros(3)))
    bottom = np.column_stack((np.cross(p, n), np.cross(p, o), np.cross(p, t), n))
    return np.vstack((top, bottom))


def plain(grasp):
    """[(G_i, mu_i, mu_si)] for truth.py, G_i built here from the contact's frame."""
    return [(grasp_map(c.position, c.normal, c.tangents), c.mu, c.mu_spin)
            for c in grasp.contacts]


def _surface_point(rng, shape, size):
    """A point on a random object's surface and its inward unit normal."""
    d = rng.normal(size=3)
    d /= np.linalg.norm(d)
    if shape == "ellipsoid":
        p = d / np.sqrt(np.sum((d / size) ** 2))
        n = -p / size ** 2
    elif shape == "box":
        k = int(np.argmax(np.abs(d) / size))
        p = d * (size[k] / abs(d[k]))
        n = np.zeros(3)
        n[k] = -np.sign(d[k])
    else:                                       # cylinder about z, radius size[0], half height size[2]
        radial = math.hypot(d[0], d[1])
        if radial / size[0] >= abs(d[2]) / size[2]:
            p = d * (size[0] / radial)
            n = -np.array([p[0], p[1], 0.0])
        else:
            p = d * (size[2] / abs(d[2]))
            n = np.array([0.0, 0.0, -np.sign(d[2])])
    return p, n / np.linalg.norm(n)


def random_grasp(rng, m, kinds=KINDS, tilt=0.3):
    """m contacts on a random ellipsoid, box or cylinder of 3-10 cm, normals the inward surface
    normal tilted by up to `tilt` rad ("inward-ish"), mu in [0.2, 1], mu_s in [0.005, 0.05] m,
    kinds drawn from `kinds`; the object is shifted off the origin so torques are not special."""
    shape = ("ellipsoid", "box", "cylinder")[rng.integers(3)]
    size = rng.uniform(0.03, 0.1, 3)
    shift = rng.uniform(-0.05, 0.05, 3)
    contacts = []
    for _ in range(m):
        p, n = _surface_point(rng, shape, size)
        axis = np.cross(n, rng.normal(size=3))
        axis /= np.linalg.norm(axis)
        angle = rng.uniform(0.0, tilt)
        n = math.cos(angle) * n + math.sin(angle) * axis
        kind = kinds[rng.integers(len(kinds))]
        mu = 0.0 if kind == "frictionless" else rng.uniform(0.2, 1.0)
        mu_s = rng.uniform(0.005, 0.05) if kind == "soft" else 0.0
        contacts.append(gf.Contact(p + shift, n, mu, mu_s))
    return gf.Grasp(contacts)


def random_wrench(rng, force=5.0, torque=0.3):
    return np.concatenate((rng.normal(0.0, force, 3), rng.normal(0.0, torque, 3)))
