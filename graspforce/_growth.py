"""The compiled growth-distance query: one call from Python per pair of poses (section 4.1).

Python's share of a query is then one call and the result record: writing the rotations into the
program with numpy slices, forming r, checking the poses and deciding the verdict in numpy cost
more than the shooter itself on small shapes (measured: 5 us of 20). The query is compiled for
one signature (graspforce._signature), so that a pose of another type (a list, float32, a
non-contiguous view) fails the call with a TypeError instead of compiling a new specialization
for minutes; the Python side then converts it and calls again (graspforce.growth). Its
arguments are arrays only, and it fills an array the caller allocated: each scalar argument and
each returned array costs the call from Python (measured: 16 arguments and a returned array
1.6 us, nine arrays 0.8 us). The solver's constants and warm-start memory (`TAIL`) ride at the end
of the program's floats, which the kernel reads only at its nodes' offsets: seven arrays, not nine.
"""
import numpy as np
from numba import njit, types

from ._dispatch import shoot
from ._jit import borrowing
from ._packed import HEAD, pack
from ._shooters import HIT, ZC_IE
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

# the query's frame [R_A (9), p_A, R_B (9), p_B, the shooter's head (graspforce._packed.HEAD)]:
# the entries ahead of the packed ray-shooting arrays
POSES = 24
FRAME = POSES + HEAD

# the last TAIL entries of the program's floats: the program's two rotation offsets, the witness
# size, the method, max_iter, whether to warm-start (integers), eps, touching_tol, then the warm
# start's memory (whether the last call was certified, the spread for the next one, the last
# normal)
MA, MB, WS, METHOD, MAX_ITER, WARM_START, EPS, TOUCHING_TOL, WARM, SPREAD, NORMAL = range(11)
TAIL = NORMAL + 3
WARM_SPREAD = 0.05     # first warm start: probes at the last normal +- this (a unit vector's tilt)
# a cold ZC-IE query's probes: around r itself, at this spread (graspforce._warm), instead of ZC
# from the origin. Delta changes with every pose, so no start table can be kept for it; but the
# normal at z_Delta(r) is rarely far from r, and the facet of three support points around r
# holds the ray (protocol, 300 contact pairs, compiled shot: spread 0 (ZC) 4.1 us and 25.8 IE
# steps, 0.05 3.8, 0.2 3.4, 0.7 3.35 and 23.4, 1.0 3.36, 2.0 3.44, 3.0 3.53). With IE's secant
# query (stop 28): 0 (ZC) 3.86 us and 25.8 steps, 0.05 3.00, 0.1 2.94, 0.2 2.76, 0.5 2.70,
# 0.7 2.69 and 18.3
COLD_SPREAD = 0.7

# the one signature of `query` (graspforce._signature)
SIGNATURE = (INTS, VECTOR, types.float64[:, ::1], VECTOR, types.float64[:, ::1], VECTOR, VECTOR)


@borrowing
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
def query(ints, floats, R_a, p_a, R_b, p_b, packed):
    """(code, verdict, sigma, sigma_lower, sigma_upper, iterations, support_calls) for
    Delta = R_A(A_0) - R_B(B_0) and r = p_B - p_A (eq. 10).

    code: OK, BAD_POSE_A / BAD_POSE_B (wrong shape, not finite, or not a proper rotation: R^T R
    = I to ROTATION_TOL and det R > 0), COINCIDENT (sigma = 0). With t r <= z_Delta(r) <=
    t_upper r the shooter's bracket, g lies in [1/t_upper, 1/t] (clamped: an exact face of
    Delta can put h_Delta(n) / n^T r an ulp below t); sigma is the midpoint, and the verdict is
    TOUCHING when the bracket widened by touching_tol holds 1, else SEPARATED (g > 1) or
    PENETRATING. 0 is interior to Delta (both origins are interior points), so the ray always
    hits and only max_iter stops it short: NOT_CERTIFIED, sigma = 1/t (the method's last
    estimate, inf for t = 0), bracket [0, inf].
    packed (FRAME + capacity(3, ws) entries): the frame [R_A, p_A, R_B, p_B, the shooter's
    head] (a copy, so that the record's contact stays right if the caller reuses its pose
    arrays), then the arrays of `_dispatch.shoot` (graspforce._packed). floats ends with TAIL
    (above); the program's Affine nodes hold M = R_A at floats[ma:ma + 9] and M = -R_B at
    floats[mb:mb + 9] (row-major), overwritten here. With WARM_START, a call after a certified
    one starts ZC-IE from probes around the last normal (graspforce._warm), spread by the last
    change of the normal; the tail remembers both. Any other ZC-IE call starts from probes
    around r (COLD_SPREAD); either falls back to ZC from the origin when the ray misses the
    probes' facets.
    """
    # one read per cache line of the program, before the kernel's chain of dependent reads
    # (ints[CSTART] -> ints[CHILDREN + ...] -> floats[PSTART + ...]) meets each line's miss one
    # after the other: in a loop over many pairs the solver's arrays are cold, and these reads'
    # misses overlap. Written to the packed head, which the shot overwrites, so that they stay.
    touched = 0.0
    for i in range(0, ints.shape[0], 8):
        touched += ints[i]
    for i in range(0, floats.shape[0], 8):
        touched += floats[i]
    # the last lines, whatever the arrays' alignment
    packed[POSES] = touched + ints[ints.shape[0] - 1] + floats[floats.shape[0] - 1]
    code = OK
    if not _proper(R_a, p_a):
        code = BAD_POSE_A
    elif not _proper(R_b, p_b):
        code = BAD_POSE_B
    if code != OK:
        return code, NOT_CERTIFIED, 0.0, 0.0, 0.0, 0, 0
    c = floats.shape[0] - TAIL
    ma = int(floats[c + MA])
    mb = int(floats[c + MB])
    # r and its direction: one allocation
    ray = np.empty((2, 3))
    r = ray[0]
    rr = 0.0
    for a in range(3):
        for b in range(3):
            packed[3 * a + b] = R_a[a, b]
            packed[12 + 3 * a + b] = R_b[a, b]
            floats[ma + 3 * a + b] = R_a[a, b]
            floats[mb + 3 * a + b] = -R_b[a, b]
        packed[9 + a] = p_a[a]
        packed[21 + a] = p_b[a]
        r[a] = p_b[a] - p_a[a]
        rr += r[a] * r[a]
    if rr == 0.0:
        # A(0) = B(0): no shot, an empty head, no normal to remember
        for a in range(POSES, FRAME):
            packed[a] = 0.0
        floats[c + WARM] = 0.0
        floats[c + SPREAD] = WARM_SPREAD
        return COINCIDENT, PENETRATING, 0.0, 0.0, 0.0, 0, 0
    ws = int(floats[c + WS])
    eps = floats[c + EPS]
    max_iter = int(floats[c + MAX_ITER])
    warm = floats[c + WARM] > 0.0
    normal = floats[c + NORMAL:c + NORMAL + 3]
    method = int(floats[c + METHOD])
    if warm:
        head = shoot_warm(ints, floats, r, ws, eps, max_iter, normal, floats[c + SPREAD], packed,
                          FRAME)
    elif method == ZC_IE:
        rn = 1.0 / np.sqrt(rr)
        for a in range(3):
            ray[1, a] = r[a] * rn
        head = shoot_warm(ints, floats, r, ws, eps, max_iter, ray[1], COLD_SPREAD, packed, FRAME)
    else:
        head = pack(shoot(ints, floats, r, ws, method, eps, max_iter), packed, FRAME)
    status, t, t_up, h_n, iterations, calls, singular, k = head
    packed[POSES] = status
    packed[POSES + 1] = t
    packed[POSES + 2] = t_up
    packed[POSES + 3] = h_n
    packed[POSES + 4] = iterations
    packed[POSES + 5] = calls
    packed[POSES + 6] = singular
    packed[POSES + 7] = k
    if floats[c + WARM_START] != 0.0:
        # the first warm call probes at WARM_SPREAD, the next ones at the last change of the
        # normal times SPREAD_GAIN
        if status == HIT and warm:
            dn = 0.0
            for a in range(3):
                dn += (packed[FRAME + a] - normal[a]) ** 2
            floats[c + SPREAD] = min(max(SPREAD_GAIN * np.sqrt(dn), SPREAD_MIN), SPREAD_MAX)
        else:
            floats[c + SPREAD] = WARM_SPREAD
        floats[c + WARM] = 1.0 if status == HIT else 0.0
        if status == HIT:
            for a in range(3):
                normal[a] = packed[FRAME + a]
    if status != HIT:
        sigma = 1.0 / t if t > 0.0 else np.inf
        return code, NOT_CERTIFIED, sigma, 0.0, np.inf, iterations, calls
    upper = 1.0 / t
    lower = min(1.0 / t_up, upper)
    tol = floats[c + TOUCHING_TOL]
    if lower - tol <= 1.0 <= upper + tol:
        verdict = TOUCHING
    else:
        verdict = SEPARATED if lower > 1.0 else PENETRATING
    return code, verdict, 0.5 * (lower + upper), lower, upper, iterations, calls
