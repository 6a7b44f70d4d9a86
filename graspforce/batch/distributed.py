"""The batch calls on a Dask cluster: rows in chunks, one task per chunk, results in order.

A task answers its chunk with the local compiled loop on one thread; a worker runs as many
tasks at once as it has threads (the loop releases the GIL), so its cores are used without
oversubscribing them. Grasps and shapes travel by pickle: a Grasp drops its compiled caches
(Grasp.__getstate__) and a worker rebuilds them, and the start table, on its first chunk; both
are deterministic, so a worker's answers equal the local ones bit for bit. Data is scattered
with hash=False: content-hashed keys are shared by consecutive calls on the same grasp, and one
call's release of its key can cancel the next call's tasks ("lost dependencies").
"""
import math
import threading

import numpy as np

from ._check import chunk_count, wrench_rows
from .result import BatchForces, BatchGrowth

DEFAULT_CHUNK = 50_000     # rows a task: ~0.2-0.5 s of work, against ~1-5 ms of Dask per task

# one worker runs several tasks on one unpickled grasp at once; its caches are built under a lock
_PREPARE = threading.Lock()


class _Cluster:
    """A Client for the duration of one call: the caller's, or one opened on an address (and
    closed after)."""

    def __init__(self, client):
        self.client, self.owned = client, False

    def __enter__(self):
        if isinstance(self.client, str):
            from distributed import Client
            self.client, self.owned = Client(self.client), True
        elif not (hasattr(self.client, "map") and hasattr(self.client, "scatter")):
            raise TypeError(f"client: expected a dask.distributed.Client or a scheduler address, "
                            f"got {type(self.client).__name__}")
        return self.client

    def __exit__(self, *exc):
        if self.owned:
            self.client.close()


def chunk_bounds(n, chunk_size):
    """[(start, stop)] covering range(n) in order, chunks of chunk_size rows."""
    return [(a, min(n, a + chunk_size)) for a in range(0, n, chunk_size)] or [(0, 0)]


def _size(chunk_size):
    return DEFAULT_CHUNK if chunk_size is None else chunk_count(chunk_size)


def _min_force_chunk(grasp, rows, norm, magnitude, method, eps, max_iter, forces):
    from .forces import min_force, prepared_call
    with _PREPARE:
        prepared_call(grasp, norm, magnitude, method)
    return min_force(grasp, rows, norm, magnitude, method, eps, max_iter, forces, threads=1)


def min_force_on_cluster(client, grasp, wrenches, norm, magnitude, method, eps, max_iter, forces,
                         chunk_size):
    from .forces import prepared_call
    prepared_call(grasp, norm, magnitude, method)       # the arguments' errors, raised here
    rows = wrench_rows(wrenches)
    bounds = chunk_bounds(rows.shape[0], _size(chunk_size))
    with _Cluster(client) as c:
        g = c.scatter(grasp, broadcast=True, hash=False)
        parts = c.scatter([rows[a:b] for a, b in bounds], hash=False)
        futures = c.map(_min_force_chunk, [g] * len(parts), parts, norm=norm,
                        magnitude=magnitude, method=method, eps=eps, max_iter=max_iter,
                        forces=forces, pure=False)
        return BatchForces.concatenate(c.gather(futures))


def _grasps_chunk(grasps, wrench, norm, magnitude, method, eps, max_iter, forces):
    from .forces import min_force_grasps
    return min_force_grasps(grasps, wrench, norm, magnitude, method, eps, max_iter, forces)


def min_force_grasps_on_cluster(client, grasps, wrench, norm, magnitude, method, eps, max_iter,
                                forces, chunk_size):
    grasps = list(grasps)
    size = max(1, math.ceil(len(grasps) / 64)) if chunk_size is None else chunk_count(chunk_size)
    bounds = chunk_bounds(len(grasps), size)
    with _Cluster(client) as c:
        futures = c.map(_grasps_chunk, [grasps[a:b] for a, b in bounds], wrench=wrench,
                        norm=norm, magnitude=magnitude, method=method, eps=eps,
                        max_iter=max_iter, forces=forces, pure=False)
        parts = c.gather(futures)
    out = BatchForces.concatenate(
        [BatchForces(p.sigma, p.sigma_lower, p.status, p.iterations, None) for p in parts])
    if forces:
        out.forces = [f for p in parts for f in p.forces]
    return out


def _growth_chunk(A, B, R_a, p_a, R_b, p_b, method, eps, max_iter, touching_tol):
    from ..growth.growth import GrowthDistance
    from .growth import growth_rows_local
    R_a, p_a, R_b, p_b = (np.require(x, np.float64, ["C_CONTIGUOUS", "ALIGNED"])
                          for x in (R_a, p_a, R_b, p_b))
    with _PREPARE:          # the shapes are shared by the worker's tasks; their checks are cached
        solver = GrowthDistance(A, B, method, eps, max_iter, touching_tol, warm_start=False)
    return growth_rows_local(solver, R_a, p_a, R_b, p_b, 1)


def growth_on_cluster(client, A, B, R_a, p_a, R_b, p_b, method, eps, max_iter, touching_tol,
                      chunk_size):
    bounds = chunk_bounds(R_a.shape[0], _size(chunk_size))
    with _Cluster(client) as c:
        a, b = (c.scatter(X, broadcast=True, hash=False) for X in (A, B))
        futures = [c.submit(_growth_chunk, a, b, R_a[i:j], p_a[i:j], R_b[i:j], p_b[i:j], method,
                            eps, max_iter, touching_tol, pure=False) for i, j in bounds]
        return BatchGrowth.concatenate(c.gather(futures))

