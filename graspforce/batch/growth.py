"""The growth distance of one pair of shapes at many poses: one compiled parallel loop."""
import numpy as np

from .._core import growth_rows
from .._core.growth import BAD_POSE_A, BAD_POSE_B
from ..growth.growth import _VERDICTS, GrowthDistance
from ._check import thread_count
from .result import BatchGrowth

_STATUS_OF_VERDICT = np.array([_VERDICTS[k] for k in sorted(_VERDICTS)] + ["bad_pose"])


def pose_rows(poses, n, name):
    """(R (N, 9), p (N, 3)) as C-contiguous float64 arrays from (N, 4, 4) homogeneous matrices,
    a pair (R (N, 3, 3), p (N, 3)), or one pose of either form for all N rows."""
    if isinstance(poses, (tuple, list)) and len(poses) == 2:
        R, p = (np.asarray(x, dtype=np.float64) for x in poses)
    else:
        M = np.asarray(poses, dtype=np.float64)
        if M.shape[-2:] != (4, 4):
            raise ValueError(f"{name}: expected (N, 4, 4) matrices or a pair (R (N, 3, 3), "
                             f"p (N, 3)), got shape {M.shape}")
        R, p = M[..., :3, :3], M[..., :3, 3]
    if R.shape[-2:] != (3, 3) or p.shape[-1:] != (3,) or R.shape[:-2] != p.shape[:-1] \
            or R.ndim > 3:
        raise ValueError(f"{name}: expected rotations (N, 3, 3) and translations (N, 3), got "
                         f"{R.shape} and {p.shape}")
    R = np.broadcast_to(R.reshape(-1, 9), (n, 9)) if R.ndim == 2 else R.reshape(-1, 9)
    p = np.broadcast_to(p.reshape(-1, 3), (n, 3)) if p.ndim == 1 else p.reshape(-1, 3)
    R, p = (np.require(x, np.float64, ["C_CONTIGUOUS", "ALIGNED"]) for x in (R, p))
    if R.shape[0] != n or p.shape[0] != n:
        raise ValueError(f"{name}: expected {n} poses, got {R.shape[0]}")
    return R, p


def _count(poses):
    """N of a pose argument, or None for one pose."""
    if isinstance(poses, (tuple, list)) and len(poses) == 2:
        R = np.asarray(poses[0])
        return R.shape[0] if R.ndim == 3 else None
    M = np.asarray(poses)
    return M.shape[0] if M.ndim == 3 else None


def growth_distance(A, B, poses_a, poses_b, method="zc-ie", eps=1e-9, max_iter=10000,
                    touching_tol=1e-9, threads=None, client=None, chunk_size=None):
    """gf.growth_distance(A, pose_a, B, pose_b) for N pose pairs of one pair of shapes, as one
    compiled loop over the rows on `threads` threads (None: all cores). poses_a, poses_b:
    (N, 4, 4) homogeneous matrices or (R (N, 3, 3), p (N, 3)); either may be one pose, used
    for every row. Row i equals the single call's sigma, bracket, status and iterations; a pose
    that is not a proper rotation or not finite is status "bad_pose" (sigma NaN) instead of a
    ValueError. client: a dask.distributed.Client or scheduler address (chunks of chunk_size)."""
    counts = {_count(poses_a), _count(poses_b)} - {None}
    if len(counts) > 1:
        raise ValueError(f"poses_a, poses_b: different numbers of poses {sorted(counts)}")
    n = counts.pop() if counts else 1
    R_a, p_a = pose_rows(poses_a, n, "poses_a")
    R_b, p_b = pose_rows(poses_b, n, "poses_b")
    if client is not None:
        from .distributed import growth_on_cluster
        return growth_on_cluster(client, A, B, R_a, p_a, R_b, p_b, method, eps, max_iter,
                                 touching_tol, chunk_size)
    threads = thread_count(threads)
    solver = GrowthDistance(A, B, method, eps, max_iter, touching_tol, warm_start=False)
    return growth_rows_local(solver, R_a, p_a, R_b, p_b, threads)


def growth_rows_local(solver, R_a, p_a, R_b, p_b, threads):
    """The compiled loop on checked pose rows with a GrowthDistance solver without warm start
    (its program is copied for every row, never written); coincident reference points give sigma 0 and
    "penetrating", as a single call does."""
    n = R_a.shape[0]
    code = np.empty(n, np.int64)
    verdict = np.empty(n, np.int64)
    sigma, lower, upper = np.empty(n), np.empty(n), np.empty(n)
    iterations = np.empty(n, np.int64)
    growth_rows(R_a, p_a, R_b, p_b, solver._ints, solver._floats, solver._size, code, verdict,
                sigma, lower, upper, iterations, threads)
    bad = (code == BAD_POSE_A) | (code == BAD_POSE_B)
    verdict[bad] = len(_STATUS_OF_VERDICT) - 1
    sigma[bad] = lower[bad] = upper[bad] = np.nan
    status = _STATUS_OF_VERDICT[verdict]
    return BatchGrowth(sigma, lower, upper, status, iterations.astype(np.int32))
