"""Input checks that name the field and the rule."""
import math

import numpy as np

from ._core import finite_min


def finite_array(value, name, ndim=None, shape=None, minimum=None):
    try:
        # C order: a leaf's parameters are written from its arrays as they lie in memory
        a = np.array(value, dtype=float, order="C")
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected an array of numbers") from None
    if shape is not None and a.shape != tuple(shape):
        raise ValueError(f"{name}: expected shape {tuple(shape)}, got {a.shape}")
    if ndim is not None and a.ndim != ndim:
        raise ValueError(f"{name}: expected a {ndim}-D array, got shape {a.shape}")
    # finiteness and the least entry in one compiled pass (~0.1 us for a primitive's entries)
    low = finite_min(a)
    if low != low:
        raise ValueError(f"{name}: must be finite (no NaN or inf)")
    if minimum is not None and low < minimum:
        raise ValueError(f"{name}: must be >= {minimum}")
    return a


def finite_scalar(value, name, minimum=None, exclusive=False):
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected a number") from None
    if x - x != 0.0:                  # NaN or inf (x - x is NaN for both), without a call
        raise ValueError(f"{name}: must be finite (no NaN or inf)")
    if minimum is not None and (x <= minimum if exclusive else x < minimum):
        raise ValueError(f"{name}: must be {'>' if exclusive else '>='} {minimum}, got {x}")
    return x


def positive_int(value, name):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name}: must be a positive integer, got {value!r}")
    return int(value)


def check_choice(value, allowed, name):
    """value, if it is one of `allowed` (a dict's keys or a sequence)."""
    try:
        known = value in allowed
    except TypeError:         # unhashable, so not one of a dict's keys
        known = False
    if not known:
        raise ValueError(f"{name}: must be one of {sorted(allowed)}, got {value!r}")
    return value


def finite_vector(value, name, n):
    """(x, x.x) for a finite float vector of n entries. An exact float64 (n,) array costs one dot
    product (~0.3 us): x.x is NaN or inf iff an entry is, so the slow checks run only to name
    the rule. ray_shoot calls this once per call; min_force only for a wrench its compiled call
    refused."""
    x = value
    if not (type(x) is np.ndarray and x.dtype == np.float64 and x.shape == (n,)):
        x = finite_array(value, name, ndim=1)
        if x.shape[0] != n:
            raise ValueError(f"{name}: must have {n} entries, got {x.shape[0]}")
    xx = float(x.dot(x))        # ndarray.dot: half the dispatch cost of `@` on tiny vectors
    if not math.isfinite(xx):
        finite_array(x, name)
        raise ValueError(f"{name}: too large: the squared norm overflows; rescale it")
    return x, xx


FLOAT64 = np.dtype(np.float64)


def is_vector(x):
    """Whether x is exactly what the compiled core takes for a vector: a C-contiguous float64
    ndarray of one dimension (its length is the callee's to check). ~0.1 us."""
    return type(x) is np.ndarray and x.dtype is FLOAT64 and x.strides == (8,)


def finite_vector3(value, name):
    """finite_array(value, name, shape=(3,)) in a third of its time (a grasp made per query
    checks two of these per contact): finite iff 0 x + 0 y + 0 z is 0 (0 inf is NaN)."""
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected an array of numbers") from None
    if a.shape == (3,):
        x, y, z = a.tolist()
        if 0.0 * x + 0.0 * y + 0.0 * z == 0.0:
            return a
    return finite_array(a, name, shape=(3,))
