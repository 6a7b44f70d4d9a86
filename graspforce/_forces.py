"""Contact forces read off the final simplex Z_W(r) (compiled: it runs on every min_force call)."""
import numpy as np
from numba import njit, types
from numba.extending import register_jitable

from ._jit import borrowing
from ._kernel import blocks
from ._linalg import dot
from ._packed import pack
from ._shooters import MISS
from ._signature import INTS, VECTOR
from ._start_table import shoot_with_table

# rows of a wrench space's leaf table (graspforce.wrench_space.WrenchSpace.table)
CONTACT, SLOT, SIZE, MAP = 0, 1, 2, 3
ORIGIN_FLOOR = 1e-12   # |z| <= this times W's size: z is the origin to rounding


@register_jitable
def extra_size(m):
    """Entries [sigma, forces (m, 4), wrenches (m, 6), resultant (6,)] ahead of the ray-shooting
    arrays in the packed result of `shoot_and_read_forces`."""
    return 7 + 10 * m


# A Target's force reader (graspforce.wrench_space): how forces are read off witnesses, as one
# float array, since each array a min_force call hands to the compiled code costs ~50 ns to cross
# from Python (the six this gathers cost ~0.2 us more). Layout: [witness size, linf, full, m,
# leaves L, table (4, L), G (m, 6, 4), spin_weight (m,), maps].
READER_HEAD = 5


def force_reader(witness_size, linf, full, G, table, maps, spin_weight):
    """The reader array of a shot set (layout above): its witness size, the objective (linf,
    full), the contacts' G_i (m, 6, 4), the leaf table and maps of `contact_forces` and the
    weights of f_4^2 (full magnitude)."""
    return np.concatenate(([witness_size, linf, full, G.shape[0], table.shape[1]],
                           table.ravel(), G.ravel(), spin_weight, maps)).astype(float)


@register_jitable
def reader_parts(reader):
    """(witness size, linf, full, table (4, L), G (m, 6, 4), spin_weight (m,), maps): views of a
    force reader."""
    m = int(reader[3])
    leaves = int(reader[4])
    g0 = READER_HEAD + 4 * leaves
    s0 = g0 + 24 * m
    return (int(reader[0]), reader[1] != 0.0, reader[2] != 0.0,
            reader[READER_HEAD:g0].reshape(4, leaves), reader[g0:s0].reshape(m, 6, 4),
            reader[s0:s0 + m], reader[s0 + m:])


@register_jitable
def force_views(packed, m):
    """(forces (m, 4), wrenches (m, 6), resultant (6,)): views of those entries, for the compiled
    writer and the Python reader alike."""
    return (packed[1:1 + 4 * m].reshape(m, 4), packed[1 + 4 * m:1 + 10 * m].reshape(m, 6),
            packed[1 + 10 * m:7 + 10 * m])


@borrowing
def contact_forces(W, weights, scale, G, table, maps, linf, full, spin_weight, forces, wrenches,
                   resultant):
    """sigma, with forces (m, 4), wrenches (m, 6) and resultant (6,) (zeroed by the caller)
    filled in, for z = sum_k weights_k v_k = t r, scale = 1/t, G (m, 6, 4) the contacts' G_i of
    eq. (11).

    Every vertex v_k of Z_W(r) holds one wrench G_i u_ki (W_L1, or the lift of W_Linf, whose
    vertices' weights sum to 1/m per contact) or a sum of them (W_Linf itself), u_ki a unit
    contact force recovered from the vertex's witness row as base + map @ local (table: per
    leaf its contact, witness slot, local size and offset in maps, as floats: the force reader).
    Then
    r = sum_i G_i f_i with f_i = sum_k (weights_k / t) u_ki: the forces resist w_ext = -r exactly,
    up to the rounding of the simplex. sigma is their objective (eq. 13 or 15), <= 1/t (1/(m t)
    on the lift) by the triangle inequality (equal when each contact appears in one vertex). For
    the full magnitude
    spin_weight holds (mu_i / mu_si)^2 per contact (0 for point contacts), the weight of f_4^2 in
    ||f_i||.
    """
    m = G.shape[0]
    for k in range(W.shape[0]):
        c = weights[k] * scale
        for j in range(table.shape[1]):
            i = int(table[CONTACT, j])
            s = int(table[SLOT, j])
            if i < 0 or W[k, s] < 0.5:
                continue
            p = int(table[MAP, j])
            L = int(table[SIZE, j])
            for a in range(4):
                f = maps[p + a]
                for b in range(L):
                    f += maps[p + 4 + a * L + b] * W[k, s + 1 + b]
                forces[i, a] += c * f
    sigma = 0.0
    for i in range(m):
        if full:
            value = np.sqrt(forces[i, 0] ** 2 + forces[i, 1] ** 2 + forces[i, 2] ** 2
                            + spin_weight[i] * forces[i, 3] ** 2)
        else:
            value = forces[i, 0]
        if linf:
            sigma = max(sigma, value)
        else:
            sigma += value
    for i in range(m):
        for a in range(6):
            s = 0.0
            for b in range(4):
                s += G[i, a, b] * forces[i, b]
            wrenches[i, a] = s
            resultant[a] += s
    return sigma


# the one signature of `shoot_and_read_forces` (graspforce._signature): the per-call arguments,
# then a wrench space Target's `compiled_args` (the set's program and the force reader)
SIGNATURE = (VECTOR, types.int64, types.float64, types.int64, VECTOR, VECTOR, INTS, VECTOR,
             VECTOR)

# statuses of shoot_and_read_forces that say no shot was made (the shooters' are >= 0)
BAD_WRENCH = -1       # not 6 entries, or not finite
ZERO_WRENCH = -2      # w_ext = 0: no force needed, sigma = 0


@njit(cache=True)
def shoot_and_read_forces(w_ext, method, eps, max_iter, packed, start, ints, floats, reader):
    """One compiled call per min_force: z = t r on W by `method` (r = -w_ext), then the forces
    read off Z_W(r). Compiled for one signature and called through its entry point
    (graspforce._signature.entry_point): the caller passes only a C-contiguous float64 wrench and
    converts any other first. The per-call arguments come first (start: the wrench set's start
    table, graspforce._start_table, or an empty array), so that the caller appends a wrench
    space's constant ones as they are: the shot set's program and its force reader.

    Returns the head of the shot (graspforce._packed), whose arrays go to `packed`
    (extra_size(m) + capacity(6, ws) entries) after the extra entries [sigma, forces (m, 4),
    wrenches (m, 6), resultant (6,)] (`force_views`); zero forces and sigma = inf when the ray
    misses W or leaves it at the origin (to rounding). Or, with no shot, a head whose status is
    ZERO_WRENCH or BAD_WRENCH.
    """
    ww = dot(w_ext, w_ext)
    # x.x is NaN or inf iff an entry is (or the squares overflow)
    if w_ext.shape[0] != 6 or not np.isfinite(ww):
        return BAD_WRENCH, 0.0, 0.0, 0.0, 0, 0, 0, 0
    if ww == 0.0:
        return ZERO_WRENCH, 0.0, 0.0, 0.0, 0, 0, 0, 0
    # r = -w_ext, after the lift's m - 1 zeros for Linf (graspforce.wrench_space)
    ws, linf, full, table, G, spin_weight, maps = reader_parts(reader)
    n = ints[blocks(ints[0])[1]]          # the set's dimension: its root node's
    r = np.zeros(n)
    for a in range(6):
        r[n - 6 + a] = -w_ext[a]
    out = shoot_with_table(ints, floats, r, ws, method, eps, max_iter, start)
    t = out[1]
    m = G.shape[0]
    V = out[7]
    size = 0.0
    for k in range(V.shape[0]):
        for a in range(V.shape[1]):
            size = max(size, abs(V[k, a]))
    e = extra_size(m)
    for a in range(e):
        packed[a] = 0.0
    # a point of W at t r with |t r| at the rounding of W's size is the origin: an Linf set
    # contains 0, and a ray that leaves W there has no finite forces (the witnesses' forces,
    # scaled by 1/t, would be rounding blown up)
    if out[0] == MISS or not t * np.sqrt(ww) > ORIGIN_FLOOR * size:
        packed[0] = np.inf
    else:
        forces, wrenches, resultant = force_views(packed, m)
        packed[0] = contact_forces(out[9], out[8], 1.0 / t, G, table, maps, linf, full,
                                   spin_weight, forces, wrenches, resultant)
    return pack(out, packed, e)
