"""min_force over many wrenches (one compiled parallel loop) and over many grasps."""
import numpy as np

from .._core import min_force_rows
from ..geometry._start_table import NO_TABLE, SEEN_ONCE, start_table
from .._validate import finite_vector
from ..shooting.ray_shoot import check_tolerances
from ._check import check_grasp, thread_count, wrench_rows
from .result import BatchForces


def prepared_call(grasp, norm, magnitude, method, table=True):
    """What the compiled loop needs of (norm, magnitude, method), as Grasp.min_force passes it to
    shoot_and_read_forces: (method code, packed size, start table, ints, floats, force reader,
    t_scale). With `table`, the start table is built here if the grasp has not been shot twice
    yet, so every row starts from it, as Grasp.min_force's calls do from their second on;
    without, rows start as a new grasp's first call does."""
    check_grasp(grasp)
    call = grasp._calls.get((norm, magnitude, method)) if _hashable(norm, magnitude, method) \
        else None
    if call is None:
        call = grasp._call(norm, magnitude, method)
    _space, code, _shoot, args, A, size, _extra, t_scale = call
    start = NO_TABLE
    if table:
        start = start_table(A, 6)
        if A._start_table is SEEN_ONCE:      # a set's first shot takes none: build it now
            start = start_table(A, 6)
    ints, floats, reader = args
    return code, size, start, ints, floats, reader, float(t_scale)


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
    code, size, start, ints, floats, reader, t_scale = prepared_call(grasp, norm, magnitude,
                                                                      method)
    eps, max_iter = check_tolerances(eps, max_iter)
    rows = wrench_rows(wrenches)
    threads = thread_count(threads)
    n = rows.shape[0]
    m = len(grasp)
    sigma = np.empty(n)
    lower = np.empty(n)
    status = np.empty(n, np.int64)
    iterations = np.empty(n, np.int64)
    out_forces = np.empty((n, m, 4)) if forces else np.empty(0)
    min_force_rows(rows, code, eps, max_iter, size, start, ints, floats, reader, t_scale, sigma,
                   lower, status, iterations, out_forces.reshape(-1), threads)
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
        code, size, start, ints, floats, reader, t_scale = prepared_call(g, norm, magnitude,
                                                                          method, table=False)
        f = np.empty((len(g), 4)) if forces else np.empty(0)
        min_force_rows(row, code, eps, max_iter, size, start, ints, floats, reader, t_scale,
                       sigma[i:i + 1], lower[i:i + 1], status[i:i + 1], iterations[i:i + 1],
                       f.reshape(-1), 1)
        if forces:
            found.append(f)
    return BatchForces(sigma, lower, status.astype(np.int8), iterations.astype(np.int32), found)
