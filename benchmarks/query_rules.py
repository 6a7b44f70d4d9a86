"""Support calls of IE under other query rules, on the growth protocol's contact pairs (numpy).

IE (section 3.2) queries the support map in the normal of the facet the ray crosses, a cutting
plane step: its facet shrinks by about half a step on curved contacts, so a query at eps = 1e-9
takes 26-36 support calls. This script counts the calls of other rules on
the same pairs, to show which change could cut them. It is not timed: the shooter here is plain
numpy around `Delta.support_witness`, and only the number of support calls is compared.

    python -m benchmarks.query_rules              # 150 pairs (50 per contact case)
    python -m benchmarks.query_rules --n 30

Every rule keeps IE's invariant and certificate: n support points whose facet the ray crosses
(lower bound t, the crossing) and the best h_Delta(u) / u^T r over the queried normals (upper
bound); it stops when the two are within eps relative. A facet the ray misses by rounding, or
one whose points crowd (condition number above MAX_CONDITION, as the model's points do), is
given up for the previous one and its normal. Each starts from the same facet: support
points in n directions spread around r (widened until the ray crosses their facet). The rules:

- facet: query the facet's normal (the paper's IE).
- pool: the facet normal, but after each step every support point collected so far may re-enter
  by the ratio test (Kelley's cutting plane model over all cuts, not IE's n).
- model: fit a quadratic surface to the last three support points and their query normals
  (Hermite data: a point and a tangent plane each) and query the model's normal where the ray
  leaves it; the facet normal when the fit fails, and for one step after a model query whose
  point does not lie beyond the facet (which moves only the upper bound).
- model-until-miss: the model, until its first query whose point does not lie beyond the
  facet; the facet normal from then on.
- model-on-smooth: the model only when the last three support points come from one smooth piece
  of Delta: in every leaf of Delta's program, their leaf-local points (the witnesses) lie within
  SAME_PIECE of each other, relative to their size. Points on the two rims of a cone's side, or
  around a base disk's rim, differ: the facet normal there.

The truth of a contact pair is g = 1 (t = 1): the error column checks every rule.
"""
import argparse

import numpy as np

from benchmarks.growth_sets import CASES, protocol_pairs

RULES = ("facet", "pool", "model", "model-until-miss", "model-on-smooth")
EPS = 1e-9
MAX_CALLS = 300
MODEL_POINTS = 3
MODEL_START = 3      # facet steps before the first model query: the model needs close points
MAX_CONDITION = 1e7  # the model's points can crowd: keep the facet's crossing exact to ~1e-9
SAME_PIECE = 0.2     # leaf-local points this close (relative) are taken as one smooth piece


def probe_facet(support, r):
    """n support points in directions around r whose facet the ray crosses, with the directions
    and the points' leaf-local witnesses."""
    n = r.shape[0]
    rhat = r / np.linalg.norm(r)
    # a regular simplex centred at 0 in the plane orthogonal to r: the rows of I - 1/n live in
    # the plane orthogonal to (1, ..., 1); both planes get an orthonormal basis from an SVD
    to_plane = np.linalg.svd(np.eye(n) - np.outer(rhat, rhat))[0][:, :n - 1]
    centred = np.eye(n) - 1.0 / n
    simplex = centred @ np.linalg.svd(centred)[0][:, :n - 1] @ to_plane.T
    spread = 0.5
    for _ in range(30):
        U = rhat + spread * simplex
        U /= np.linalg.norm(U, axis=1)[:, None]
        out = [support(u) for u in U]
        P = np.array([point for _, point, _ in out])
        if np.linalg.matrix_rank(P) == n and np.linalg.solve(P.T, r).min() > 0.0:
            return P, U, [piece for _, _, piece in out]
        spread *= 2.0
    raise RuntimeError("no probe facet crosses the ray: is the origin interior to the set?")


def model_normal(points, normals, z, r, e3):
    """The normal where the ray z + s r leaves the quadratic surface x3 = f(x1, x2) (a frame with
    x3 along e3, origin z) fitted to the points and their tangent planes; None when it fails."""
    e1 = np.eye(3)[np.argmin(np.abs(e3))]
    e1 = e1 - (e1 @ e3) * e3
    e1 /= np.linalg.norm(e1)
    frame = np.array([e1, np.cross(e3, e1), e3])
    rows, rhs = [], []
    for p, u in zip(points, normals):
        q, v = frame @ (p - z), frame @ u
        if v[2] <= 1e-3:
            return None
        x, y = q[0], q[1]
        # f = c + g1 x + g2 y + (h11 x^2 + 2 h12 x y + h22 y^2) / 2 and its gradient -v12 / v3
        rows += [[1, x, y, x * x / 2, x * y, y * y / 2], [0, 1, 0, x, y, 0], [0, 0, 1, 0, x, y]]
        rhs += [q[2], -v[0] / v[2], -v[1] / v[2]]
    c = np.linalg.lstsq(np.array(rows), np.array(rhs), rcond=None)[0]
    d = frame @ r
    a = (c[3] * d[0] ** 2 + 2 * c[4] * d[0] * d[1] + c[5] * d[1] ** 2) / 2
    b = c[1] * d[0] + c[2] * d[1] - d[2]
    if abs(a) < 1e-14:
        s = -c[0] / b
    else:
        disc = b * b - 4 * a * c[0]
        if disc < 0.0:
            return None
        s = min(((-b + sign * np.sqrt(disc)) / (2 * a) for sign in (1, -1)), key=abs)
    x, y = s * d[0], s * d[1]
    u = frame.T @ np.array([-(c[1] + c[3] * x + c[4] * y), -(c[2] + c[4] * x + c[5] * y), 1.0])
    return u / np.linalg.norm(u)


def one_piece(pieces):
    """Whether the leaf-local points of these support points agree leaf by leaf."""
    for locals_ in zip(*pieces):
        size = max(np.linalg.norm(x) for x in locals_) + 1e-300
        if max(np.linalg.norm(a - b) for a in locals_ for b in locals_) > SAME_PIECE * size:
            return False
    return True


def witness_support(X):
    """u -> (h_X(u), s_X(u), the leaf-local points of s_X(u), leaf by leaf)."""
    def support(u):
        h, point, witness = X.support_witness(u)
        return h, point, [np.asarray(local, dtype=float) for _, local in witness]
    return support


def ratio_test(B, gam, s):
    """The vertex s replaces so that the ray still crosses the facet (B: the facet's inverse)."""
    alpha = B @ s
    ratios = np.where(alpha > 0.0, gam / np.where(alpha > 0.0, alpha, 1.0), np.inf)
    return int(np.argmin(ratios))


def shoot(support, r, rule):
    """(support calls, t, t_upper) of IE with the given query rule."""
    n = r.shape[0]
    P, U, pieces = probe_facet(support, r)
    calls = n
    points, normals = list(P), list(U)
    t_up = np.inf
    model_on = rule.startswith("model")
    missed = False
    previous = P.copy()
    for step in range(MAX_CALLS):
        B = np.linalg.inv(P.T)
        y, gam = B.T @ np.ones(n), B @ r
        if gam.min() < -1e-12 * gam.sum() or np.linalg.cond(P) > MAX_CONDITION:
            # rounding: the ray misses this facet, or its points crowd so close that its
            # crossing is not a lower bound to eps. Back to the previous facet, and its normal.
            P = previous.copy()
            B = np.linalg.inv(P.T)
            y, gam = B.T @ np.ones(n), B @ r
            missed = True
        previous = P.copy()
        t = 1.0 / (y @ r)
        u = y / np.linalg.norm(y)
        smooth = rule != "model-on-smooth" or one_piece(pieces[-MODEL_POINTS:])
        if model_on and step >= MODEL_START and not missed and smooth:
            m = model_normal(points[-MODEL_POINTS:], normals[-MODEL_POINTS:], t * r, r, u)
            u = m if m is not None and m @ r > 0.0 else u
        h, s, piece = support(u)
        calls += 1
        t_up = min(t_up, h / (u @ r))
        if t_up - t <= EPS * t:
            break
        points.append(s)
        normals.append(u)
        pieces.append(piece)
        missed = y @ s <= 1.0 + 1e-12
        if missed:
            # not beyond the facet: only the upper bound moved
            model_on = model_on and rule != "model-until-miss"
            continue
        P[ratio_test(B, gam, s)] = s
        # pool: the point farthest beyond the new facet re-enters, and so on (a bounded number
        # of pivots: degenerate ones can cycle, as in the simplex method)
        for _ in range(len(points) if rule == "pool" else 0):
            B = np.linalg.inv(P.T)
            y, gam = B.T @ np.ones(n), B @ r
            j = int(np.argmax([y @ q for q in points]))
            if y @ points[j] <= 1.0 + 1e-12:
                break
            P[ratio_test(B, gam, points[j])] = points[j]
    return calls, t, t_up


def run(n_pairs=150, seed=0, log=print):
    import graspforce as gf
    pairs = protocol_pairs(n_pairs, seed)
    queries = []
    for pair in pairs:
        A = gf.Ellipsoid(np.zeros(3), np.diag(pair["axes"]))
        C = gf.TruncatedCone(pair["rb"], pair["rt"], pair["h"])
        # Delta = R_A(A) - R_C(C) at the pair's poses, and r from A's origin to C's
        delta = gf.minkowski_sum(gf.affine(pair["R_e"], A), gf.affine(-pair["R_c"], C))
        queries.append((pair["case"], witness_support(delta), pair["p_c"] - pair["p_e"]))
    log("| rule | " + " | ".join(f"{c}: mean / median / max calls" for c in CASES)
        + " | max abs error of g |")
    log("|---|" + "---|" * len(CASES) + "---|")
    for rule in RULES:
        calls = {c: [] for c in CASES}
        err = 0.0
        for case, support, r in queries:
            k, t, t_up = shoot(support, r, rule)
            calls[case].append(k)
            err = max(err, abs(1.0 / t - 1.0), abs(1.0 / t_up - 1.0))
        cells = [f"{np.mean(v):.1f} / {np.median(v):.0f} / {max(v)}" for v in calls.values()]
        log(f"| {rule} | " + " | ".join(cells) + f" | {err:.2e} |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=150, help="contact pairs (cycling the cases)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    run(args.n, args.seed)


if __name__ == "__main__":
    main()
