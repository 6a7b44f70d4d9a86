"""The compiled growth-distance query: one call from Python per pair of poses (section 4.1).

Python's share of a query is then two type checks per pose and the result record: writing the
rotations into the program with numpy slices, forming r and checking the rotations in numpy cost
more than the shooter itself on small shapes (measured: 5 us of 20).
"""
import numpy as np
from numba import njit

from ._dispatch import shoot
from ._packed import pack
from ._shooters import HIT, LIMIT, _result
from ._warm import shoot_warm

OK = 0
BAD_POSE_A = 1       # not a proper rotation (R^T R = I to ROTATION_TOL, det R > 0) or not finite
BAD_POSE_B = 2
COINCIDENT = 3       # p_A = p_B: A(0) and B(0) are the same point, g(A, B) = 0

ROTATION_TOL = 1e-9
# warm start: the probes' spread follows the last change of the normal between calls, times
# SPREAD_GAIN (the ray must cross the probes' facet, and the next change is about the last one),
# within [SPREAD_MIN, SPREAD_MAX]. IE then needs about log2(spread^2 / eps) steps: on a pair
# moving by ~0.002 rad a call, 16 iterations instead of 19 with a fixed spread of 0.05 and 28 cold
SPREAD_GAIN = 4.0
SPREAD_MIN = 1e-3
SPREAD_MAX = 0.2

# the query's frame [R_A (9), p_A, R_B (9), p_B]: the entries ahead of the packed ray-shooting
# arrays (graspforce._packed)
FRAME = 24

@njit(cache=True)
def _proper(R, p):
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
          spread):
    """(code, status, t, t_upper, h_n, iterations, support_calls, singular, packed,
    next_spread) for Delta = R_A(A_0) - R_B(B_0) and r = p_B - p_A (eq. 10): the result of
    `_dispatch.shoot` with its arrays packed after the frame [R_A, p_A, R_B, p_B]
    (graspforce._packed). The frame is a copy, so that the record's contact stays right if the
    caller reuses its pose arrays. The program's Affine nodes hold M = R_A at
    floats[ma:ma + 9] and M = -R_B at floats[mb:mb + 9] (row-major), overwritten here. warm:
    start ZC-IE from probes around `normal` at `spread` (graspforce._warm); next_spread is the
    spread for the next warm call."""
    frame = np.empty(FRAME)
    for a in range(3):
        for b in range(3):
            frame[3 * a + b] = R_a[a, b]
            frame[12 + 3 * a + b] = R_b[a, b]
        frame[9 + a] = p_a[a]
        frame[21 + a] = p_b[a]
    code = OK
    if not _proper(R_a, p_a):
        code = BAD_POSE_A
    elif not _proper(R_b, p_b):
        code = BAD_POSE_B
    r = np.empty(3)
    rr = 0.0
    for a in range(3):
        r[a] = p_b[a] - p_a[a]
        rr += r[a] * r[a]
    if code == OK and rr == 0.0:
        code = COINCIDENT
    if code != OK:
        out = _result(LIMIT, 0.0, 0.0, 0.0, 0, 0, np.zeros(3), np.empty((0, 3)), np.empty(0),
                      np.empty((0, ws)), 0, 0)
    else:
        for a in range(3):
            for b in range(3):
                floats[ma + 3 * a + b] = R_a[a, b]
                floats[mb + 3 * a + b] = -R_b[a, b]
        if warm:
            out = shoot_warm(ints, floats, r, ws, eps, max_iter, normal, spread)
        else:
            out = shoot(ints, floats, r, ws, method, eps, max_iter)
    next_spread = spread
    if warm and out[0] == HIT:
        dn = 0.0
        for a in range(3):
            dn += (out[6][a] - normal[a]) ** 2
        next_spread = min(max(SPREAD_GAIN * np.sqrt(dn), SPREAD_MIN), SPREAD_MAX)
    return (code,) + pack(out, frame) + (next_spread,)
