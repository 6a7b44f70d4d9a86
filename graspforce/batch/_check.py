"""Checks of a batch's arguments that name the field and the rule."""
import numpy as np

from ..grasping.grasp import Grasp


def check_grasp(grasp, name="grasp"):
    if not isinstance(grasp, Grasp):
        raise TypeError(f"{name}: expected gf.Grasp, got {type(grasp).__name__}")
    return grasp


def wrench_rows(wrenches, name="wrenches"):
    """wrenches as a C-contiguous float64 (N, 6) array; NaN and inf are kept (such rows are
    marked "bad_wrench", not refused)."""
    try:
        a = np.asarray(wrenches, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected an (N, 6) array of numbers") from None
    if a.ndim == 1 and a.shape[0] == 6:
        a = a.reshape(1, 6)
    # the compiled loop reads aligned C-ordered native float64 only; arrays received over the
    # network can be unaligned views of a message buffer
    a = np.require(a, np.float64, ["C_CONTIGUOUS", "ALIGNED"])
    if a.ndim != 2 or a.shape[1] != 6:
        raise ValueError(f"{name}: expected shape (N, 6), got {a.shape}")
    return a


def thread_count(threads):
    """0 (all cores) for None, else a positive int."""
    if threads is None:
        return 0
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 1:
        raise ValueError(f"threads: must be a positive integer or None (all cores), got "
                         f"{threads!r}")
    return int(threads)


def chunk_count(chunk_size, name="chunk_size"):
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, (int, np.integer)) \
            or chunk_size < 1:
        raise ValueError(f"{name}: must be a positive integer, got {chunk_size!r}")
    return int(chunk_size)
