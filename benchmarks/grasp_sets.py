"""Wrench sets of a four-contact soft-finger grasp of an "ingot" (paper section 5, fig. 9b).

The paper does not dimension the ingot of fig. 9b (NOTES.md item 6), so this module defines one.

Geometry (metres, object frame, origin at the centre of mass, z up):

* a right trapezoidal prism: bottom face 0.10 (x) by 0.06 (y) at z = -zc, top face 0.07 by 0.06 at
  z = 0.04 - zc, height 0.04, where zc = 0.04 (2 b + a) / (3 (a + b)) = 0.01882 is the height of the
  centre of mass above the bottom face (a = 0.10, b = 0.07). The two faces normal to y are vertical;
  the two faces normal to (+-0.04, 0, 0.015) are slanted: each leans inwards by
  atan(0.015 / 0.04) = 20.56 degrees from the vertical.
* four soft-finger contacts, two per slanted face, at the face's mid-height (z = 0.02 - zc) and at
  y = -0.02 and y = +0.02. The +x face holds contacts 1 (y = -0.02) and 2 (y = +0.02), the -x face
  contacts 3 (y = -0.02) and 4 (y = +0.02).
* at each contact: n = the inward unit normal of the face (it points inwards and slightly down),
  o = (0, 1, 0) and t = n x o, so that (o, t, n) is right-handed and n = o x t as in eq. (11).
* friction: mu = 0.5 (tangential), mu_s = 0.05 m (torsional), the same at every contact.

Why the top face is 0.07 and not 0.06 wide: with 0.06 the faces lean by atan(0.02 / 0.04) =
atan(0.5) = atan(mu), so the upper edge of every friction cone is exactly horizontal. The grasp then
cannot push the ingot upwards at all, is not force-closure, and every wrench with a downward force
(half of the random ones) sits on the boundary of feasibility. With 0.07 the friction cones reach
6 degrees above the horizontal: the grasp is force-closure (every random wrench is resistible) but
the margin is small, so some wrenches need large contact forces, which is realistic for a bar held
on its sloped sides.

Wrench sets (eq. 14): G_i = [[n, o, t, 0], [p x n, p x o, p x t, n]] (6 x 4) maps the contact force
(f1, f2, f3, f4) = (normal force, two tangential forces, spin moment) to a wrench (force, torque
about the origin). U_i = {f1 = 1, (f2^2 + f3^2)/mu^2 + f4^2/mu_s^2 <= 1} (the convex hull of the
ellipse of eq. 14, NOTES.md item 3), so W_i = G_i(U_i) is the degenerate ellipsoid
{c_i + S_i x : ||x|| <= 1} with c_i = G_i[:, 0] and S_i = G_i[:, 1:4] diag(mu, mu, mu_s) (6 x 3,
rank 3 in R^6), and W_L1 = CH(W_1 U ... U W_4). The minimum of sigma_L1 = sum_i f_i1 that resists
w_ext is 1 / t, where t r (r = -w_ext) is the farthest point of W_L1 on the ray R(r).
"""
import numpy as np

MU = 0.5
MU_S = 0.05
BOTTOM = (0.10, 0.06)   # x, y extents of the bottom face
TOP = (0.07, 0.06)      # x, y extents of the top face
HEIGHT = 0.04
CONTACT_Y = (-0.02, 0.02)


def ingot_contacts():
    """The four contacts as a list of (p, n, o, t), each a (3,) array, in the order documented above."""
    a, b, h = BOTTOM[0], TOP[0], HEIGHT
    zc = h * (2 * b + a) / (3 * (a + b))       # centre of mass above the bottom face
    z_mid = 0.5 * h - zc                         # the faces' mid-height in the object frame
    x_mid = 0.25 * (a + b)                       # |x| of a slanted face at mid-height
    dx = 0.5 * (a - b)                           # how far a slanted face leans in over the height
    contacts = []
    for side in (1.0, -1.0):                     # +x face, then -x face
        outward = np.array([side * h, 0.0, dx])
        n = -outward / np.linalg.norm(outward)
        o = np.array([0.0, 1.0, 0.0])
        t = np.cross(n, o)
        for y in CONTACT_Y:
            p = np.array([side * x_mid, y, z_mid])
            contacts.append((p, n, o, t))
    return contacts


def contact_matrix(p, n, o, t):
    """G_i of eq. (11): [[n, o, t, 0], [p x n, p x o, p x t, n]], shape (6, 4)."""
    G = np.zeros((6, 4))
    G[:3, 0], G[:3, 1], G[:3, 2] = n, o, t
    G[3:, 0], G[3:, 1], G[3:, 2] = np.cross(p, n), np.cross(p, o), np.cross(p, t)
    G[3:, 3] = n
    return G


def ingot_ellipsoids(mu=MU, mu_s=MU_S):
    """(center (6,), shape (6, 3)) of W_i = G_i(U_i) for every contact: plain numpy, no graspforce."""
    scale = np.diag([mu, mu, mu_s])
    out = []
    for p, n, o, t in ingot_contacts():
        G = contact_matrix(p, n, o, t)
        out.append((G[:, 0].copy(), G[:, 1:4] @ scale))
    return out


def ingot_grasp_sets(mu=MU, mu_s=MU_S):
    """(W_L1, [(center, shape), ...]): W_L1 = gf.hull(W_1, ..., W_4) (eq. 14) and the data of each W_i."""
    import graspforce as gf
    ellipsoids = ingot_ellipsoids(mu, mu_s)
    W = gf.hull(*[gf.Ellipsoid(center=c, shape=S) for c, S in ellipsoids])
    return W, ellipsoids


def ingot_grasp(mu=MU, mu_s=MU_S):
    """The same four contacts as a gf.Grasp (for Grasp.min_force and the baselines)."""
    import graspforce as gf
    return gf.Grasp(gf.Contact(p, n, mu, mu_s, tangents=(o, t)) for p, n, o, t in ingot_contacts())


def random_wrenches(k, seed=0):
    """k random external wrenches (k, 6): forces ~ N(0, 10 N), torques ~ N(0, 0.5 Nm) per component.

    The ray of the ray-shooting problem is r = -w_ext.
    """
    rng = np.random.default_rng(seed)
    return np.hstack([rng.normal(0.0, 10.0, (k, 3)), rng.normal(0.0, 0.5, (k, 3))])


def cone_outside(contact, f):
    """How far the local force f lies outside F_i of eq. (12), in its own units (<= 0 inside),
    from the contact's mu and mu_spin alone: its cone's excess or a negative normal force."""
    tangential = np.hypot(f[1], f[2])
    if contact.mu == 0.0:
        excess = max(tangential, abs(f[3]))
    elif contact.mu_spin == 0.0:
        excess = max(tangential / contact.mu - f[0], abs(f[3]))
    else:
        excess = np.hypot(tangential / contact.mu, f[3] / contact.mu_spin) - f[0]
    return max(excess, -f[0])


def support_L1(ellipsoids, u):
    """h_{W_L1}(u) in closed form (NOTES.md item 3): max_i c_i.u + ||S_i^T u||. Independent of graspforce."""
    return max(c @ u + np.linalg.norm(S.T @ u) for c, S in ellipsoids)
