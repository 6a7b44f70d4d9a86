"""The paper's growth-distance protocol (section 4.2, fig. 7): an ellipsoid touching a truncated cone
through its side surface, a base rim edge, or a base face, at random sizes and poses; scaled by
1/2 or 2 about their reference points the growth distance becomes 2 or 1/2.

Plain numpy: the pairs are built from geometry, not from graspforce, so their truth (1, 2, 0.5)
is independent of the code under test. A pair is a dict with the ellipsoid's semi-axes and pose,
the truncated cone's radii, height and pose (reference points: the ellipsoid's centre and the
midpoint of the cone's axis, its local origin), the contact point and the contact normal (from
the cone to the ellipsoid).
"""
import numpy as np

CASES = ("side", "rim", "base")
SCALES = {"contact": (1.0, 1.0), "separate": (0.5, 2.0), "penetrate": (2.0, 0.5)}


def random_rotation(rng):
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def touching_pair(rng, case):
    """An ellipsoid touching a truncated cone through `case` ("side", "rim", "base")."""
    axes = rng.uniform(0.5, 1.5, 3)
    rb, rt = rng.uniform(0.3, 1.0, 2)
    h = rng.uniform(0.5, 2.0)
    R_c, p_c = random_rotation(rng), rng.normal(0.0, 1.0, 3)
    R_e = random_rotation(rng)
    phi = rng.uniform(0, 2 * np.pi)
    radial = np.array([np.cos(phi), np.sin(phi), 0.0])
    side_normal = radial + np.array([0.0, 0.0, (rb - rt) / h])
    side_normal /= np.linalg.norm(side_normal)
    top = rng.random() < 0.5
    z, rad, axial = (0.5 * h, rt, 1.0) if top else (-0.5 * h, rb, -1.0)
    if case == "side":
        s = rng.uniform(-0.4, 0.4)                       # away from the rims
        q0 = (rb + (rt - rb) * (s + 0.5)) * radial + np.array([0.0, 0.0, s * h])
        n0 = side_normal
    elif case == "rim":
        q0 = rad * radial + np.array([0.0, 0.0, z])
        w = rng.uniform(0.1, 0.9)                        # inside the rim's normal cone
        n0 = w * side_normal + (1 - w) * np.array([0.0, 0.0, axial])
        n0 /= np.linalg.norm(n0)
    else:
        q0 = rng.uniform(0, 0.8) * rad * np.array([np.cos(phi + 1), np.sin(phi + 1), 0.0])
        q0[2] = z
        n0 = np.array([0.0, 0.0, axial])
    q = p_c + R_c @ q0
    n = R_c @ n0
    # the ellipsoid's boundary point with outward normal -n is its support point in -n
    S = R_e @ np.diag(axes)
    y = S.T @ (-n)
    p_e = q - S @ y / np.linalg.norm(y)
    return {"axes": axes, "R_e": R_e, "p_e": p_e, "rb": rb, "rt": rt, "h": h, "R_c": R_c,
            "p_c": p_c, "point": q, "normal": n, "case": case}


def protocol_pairs(n, seed=0, cases=CASES):
    """n touching pairs per case, cycling through the cases."""
    rng = np.random.default_rng(seed)
    return [touching_pair(rng, cases[i % len(cases)]) for i in range(n)]


def scaled_shapes(pair, scale):
    """(ellipsoid semi-axes, (rb, rt, h)) of the pair scaled about the reference points."""
    return pair["axes"] * scale, (pair["rb"] * scale, pair["rt"] * scale, pair["h"] * scale)


def random_shapes(k, seed=0):
    """k random ellipsoids and truncated cones (alternating) with random poses, for the
    all-pairs row of table 2: ("ellipsoid", axes, R, p) or ("cone", (rb, rt, h), R, p)."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(k):
        R, p = random_rotation(rng), rng.normal(0.0, 2.0, 3)
        if i % 2 == 0:
            out.append(("ellipsoid", rng.uniform(0.5, 1.5, 3), R, p))
        else:
            out.append(("cone", (*rng.uniform(0.3, 1.0, 2), rng.uniform(0.5, 2.0)), R, p))
    return out
