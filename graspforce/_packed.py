"""A ray-shooting result crosses from compiled code to Python as one array.

Numba boxes every returned array separately, ~0.5 us each (measured: a tuple of seven arrays
3.9 us, one array 0.8 us), so the entry points called once per query return the scalars of the
result and a single float array holding [extra (caller's data), normal (n), weights (k),
vertices (k, n), witnesses (k, ws)]; Python takes views of it only when a field is read.
"""
import numpy as np
from numba import njit

HEAD = 7   # (status, t, t_upper, h_n, iterations, support_calls, singular_steps)


@njit(cache=True)
def pack(out, extra):
    """(status, t, t_upper, h_n, iterations, support_calls, singular_steps, packed) from the
    result tuple of the shooters (graspforce._shooters._result) and the caller's `extra`."""
    normal, V, lam, W = out[6], out[7], out[8], out[9]
    k, n = V.shape
    ws = W.shape[1]
    e = extra.shape[0]
    packed = np.empty(e + n + k * (1 + n + ws))
    for a in range(e):
        packed[a] = extra[a]
    pos = e
    for a in range(n):
        packed[pos + a] = normal[a]
    pos += n
    for j in range(k):
        packed[pos + j] = lam[j]
    pos += k
    for j in range(k):
        for a in range(n):
            packed[pos + n * j + a] = V[j, a]
    pos += n * k
    for j in range(k):
        for a in range(ws):
            packed[pos + ws * j + a] = W[j, a]
    return out[0], out[1], out[2], out[3], out[4], out[5], out[10], packed


def normal_of(packed, extra, n):
    """The normal, a view of `packed` after `extra` entries."""
    return packed[extra:extra + n]


def unpack(packed, extra, n, ws):
    """(normal, weights, vertices, witness rows) as views of `packed` after `extra` entries."""
    k = (packed.shape[0] - extra - n) // (1 + n + ws)
    pos = extra + n
    return (normal_of(packed, extra, n), packed[pos:pos + k],
            packed[pos + k:pos + k + n * k].reshape(k, n), packed[pos + k + n * k:].reshape(k, ws))
