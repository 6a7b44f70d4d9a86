"""The compiled growth-distance query: one call from Python per pair of poses (section 4.1).

Python's share of a query is then one call and the result record: writing the rotations into the
program with numpy slices, forming r, checking the poses and deciding the verdict in numpy cost
more than the shooter itself on small shapes (measured: 5 us of 20). The query is compiled for
one signature (graspforce._signature), so that a pose of another type (a list, float32, a
non-contiguous view) fails the call with a TypeError instead of compiling a new specialization
for minutes; the Python side then converts it and calls again (graspforce.growth).
"""
import numpy as np
from numba import njit, types

from ._dispatch import shoot
from ._packed import HEAD, pack
from ._shooters import HIT
from ._signature import INTS, VECTOR
from ._warm import shoot_warm

OK = 0
BAD_POSE_A = 1       # not a proper rotation (R^T R = I to ROTATION_TOL, det R > 0) or not finite
BAD_POSE_B = 2
COINCIDENT = 3       # p_A = p_B: A(0) and B(0) are the same point, g(A, B) = 0

# the verdict of a query whose poses are valid (graspforce.growth names them)
SEPARATED = 0
TOUCHING = 1
PENETRATING = 2
NOT_CERTIFIED = 3    # max_iter: the bracket did not close

ROTATION_TOL = 1e-9
# warm start: the probes' spread follows the last change of the normal between calls, times
# SPREAD_GAIN (the ray must cross the probes' facet, and the next change is about the last one),
# within [SPREAD_MIN, SPREAD_MAX]. IE then needs about log2(spread^2 / eps) steps: on a pair
# moving by ~0.002 rad a call, 16 iterations instead of 19 with a fixed spread of 0.05 and 28 cold
SPREAD_GAIN = 4.0
SPREAD_MIN = 1e-3
SPREAD_MAX = 0.2

# the query's frame [R_A (9), p_A, R_B (9), p_B, status, t, t_upper, h_n, iterations,
# support_calls, singular_steps]: the entries ahead of the packed ray-shooting arrays
# (graspforce._packed); the last seven are the shooter's scalars (_packed.HEAD)
POSES = 24
FRAME = POSES + HEAD

# the one signature of `query` (graspforce._signature)
SIGNATURE = (INTS, VECTOR, types.int64, types.int64, types.int64,
              types.float64[:, ::1], VECTOR, types.float64[:, ::1], VECTOR, types.int64,
              types.float64, types.int64, types.boolean, VECTOR, types.float64, types.float64)

@njit(cache=True)
def _proper(R, p):
    if R.shape[0] != 3 or R.shape[1] != 3 or p.shape[0] != 3:
        return False
    for a in range(3):
        if not np.isfinite(p[a]):
            return False
        for b in range(3):
            s = 0.0
            for c in range(3):
                s += R[c, a] * R[c, b]
            # written so that NaN fails it
            if not abs(s - (1.0 if a == b else 0.0)) <= ROTATION_TOL:
                return False
    det = (R[0, 0] * (R[1, 1] * R[2, 2] - R[1, 2] * R[2, 1])
           - R[0, 1] * (R[1, 0] * R[2, 2] - R[1, 2] * R[2, 0])
           + R[0, 2] * (R[1, 0] * R[2, 1] - R[1, 1] * R[2, 0]))
    return det > 0.0


@njit(cache=True)
def query(ints, floats, ma, mb, ws, R_a, p_a, R_b, p_b, method, eps, max_iter, warm, normal,
          spread, touching_tol):
    """(code, verdict, sigma, sigma_lower, sigma_upper, iterations, support_calls, next_spread,
    packed) for Delta = R_A(A_0) - R_B(B_0) and r = p_B - p_A (eq. 10).

    code: OK, BAD_POSE_A / BAD_POSE_B (wrong shape, not finite, or not a proper rotation: R^T R
    = I to ROTATION_TOL and det R > 0), COINCIDENT (sigma = 0). With t r <= z_Delta(r) <=
    t_upper r the shooter's bracket, g lies in [1/t_upper, 1/t] (clamped: an exact face of
    Delta can put h_Delta(n) / n^T r an ulp below t); sigma is the midpoint, and the verdict is
    TOUCHING when the bracket widened by touching_tol holds 1, else SEPARATED (g > 1) or
    PENETRATING. 0 is interior to Delta (both origins are interior points), so the ray always
    hits and only max_iter stops it short: NOT_CERTIFIED, sigma = 1/t (the method's last
    estimate, inf for t = 0), bracket [0, inf].
    packed: the frame [R_A, p_A, R_B, p_B, the shooter's scalars] (a copy, so that the record's
    contact stays right if the caller reuses its pose arrays), then the result of
    `_dispatch.shoot` (graspforce._packed). The program's Affine nodes hold M = R_A at
    floats[ma:ma + 9] and M = -R_B at floats[mb:mb + 9] (row-major), overwritten here. warm:
    start ZC-IE from probes around `normal` at `spread` (graspforce._warm); next_spread is the
    spread for the next warm call."""
    frame = np.zeros(FRAME)
    code = OK
    if not _proper(R_a, p_a):
        code = BAD_POSE_A
    elif not _proper(R_b, p_b):
        code = BAD_POSE_B
    if code != OK:
        return code, NOT_CERTIFIED, 0.0, 0.0, 0.0, 0, 0, spread, frame
    r = np.empty(3)
    rr = 0.0
    for a in range(3):
        for b in range(3):
            frame[3 * a + b] = R_a[a, b]
            frame[12 + 3 * a + b] = R_b[a, b]
            floats[ma + 3 * a + b] = R_a[a, b]
            floats[mb + 3 * a + b] = -R_b[a, b]
        frame[9 + a] = p_a[a]
        frame[21 + a] = p_b[a]
        r[a] = p_b[a] - p_a[a]
        rr += r[a] * r[a]
    if rr == 0.0:
        return COINCIDENT, PENETRATING, 0.0, 0.0, 0.0, 0, 0, spread, frame
    if warm:
        out = shoot_warm(ints, floats, r, ws, eps, max_iter, normal, spread)
    else:
        out = shoot(ints, floats, r, ws, method, eps, max_iter)
    status, t, t_up = out[0], out[1], out[2]
    frame[POSES] = status
    frame[POSES + 1] = t
    frame[POSES + 2] = t_up
    frame[POSES + 3] = out[3]
    frame[POSES + 4] = out[4]
    frame[POSES + 5] = out[5]
    frame[POSES + 6] = out[10]
    next_spread = spread
    if status != HIT:
        sigma = 1.0 / t if t > 0.0 else np.inf
        return (code, NOT_CERTIFIED, sigma, 0.0, np.inf, out[4], out[5], next_spread,
                pack(out, frame)[7])
    if warm:
        dn = 0.0
        for a in range(3):
            dn += (out[6][a] - normal[a]) ** 2
        next_spread = min(max(SPREAD_GAIN * np.sqrt(dn), SPREAD_MIN), SPREAD_MAX)
    upper = 1.0 / t
    lower = min(1.0 / t_up, upper)
    if lower - touching_tol <= 1.0 <= upper + touching_tol:
        verdict = TOUCHING
    else:
        verdict = SEPARATED if lower > 1.0 else PENETRATING
    return (code, verdict, 0.5 * (lower + upper), lower, upper, out[4], out[5], next_spread,
            pack(out, frame)[7])
