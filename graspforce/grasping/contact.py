"""A contact with friction: where it is, how it may push, and its grasp map G_i of eq. (11)."""
import math

import numpy as np

from .._core import contact
from .._validate import finite_array, finite_scalar, finite_vector3


class Contact:
    """A contact on an object, in the world (or object) frame.

    position: p_i (3,). normal: n_i (3,), pointing into the object, the direction in which the
    finger pushes (normalized here). mu: tangential friction coefficient (>= 0; 0 is frictionless).
    mu_spin: torsional friction coefficient mu_s of eq. (12), in metres: > 0 is a soft finger,
    0 a point contact with friction (no spin moment). tangents: (o_i, t_i), two unit vectors
    with n = o x t; by default a right-handed frame is chosen.

    The contact force f_i = (f_1, f_2, f_3, f_4) = (normal force, force along o, force along t,
    spin moment about n) lies in the friction cone F_i of eq. (12):
        sqrt((f_2^2 + f_3^2) / mu^2 + f_4^2 / mu_spin^2) <= f_1,
    with f_2 = f_3 = 0 when mu = 0 and f_4 = 0 when mu_spin = 0.

    A contact is fixed once made: its frame and G_i are computed once, when it is made, by one
    compiled call (core/grasping/contacts.hpp; a grasp built per query pays for them once, not at
    every use).
    """

    def __init__(self, position, normal, mu, mu_spin=0.0, tangents=None):
        made = None
        # the common contact (float mu and mu_spin in range, default tangents, float64 arrays
        # or lists of floats) is checked and computed by one compiled call
        if (tangents is None and type(mu) is float and type(mu_spin) is float
                and 0.0 <= mu < math.inf and 0.0 <= mu_spin < math.inf
                and not (mu == 0.0 and mu_spin > 0.0)):
            made = contact(position, normal, mu, mu_spin)
        if made is None:
            position, normal, mu, mu_spin, tangents = self._checked(position, normal, mu,
                                                                    mu_spin, tangents)
            made = contact(position, normal, mu, mu_spin) if tangents is None else \
                _with_tangents(position, normal, mu, mu_spin, tangents)
        self.mu = mu
        self.mu_spin = mu_spin
        # position, unit normal and the entries a grasp's values are made of
        # (graspforce.grasping.wrench_space.grasp_values): G_i (6 x 4, row-major), mu, mu_s, mu_s /
        # mu, (mu / mu_s)^2; and ||p||^2 + mu_s^2, which a grasp's default length sums
        self.position, self.normal, self._g, self._arm2 = made

    @staticmethod
    def _checked(position, normal, mu, mu_spin, tangents):
        """The arguments checked one by one (each rule named) and converted: position and
        normal float64 arrays, mu and mu_spin floats, tangents None or (o, t) arrays."""
        position = finite_vector3(position, "position")
        n = finite_vector3(normal, "normal")
        # sqrt(n.n) is np.linalg.norm(n) bit for bit: both take the dot product from BLAS,
        # whose rounding (fused or not) a sum written in Python would not reproduce
        length = math.sqrt(n.dot(n))
        if not length > 1e-12:
            raise ValueError("normal: must be a nonzero vector")
        mu = finite_scalar(mu, "mu", minimum=0.0)
        mu_spin = finite_scalar(mu_spin, "mu_spin", minimum=0.0)
        if mu == 0.0 and mu_spin > 0.0:
            raise ValueError("mu_spin: must be 0 when mu is 0 (a frictionless contact has no "
                             "torsional friction)")
        if tangents is not None:
            tangents = _check_tangents(tangents, n / length)
        return position, n, mu, mu_spin, tangents

    @property
    def tangents(self):
        """(o, t): the unit tangents of the frame, n = o x t (arrays, made on first read)."""
        tangents = self.__dict__.get("_tangents")
        if tangents is None:
            g = self._g
            tangents = self._tangents = (g[1:12:4].copy(), g[2:12:4].copy())
        return tangents

    @property
    def kind(self):
        """"soft" (mu_spin > 0), "point" (friction, no spin moment) or "frictionless"."""
        if self.mu == 0.0:
            return "frictionless"
        return "soft" if self.mu_spin > 0.0 else "point"

    @property
    def frame(self):
        """R_i = [n, o, t] (columns): local force (f_1, f_2, f_3) to world force."""
        return self._g[:12].reshape(3, 4)[:, :3].copy()

    @property
    def matrix(self):
        """G_i of eq. (11), (6, 4): [[n, o, t, 0], [p x n, p x o, p x t, n]]. It maps f_i to the
        wrench (force, torque about the frame's origin) the contact applies to the object."""
        return self._g[:24].reshape(6, 4).copy()

    def contains(self, force, tol=1e-9):
        """Whether the local force (f_1, f_2, f_3, f_4) lies in F_i of eq. (12), to `tol` relative
        to f_1 (and absolutely for a zero force)."""
        f = finite_array(force, "force", shape=(4,))
        slack = tol * max(abs(f[0]), 1.0 if f[0] == 0.0 else 0.0)
        if f[0] < -slack:
            return False
        tangential = np.hypot(f[1], f[2])
        if self.mu == 0.0:
            return tangential <= slack and abs(f[3]) <= slack
        if self.mu_spin == 0.0:
            return tangential / self.mu <= f[0] + slack and abs(f[3]) <= slack
        return np.hypot(tangential / self.mu, f[3] / self.mu_spin) <= f[0] + slack

    def __repr__(self):
        return (f"Contact(position={self.position.tolist()}, normal={self.normal.tolist()}, "
                f"mu={self.mu}, mu_spin={self.mu_spin})")


def _with_tangents(position, n, mu, mu_spin, tangents):
    """(position, unit normal, entries of Contact._g, squared arm) for a contact with its own
    tangents (o, t): the arithmetic of core/grasping/contacts.hpp with o given."""
    length = math.sqrt(n.dot(n))
    nx, ny, nz = n.tolist()
    nx, ny, nz = nx / length, ny / length, nz / length
    (ox, oy, oz), (tx, ty, tz) = tangents[0].tolist(), tangents[1].tolist()
    px, py, pz = position.tolist()
    d_inv, spin_weight = 0.0, 0.0
    if mu_spin > 0.0:
        ratio = mu / mu_spin
        d_inv, spin_weight = mu_spin / mu, ratio * ratio
    # G_i row by row (eq. 11): [n, o, t, 0] over [p x n, p x o, p x t, n], each cross product
    # written as np.cross computes it
    return position, np.array((nx, ny, nz)), np.array((
        nx, ox, tx, 0.0,
        ny, oy, ty, 0.0,
        nz, oz, tz, 0.0,
        py * nz - pz * ny, py * oz - pz * oy, py * tz - pz * ty, nx,
        pz * nx - px * nz, pz * ox - px * oz, pz * tx - px * tz, ny,
        px * ny - py * nx, px * oy - py * ox, px * ty - py * tx, nz,
        mu, mu_spin, d_inv, spin_weight)), px * px + py * py + pz * pz + mu_spin * mu_spin


def _check_tangents(tangents, n):
    arr = finite_array(tangents, "tangents", shape=(2, 3))
    o, t = arr[0], arr[1]
    if not (abs(np.linalg.norm(o) - 1) < 1e-9 and abs(np.linalg.norm(t) - 1) < 1e-9
            and np.allclose(np.cross(o, t), n, atol=1e-9)):
        raise ValueError("tangents: must be unit vectors (o, t) with o x t = normal")
    return o.copy(), t.copy()
