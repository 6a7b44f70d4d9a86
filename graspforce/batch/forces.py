"""min_force over many wrenches (one compiled parallel loop) and over many grasps."""
import numpy as np

from .._core import batch as _codes
from .._core import min_force_rows
from ..geometry._start_table import NO_TABLE, SEEN_ONCE, start_table
from .._validate import finite_vector
from ..shooting.ray_shoot import check_tolerances
from ._check import check_grasp, thread_count, wrench_rows
from .result import BatchForces


def prepared_call(grasp, norm, magnitude, method, table=True, full=False):
    """What the compiled loop needs of (norm, magnitude, method), as Grasp.min_force passes it to
    shoot_and_read_forces: (method code, packed size, start table, ints, floats, force reader,
    span, t_scale). With `table`, the start table is built here if the grasp has not been shot
    twice yet, so every row starts from it, as Grasp.min_force's calls do from their second on;
    without, rows start as a new grasp's first call does. full: the set in R^6 that answers
    loads outside a rank-deficient grasp's span (Grasp._call)."""
    check_grasp(grasp)
    key = (norm, magnitude, method, True) if full else (norm, magnitude, method)
    call = grasp._calls.get(key) if _hashable(norm, magnitude, method) else None
    if call is None:
        call = grasp._call(norm, magnitude, method, full)
    _space, code, _shoot, args, A, size, _extra, t_scale, ray_dims = call
    start = NO_TABLE
    if table:
        start = start_table(A, ray_dims)
        if A._start_table is SEEN_ONCE:      # a set's first shot takes none: build it now
            start = start_table(A, ray_dims)
    ints, floats, reader, span = args
    return code, size, start, ints, floats, reader, span, float(t_scale)


def _rows(grasp, rows, prepared, norm, magnitude, method, eps, max_iter, forces, threads, table):
    """(sigma, sigma_lower, status, iterations, forces (N, m, 4) or an empty array) of the
    compiled loop over `rows` with `prepared_call`'s arguments; the rows whose load leaves a
    rank-deficient grasp's span are answered again on the full-dimensional set, as
    Grasp.min_force answers them."""
    n = rows.shape[0]
    out = (np.empty(n), np.empty(n), np.empty(n, np.int64), np.empty(n, np.int64),
           np.empty((n, len(grasp), 4)) if forces else np.empty(0))
    code, size, start, ints, floats, reader, span, t_scale = prepared
    min_force_rows(rows, code, eps, max_iter, size, start, ints, floats, reader, span, t_scale,
                   *out[:4], out[4].reshape(-1), threads)
    off = np.flatnonzero(out[2] == _codes.FULL_SET)
    if len(off):
        full = prepared_call(grasp, norm, magnitude, method, table, full=True)
        again = _rows(grasp, rows[off], full, norm, magnitude, method, eps, max_iter, forces,
                      threads, table)
        for whole, part in zip(out, again):
            if len(whole):
                whole[off] = part
    return out


def _hashable(*values):
    try:
        hash(values)
    except TypeError:
        return False
    return True


def min_force(grasp, wrenches, norm="L1", magnitude="normal", method="zc-ie", eps=1e-9,
              max_iter=10000, forces=False, threads=None, client=None, chunk_size=None):
    """Grasp.min_force for every row of wrenches (N, 6), as one compiled loop over the rows on
    `threads` threads (None: all cores) with the GIL released. Returns a BatchForces whose row
    i equals grasp.min_force(wrenches[i], ...) once the grasp has been shot twice (the start
    table built; the batch builds it); a NaN, inf or overflowing row is marked "bad_wrench".
    forces=True also returns the (N, m, 4) local forces (zeros where sigma is inf).
    client: a dask.distributed.Client or a scheduler address: the rows go in chunks of
    chunk_size to the cluster's workers (graspforce.batch.distributed); same answers."""
    if client is not None:
        from .distributed import min_force_on_cluster
        return min_force_on_cluster(client, grasp, wrenches, norm, magnitude, method, eps,
                                    max_iter, forces, chunk_size)
    prepared = prepared_call(grasp, norm, magnitude, method)
    eps, max_iter = check_tolerances(eps, max_iter)
    rows = wrench_rows(wrenches)
    sigma, lower, status, iterations, out_forces = _rows(
        grasp, rows, prepared, norm, magnitude, method, eps, max_iter, forces,
        thread_count(threads), True)
    return BatchForces(sigma, lower, status.astype(np.int8), iterations.astype(np.int32),
                       out_forces if forces else None)


def min_force_grasps(grasps, wrench, norm="L1", magnitude="normal", method="zc-ie", eps=1e-9,
                     max_iter=10000, forces=False, client=None, chunk_size=None):
    """min_force(wrench) for each grasp of a sequence (grasp synthesis: many candidates, one
    load). Row i equals gf.Grasp(contacts_i).min_force(wrench, ...), a new grasp's first call:
    no start table, which costs ~1 ms to build and pays off over many wrenches, not one; so the
    answer does not depend on the grasps' earlier calls or on where it is computed.
    A Python loop over compiled calls (one row each): a grasp's first call builds and compiles
    its wrench set (~100 us of Python), against ~10 us for the shot, so a compiled loop over
    grasps would save little. A non-finite wrench is one wrench for all: it raises, as
    Grasp.min_force does. forces (when asked) is a list of (m_i, 4) arrays."""
    if client is not None:
        from .distributed import min_force_grasps_on_cluster
        return min_force_grasps_on_cluster(client, grasps, wrench, norm, magnitude, method, eps,
                                           max_iter, forces, chunk_size)
    grasps = list(grasps)
    for i, g in enumerate(grasps):
        check_grasp(g, f"grasps[{i}]")
    row = wrench_rows(finite_vector(wrench, "wrench", 6)[0])
    eps, max_iter = check_tolerances(eps, max_iter)
    n = len(grasps)
    sigma, lower = np.empty(n), np.empty(n)
    status = np.empty(n, np.int64)
    iterations = np.empty(n, np.int64)
    found = [] if forces else None
    for i, g in enumerate(grasps):
        prepared = prepared_call(g, norm, magnitude, method, table=False)
        sigma[i:i + 1], lower[i:i + 1], status[i:i + 1], iterations[i:i + 1], f = _rows(
            g, row, prepared, norm, magnitude, method, eps, max_iter, forces, 1, False)
        if forces:
            found.append(f[0])
    return BatchForces(sigma, lower, status.astype(np.int8), iterations.astype(np.int32), found)
