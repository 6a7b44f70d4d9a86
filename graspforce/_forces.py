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

# rows of a wrench space's leaf table (graspforce.wrench_space.Target._table)
CONTACT, SLOT, SIZE, MAP = 0, 1, 2, 3
ORIGIN_FLOOR = 1e-12   # |z| <= this times W's size: z is the origin to rounding


@register_jitable
def extra_size(m):
    """Entries [sigma, forces (m, 4), wrenches (m, 6), resultant (6,)] ahead of the ray-shooting
    arrays in the packed result of `shoot_and_read_forces`."""
    return 7 + 10 * m


# A Target's force reader (graspforce.wrench_space): how forces are read off witnesses, as one
# float array read by offsets, since each array a min_force call hands to the compiled code costs
# ~50 ns to cross from Python (a zero-wrench call 641 -> 398 ns with the six gathered here) and
# each view of one costs reference counting. Layout: [witness size, linf, full, m, leaves L,
# table (4, L) by rows CONTACT, SLOT, SIZE, MAP, G (m, 6, 4), spin_weight (m,), maps].
READER_HEAD = 5


def force_reader(witness_size, linf, full, G, table, maps, spin_weight):
    """The reader array of a shot set (layout above): its witness size, the objective (linf,
    full), the contacts' G_i (m, 6, 4), the leaf table and maps of `contact_forces` and the
    weights of f_4^2 (full magnitude)."""
    return np.concatenate(([witness_size, linf, full, G.shape[0], table.shape[1]],
                           table.ravel(), G.ravel(), spin_weight, maps)).astype(float)


def force_views(packed, m):
    """(forces (m, 4), wrenches (m, 6), resultant (6,)): views of those entries of a packed
    answer, for the Python reader."""
    return (packed[1:1 + 4 * m].reshape(m, 4), packed[1 + 4 * m:1 + 10 * m].reshape(m, 6),
            packed[1 + 10 * m:7 + 10 * m])


@borrowing
def contact_forces(W, weights, scale, reader, packed):
    """sigma, with forces (m, 4), wrenches (m, 6) and resultant (6,) written to their entries of
    `packed` (`force_views`, zeroed by the caller), for z = sum_k weights_k v_k = t r,
    scale = 1/t, and the force reader of the shot set (G_i of eq. (11) among its parts).

    Every vertex v_k of Z_W(r) holds one wrench G_i u_ki (W_L1, or the lift of W_Linf, whose
    vertices' weights sum to 1/m per contact) or a sum of them (W_Linf itself), u_ki a unit
    contact force recovered from the vertex's witness row as base + map @ local (the reader's
    table: per leaf its contact, witness slot, local size and offset in maps). Then
    r = sum_i G_i f_i with f_i = sum_k (weights_k / t) u_ki: the forces resist w_ext = -r exactly,
    up to the rounding of the simplex. sigma is their objective (eq. 13 or 15), <= 1/t (1/(m t)
    on the lift) by the triangle inequality (equal when each contact appears in one vertex). For
    the full magnitude the reader's spin weights hold (mu_i / mu_si)^2 per contact (0 for point
    contacts), the weight of f_4^2 in ||f_i||.
    """
    linf = reader[1] != 0.0
    full = reader[2] != 0.0
    m = int(reader[3])
    leaves = int(reader[4])
    g0 = READER_HEAD + 4 * leaves        # G_i
    s0 = g0 + 24 * m                     # spin weights
    m0 = s0 + m                          # maps
    f0 = 1                               # forces, wrenches, resultant in packed
    w0 = f0 + 4 * m
    r0 = w0 + 6 * m
    for k in range(W.shape[0]):
        c = weights[k] * scale
        for j in range(leaves):
            i = int(reader[READER_HEAD + CONTACT * leaves + j])
            s = int(reader[READER_HEAD + SLOT * leaves + j])
            if i < 0 or W[k, s] < 0.5:
                continue
            p = m0 + int(reader[READER_HEAD + MAP * leaves + j])
            L = int(reader[READER_HEAD + SIZE * leaves + j])
            for a in range(4):
                f = reader[p + a]
                for b in range(L):
                    f += reader[p + 4 + a * L + b] * W[k, s + 1 + b]
                packed[f0 + 4 * i + a] += c * f
    sigma = 0.0
    for i in range(m):
        f = f0 + 4 * i
        if full:
            value = np.sqrt(packed[f] ** 2 + packed[f + 1] ** 2 + packed[f + 2] ** 2
                            + reader[s0 + i] * packed[f + 3] ** 2)
        else:
            value = packed[f]
        if linf:
            sigma = max(sigma, value)
        else:
            sigma += value
    for i in range(m):
        for a in range(6):
            s = 0.0
            for b in range(4):
                s += reader[g0 + 24 * i + 4 * a + b] * packed[f0 + 4 * i + b]
            packed[w0 + 6 * i + a] = s
            packed[r0 + a] += s
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
    n = ints[blocks(ints[0])[1]]          # the set's dimension: its root node's
    r = np.zeros(n)
    for a in range(6):
        r[n - 6 + a] = -w_ext[a]
    out = shoot_with_table(ints, floats, r, int(reader[0]), method, eps, max_iter, start)
    t = out[1]
    m = int(reader[3])
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
        packed[0] = contact_forces(out[9], out[8], 1.0 / t, reader, packed)
    return pack(out, packed, e)
