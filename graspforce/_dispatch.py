"""One compiled entry point from Python for every ray-shooting procedure."""
from numba import njit

from ._ie import ie
from ._shooters import (BI_GJK, GJK_BASED, IE, WITH_IE, ZC_IE, ZC_ONLY, bi_gjk, gjk_based,
                        zc_family)


@njit(cache=True)
def shoot(ints, floats, r, ws, method, eps, max_iter):
    """Dispatch on the method code: one call from Python, one compilation for all."""
    if method == GJK_BASED:
        return gjk_based(ints, floats, r, ws, eps, max_iter)
    if method == BI_GJK:
        return bi_gjk(ints, floats, r, ws, eps, max_iter)
    if method == IE:
        return ie(ints, floats, r, ws, eps, max_iter)
    return zc_family(ints, floats, r, ws, eps, max_iter, WITH_IE if method == ZC_IE else ZC_ONLY)
