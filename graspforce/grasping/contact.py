"""A contact with friction: where it is, how it may push, and its grasp map G_i of eq. (11)."""
import math

import numpy as np

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

    A contact is fixed once made: its frame and G_i are computed once, when it is made, in plain
    arithmetic (a grasp built per query pays for them once, not at every use).
    """

    def __init__(self, position, normal, mu, mu_spin=0.0, tangents=None):
        self.position = position = finite_vector3(position, "position")
        n = finite_vector3(normal, "normal")
        # sqrt(n.n) is np.linalg.norm(n) bit for bit: both take the dot product from BLAS,
        # whose rounding (fused or not) a sum written in Python would not reproduce
        length = math.sqrt(n.dot(n))
        if not length > 1e-12:
            raise ValueError("normal: must be a nonzero vector")
        nx, ny, nz = n.tolist()
        nx, ny, nz = nx / length, ny / length, nz / length
        self.normal = np.array((nx, ny, nz))
        if type(mu) is not float or not 0.0 <= mu < math.inf:
            mu = finite_scalar(mu, "mu", minimum=0.0)
        if type(mu_spin) is not float or not 0.0 <= mu_spin < math.inf:
            mu_spin = finite_scalar(mu_spin, "mu_spin", minimum=0.0)
        self.mu = mu
        self.mu_spin = mu_spin
        if mu == 0.0 and mu_spin > 0.0:
            raise ValueError("mu_spin: must be 0 when mu is 0 (a frictionless contact has no "
                             "torsional friction)")
        if tangents is None:
            (ox, oy, oz), (tx, ty, tz) = _default_tangents(nx, ny, nz)
        else:
            o, t = _check_tangents(tangents, self.normal)
            (ox, oy, oz), (tx, ty, tz) = o.tolist(), t.tolist()
        px, py, pz = position.tolist()
        # G_i row by row (eq. 11): [n, o, t, 0] over [p x n, p x o, p x t, n], each cross product
        # written as np.cross computes it
        self._g = (nx, ox, tx, 0.0,
                   ny, oy, ty, 0.0,
                   nz, oz, tz, 0.0,
                   py * nz - pz * ny, py * oz - pz * oy, py * tz - pz * ty, nx,
                   pz * nx - px * nz, pz * ox - px * oz, pz * tx - px * tz, ny,
                   px * ny - py * nx, px * oy - py * ox, px * ty - py * tx, nz)

    @property
    def tangents(self):
        """(o, t): the unit tangents of the frame, n = o x t (arrays, made on first read)."""
        tangents = self.__dict__.get("_tangents")
        if tangents is None:
            g = self._g
            tangents = self._tangents = (np.array(g[1:12:4]), np.array(g[2:12:4]))
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
        return np.array(self._g[:12]).reshape(3, 4)[:, :3].copy()

    @property
    def matrix(self):
        """G_i of eq. (11), (6, 4): [[n, o, t, 0], [p x n, p x o, p x t, n]]. It maps f_i to the
        wrench (force, torque about the frame's origin) the contact applies to the object."""
        return np.array(self._g).reshape(6, 4)

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


def _default_tangents(nx, ny, nz):
    """((o), (t)) of a unit normal, as floats, by the arithmetic np.argmin, np.linalg.norm and
    np.cross would do."""
    # the world axis least aligned with n gives a well-conditioned o; then t = n x o makes
    # (n, o, t) right-handed, i.e. n = o x t as eq. (11) requires. o = e_k - (e_k . n) n, whose
    # dot product is n_k exactly; ties go to the first axis, as np.argmin's do
    ax, ay, az = abs(nx), abs(ny), abs(nz)
    k = 0 if ax <= ay and ax <= az else (1 if ay <= az else 2)
    c = (nx, ny, nz)[k]
    o = [0.0 - c * nx, 0.0 - c * ny, 0.0 - c * nz]
    o[k] = 1.0 - c * (nx, ny, nz)[k]
    oa = np.array(o)
    length = math.sqrt(oa.dot(oa))           # np.linalg.norm(o), as for the normal
    ox, oy, oz = o[0] / length, o[1] / length, o[2] / length
    return (ox, oy, oz), (ny * oz - nz * oy, nz * ox - nx * oz, nx * oy - ny * ox)


def _check_tangents(tangents, n):
    arr = finite_array(tangents, "tangents", shape=(2, 3))
    o, t = arr[0], arr[1]
    if not (abs(np.linalg.norm(o) - 1) < 1e-9 and abs(np.linalg.norm(t) - 1) < 1e-9
            and np.allclose(np.cross(o, t), n, atol=1e-9)):
        raise ValueError("tangents: must be unit vectors (o, t) with o x t = normal")
    return o.copy(), t.copy()
