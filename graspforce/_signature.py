"""Compiled entry points with one signature, compiled on first use."""
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
