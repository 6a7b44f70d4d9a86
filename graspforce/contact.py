"""A contact with friction: where it is, how it may push, and its grasp map G_i of eq. (11)."""
import numpy as np

from ._validate import finite_array, finite_scalar


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
    """

    def __init__(self, position, normal, mu, mu_spin=0.0, tangents=None):
        self.position = finite_array(position, "position", shape=(3,))
        n = finite_array(normal, "normal", shape=(3,))
        length = np.linalg.norm(n)
        if not length > 1e-12:
            raise ValueError("normal: must be a nonzero vector")
        self.normal = n / length
        self.mu = finite_scalar(mu, "mu", minimum=0.0)
        self.mu_spin = finite_scalar(mu_spin, "mu_spin", minimum=0.0)
        if self.mu == 0.0 and self.mu_spin > 0.0:
            raise ValueError("mu_spin: must be 0 when mu is 0 (a frictionless contact has no "
                             "torsional friction)")
        self.tangents = (_default_tangents(self.normal) if tangents is None
                         else _check_tangents(tangents, self.normal))

    @property
    def kind(self):
        """"soft" (mu_spin > 0), "point" (friction, no spin moment) or "frictionless"."""
        if self.mu == 0.0:
            return "frictionless"
        return "soft" if self.mu_spin > 0.0 else "point"

    @property
    def frame(self):
        """R_i = [n, o, t] (columns): local force (f_1, f_2, f_3) to world force."""
        o, t = self.tangents
        return np.column_stack((self.normal, o, t))

    @property
    def matrix(self):
        """G_i of eq. (11), (6, 4): [[n, o, t, 0], [p x n, p x o, p x t, n]]. It maps f_i to the
        wrench (force, torque about the frame's origin) the contact applies to the object."""
        R = self.frame
        G = np.zeros((6, 4))
        G[:3, :3] = R
        G[3:, :3] = np.cross(self.position, R.T).T
        G[3:, 3] = self.normal
        return G

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


def _default_tangents(n):
    # the world axis least aligned with n gives a well-conditioned o; then t = n x o makes
    # (n, o, t) right-handed, i.e. n = o x t as eq. (11) requires
    axis = np.zeros(3)
    axis[np.argmin(np.abs(n))] = 1.0
    o = axis - (axis @ n) * n
    o /= np.linalg.norm(o)
    return o, np.cross(n, o)


def _check_tangents(tangents, n):
    arr = finite_array(tangents, "tangents", shape=(2, 3))
    o, t = arr[0], arr[1]
    if not (abs(np.linalg.norm(o) - 1) < 1e-9 and abs(np.linalg.norm(t) - 1) < 1e-9
            and np.allclose(np.cross(o, t), n, atol=1e-9)):
        raise ValueError("tangents: must be unit vectors (o, t) with o x t = normal")
    return o.copy(), t.copy()
