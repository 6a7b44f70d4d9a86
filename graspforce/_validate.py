"""Input checks that name the field and the rule."""
import numpy as np


def finite_array(value, name, ndim=None, shape=None, minimum=None):
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected an array of numbers") from None
    if shape is not None and a.shape != tuple(shape):
        raise ValueError(f"{name}: expected shape {tuple(shape)}, got {a.shape}")
    if ndim is not None and a.ndim != ndim:
        raise ValueError(f"{name}: expected a {ndim}-D array, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name}: must be finite (no NaN or inf)")
    if minimum is not None and np.any(a < minimum):
        raise ValueError(f"{name}: must be >= {minimum}")
    return a


def finite_scalar(value, name, minimum=None, exclusive=False):
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected a number") from None
    if not np.isfinite(x):
        raise ValueError(f"{name}: must be finite (no NaN or inf)")
    if minimum is not None and (x <= minimum if exclusive else x < minimum):
        raise ValueError(f"{name}: must be {'>' if exclusive else '>='} {minimum}, got {x}")
    return x


def positive_int(value, name):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name}: must be a positive integer, got {value!r}")
    return int(value)
