"""Our minimum force beside the baselines' answers to the same problem: their sigma, status,
time and relative error against ours (what the service's `compare` option returns).

    compare(grasp, w_ext, ours, solvers=("clarabel", "osqp"), norm="L1", magnitude="normal")

"clarabel" is the exact SOCP (clarabel_socp), "osqp" the linearized pyramid solved by OSQP
(pyramid, 8 faces, method "osqp-pyramid"; normal magnitude only: for "full" its row has status "not_applicable").
"""
import math
import time

SOLVERS = ("clarabel", "osqp")


def compare(grasp, w_ext, ours, solvers=SOLVERS, norm="L1", magnitude="normal"):
    """One row per solver: {solver, method, status, sigma, sigma_lower, seconds, error}, error =
    sigma / ours.sigma - 1 (None when either is not finite; inf and NaN become None)."""
    from . import clarabel_socp, pyramid
    rows = []
    for name in solvers:
        if name not in SOLVERS:
            raise ValueError(f"compare: must be a list of {list(SOLVERS)}, got {name!r}")
        if name == "osqp" and magnitude != "normal":
            rows.append({"solver": name, "method": "osqp-pyramid", "status": "not_applicable",
                         "sigma": None, "sigma_lower": None, "seconds": 0.0, "error": None})
            continue
        start = time.perf_counter()
        if name == "clarabel":
            res = clarabel_socp.min_force(grasp, w_ext, norm=norm, magnitude=magnitude)
        else:
            res = pyramid.min_force(grasp, w_ext, norm=norm, magnitude=magnitude, solver="osqp")
        seconds = time.perf_counter() - start
        error = None
        if math.isfinite(res.sigma) and math.isfinite(ours.sigma) and ours.sigma > 0.0:
            error = res.sigma / ours.sigma - 1.0
        rows.append({"solver": name, "method": res.method, "status": res.status,
                     "sigma": _finite(res.sigma), "sigma_lower": _finite(res.sigma_lower),
                     "seconds": seconds, "error": error})
    return rows


def _finite(x):
    x = float(x)
    return x if math.isfinite(x) else None
