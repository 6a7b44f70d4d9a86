"""One compiled entry point from Python for every ray-shooting procedure."""
import numpy as np
from numba import njit

from ._ie import ie
from ._shooters import (BI_GJK, GJK_BASED, HIT, IE, LIMIT, WITH_IE, WITH_NEWTON, ZC_IE,
                        ZC_IE_NEWTON, ZC_ONLY, bi_gjk, gjk_based, zc_family, zc_from)


@njit(cache=True)
def shoot(ints, floats, r, ws, method, eps, max_iter):
    """Dispatch on the method code: one call from Python, one compilation for all."""
    if method == IE:
        out = ie(ints, floats, r, ws, eps, max_iter)
    elif method == ZC_IE:
        out = zc_family(ints, floats, r, ws, eps, max_iter, WITH_IE)
    elif method == ZC_IE_NEWTON:
        out = zc_family(ints, floats, r, ws, eps, max_iter, WITH_NEWTON)
    else:
        out = _distance_based(ints, floats, r, ws, method, eps, max_iter)
    # GJK-based's own stalls are its finish's (ZC's): walking the ray again would repeat them
    return out if method == GJK_BASED else unstall(ints, floats, r, ws, eps, max_iter, out)


@njit(cache=True)
def _distance_based(ints, floats, r, ws, method, eps, max_iter):
    """GJK-based, Bi-GJK or ZC-based, finished by IE steps where they stall or stop above eps."""
    if method == GJK_BASED:
        out = gjk_based(ints, floats, r, ws, eps, max_iter)
    elif method == BI_GJK:
        out = bi_gjk(ints, floats, r, ws, eps, max_iter)
    else:
        out = zc_family(ints, floats, r, ws, eps, max_iter, ZC_ONLY)
    # a LIMIT short of max_iter is a stall (zc_from): handed over like an uncertified hit
    stalled = out[0] == LIMIT and out[4] < max_iter
    if not stalled and (out[0] != HIT or out[2] - out[1] <= eps * out[1]):
        return out
    # GJK's simplex and ZC's cone from b_k lose rank near the boundary (relative singular values
    # ~1e-13) and can stall above eps, seen on a third of the ingot grasp's rays at eps = 1e-9.
    # IE's facets are solved from the origin and stay well-conditioned: finish with IE steps,
    # from the final facet when there is one (ZC-based on the ingot: mean support calls
    # 116 -> 102), else, or if that fails too, from scratch, so that "hit" always means
    # certified to eps. The hand-over counts as a singular step.
    if out[7].shape[0] == r.shape[0]:
        none = np.empty((0, 0))
        fin = zc_from(ints, floats, r, ws, eps, max_iter, WITH_IE, out[1], out[7], out[9],
                      out[8], r.shape[0], 0, 0, none, none)
        if fin[0] == HIT and fin[2] - fin[1] <= eps * fin[1]:
            return _handed_over(out, fin)
    return _handed_over(out, ie(ints, floats, r, ws, eps, max_iter))


@njit(cache=True)
def unstall(ints, floats, r, ws, eps, max_iter, out):
    """`out`, or where it is a stall (a LIMIT short of max_iter: zc_from), GJK-based's answer
    when that one is certified. ZC's cone from b_k loses rank where the ray runs along a flat
    or thin part of A: W_Linf's lift for a doubled point contact and a wrench 1e-9 inside its
    friction cone (a 3-D set in R^7), two point contacts at a corner of W. ZC-based steps then
    stall with the bracket open, and IE and ZC-IE, which hand over to them, with them; GJK's
    simplex, walking down the ray from outside, does not lose rank there (and where GJK-based
    stops short, IE steps from its facet may not: `_distance_based`)."""
    if not (out[0] == LIMIT and out[4] < max_iter):
        return out
    fin = _distance_based(ints, floats, r, ws, GJK_BASED, eps, max_iter - out[4])
    if fin[0] != LIMIT:
        return _handed_over(out, fin)
    return _handed_over(fin, out)


@njit(cache=True)
def _handed_over(out, fin):
    """The finish's result, with the counts of both shots and the hand-over as a singular step."""
    return (fin[0], fin[1], fin[2], fin[3], out[4] + fin[4], out[5] + fin[5], fin[6], fin[7],
            fin[8], fin[9], out[10] + fin[10] + 1)
