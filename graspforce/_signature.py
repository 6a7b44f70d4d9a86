"""Compiled entry points with one signature, compiled on first use."""
import numpy as np
from numba import types

# the types the signatures spell: a C-contiguous float64 vector, and an int64 one (programs)
VECTOR = types.float64[::1]
INTS = types.int64[::1]


def one_signature(dispatcher, signature):
    """`dispatcher` compiled (or loaded from Numba's cache) for `signature` alone, with
    compilation at call time disabled, so that a call with other argument types raises a
    TypeError (the caller converts its arguments and calls again) instead of compiling a new
    version for minutes. Done on first use rather than with `njit(signature)`, which would
    compile, or load, every callee when graspforce is imported."""
    if not dispatcher.signatures:
        dispatcher.compile(signature)
        dispatcher.disable_compile()
    return dispatcher


def entry_point(dispatcher, signature):
    """The compiled function of `one_signature(dispatcher, signature)` itself, called without
    Numba's dispatch, which types every argument anew on each call (~0.45 us of a ray_shoot
    call, ~0.7 us of a min_force call, timed interleaved; BENCHMARKS.md). It unboxes its
    arguments as `signature` says without checking them: an array of another dtype, rank or
    layout would be misread, not refused, so callers pass it only arguments of exactly those
    types (`is_vector`)."""
    one_signature(dispatcher, signature)
    return dispatcher.overloads[dispatcher.signatures[0]].entry_point


FLOAT64 = np.dtype(np.float64)


def is_vector(x):
    """Whether x is exactly a VECTOR: a C-contiguous float64 ndarray of one dimension (its
    length is the callee's to check). ~0.1 us."""
    return type(x) is np.ndarray and x.dtype is FLOAT64 and x.strides == (8,)
