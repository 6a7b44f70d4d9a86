"""A ray-shooting result crosses from the compiled core to Python as scalars and one array that the
caller allocated: the entry points called once per query write [extra (caller's data), normal (n), weights
(k), vertices (k, n), witnesses (k, ws)] into a float array of `capacity` entries after the
extra ones, and return the scalars; Python takes views of the array only when a field is read.
"""


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
