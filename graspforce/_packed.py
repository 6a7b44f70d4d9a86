"""A ray-shooting result crosses from compiled code to Python as scalars and one array that the
caller allocated.

Numba boxes every array it returns, ~0.5 us each (measured: a tuple of seven arrays 3.9 us, one
array 0.8 us; the same array allocated by the caller with np.empty and filled in place, 0.2 us),
so the entry points called once per query write [extra (caller's data), normal (n), weights
(k), vertices (k, n), witnesses (k, ws)] into a float array of `capacity` entries after the
extra ones, and return the scalars; Python takes views of the array only when a field is read.
"""
from numba.extending import register_jitable

from ._jit import borrowing

HEAD = 8   # (status, t, t_upper, h_n, iterations, support_calls, singular_steps, k)


@register_jitable
def capacity(n, ws):
    """Entries the arrays of a shot in R^n with witnesses of ws entries need: the shooters'
    simplices have at most n + 2 rows."""
    return n + (n + 2) * (1 + n + ws)


@borrowing
def pack_arrays(normal, V, lam, W, k, packed, e):
    """normal, lam[:k], V[:k] and W[:k] written to packed[e:] (at least `capacity(n, ws)`
    entries), in the layout `unpack` reads."""
    n = normal.shape[0]
    ws = W.shape[1]
    for a in range(n):
        packed[e + a] = normal[a]
    pos = e + n
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


@borrowing
def pack(out, packed, e):
    """The head (status, t, t_upper, h_n, iterations, support_calls, singular_steps, k) of the
    shooters' result tuple `out` (graspforce._shooters._result), its arrays written to
    packed[e:] (`pack_arrays`)."""
    k = out[7].shape[0]
    pack_arrays(out[6], out[7], out[8], out[9], k, packed, e)
    return out[0], out[1], out[2], out[3], out[4], out[5], out[10], k


def normal_of(packed, extra, n):
    """The normal, a view of `packed` after `extra` entries."""
    return packed[extra:extra + n]


def unpack(packed, extra, n, ws, k):
    """(normal, weights, vertices, witness rows) of k vertices as views of `packed` after
    `extra` entries."""
    pos = extra + n
    return (normal_of(packed, extra, n), packed[pos:pos + k],
            packed[pos + k:pos + k + n * k].reshape(k, n),
            packed[pos + k + n * k:pos + k + (n + ws) * k].reshape(k, ws))
