"""Compiled entry points of the distance algorithms, one call from Python each."""
import numpy as np
from numba import njit

from ._distance import gjk, scratch, zc
from ._linalg import dot


@njit(cache=True)
def closest_point(ints, floats, b, ws, eps, max_iter):
    n = b.shape[0]
    P = np.empty((n + 2, n))
    Wt = np.empty((n + 2, ws))
    lam = np.empty(n + 2)
    nvec = np.empty(n)
    v = np.empty(n)
    point = np.empty(n)
    wit = np.empty(ws)
    st, k, d, h, it, calls = gjk(ints, floats, b, P, Wt, lam, 0, eps, 0.0, False, max_iter,
                                 nvec, v, point, wit, scratch(n))
    gap = h - dot(nvec, v) if st != 1 else 0.0
    return st, d, gap, it, calls, v.copy(), P[:k].copy(), lam[:k].copy(), Wt[:k].copy()


@njit(cache=True)
def cone_distance(ints, floats, b, ws, eps, max_iter):
    n = b.shape[0]
    P = np.empty((n + 2, n))
    Wt = np.empty((n + 2, ws))
    lam = np.empty(n + 2)
    nvec = np.empty(n)
    v = np.empty(n)
    point = np.empty(n)
    wit = np.empty(ws)
    st, k, d, h, it, calls = zc(ints, floats, np.zeros(n), b, P, Wt, lam, 0, 0.0, eps,
                                max_iter, nvec, v, point, wit, scratch(n))
    if st == 1:
        nvec[:] = 0.0
    return st, d, h, it, calls, v.copy(), nvec.copy(), P[:k].copy(), lam[:k].copy(), Wt[:k].copy()
