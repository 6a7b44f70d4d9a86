"""Baseline (b): friction cones linearized into pyramids, solved as a linear program through
qpsolvers, as most grasping code does and as users usually call it.

    min_force(grasp, w_ext, norm="L1", magnitude="normal", solver="osqp", faces=8, **options)

The pyramid is INSCRIBED: every generator lies on the boundary of the exact cone of eq. (12), so
the pyramid's forces are feasible for the exact problem and its minimum is >= the exact one,
converging to it as `faces` grows. Every generator has f_1 = 1:
- point contact: the k = `faces` generators (1, mu cos a_j, mu sin a_j, 0), a_j = 2 pi j / k:
  a pyramid with k faces;
- soft finger: the cross-section f_1 = 1 of eq. (12) is an ellipsoid in (f_2, f_3, f_4). On its
  unit sphere u = (f_2/mu, f_3/mu, f_4/mu_s) take k points at azimuths a_j on each of
  2 (k // 4) + 1 latitude rings, at latitudes pi/2 * l / (k // 4 + 1), l = -k//4 .. k//4, plus
  the two poles (the spin-only forces (1, 0, 0, +-mu_s)): k (2 (k // 4) + 1) + 2 generators
  (42 for k = 8), whose convex hull is a polytope inside the ellipsoid;
- frictionless: the one generator (1, 0, 0, 0).
With f_i = sum_j lambda_ij g_ij, lambda >= 0, the normal force is f_i1 = sum_j lambda_ij, so the
normal-magnitude objectives of eq. (13) are linear programs:
    L1:   minimize sum lambda     s.t.  sum_i G_i f_i = -w_ext,  lambda >= 0
    Linf: minimize s              s.t.  the same,  sum_j lambda_ij <= s  (s >= 0 is implied;
                                        it is bounded below by 0 like lambda, for OSQP's box)
The full magnitude of eq. (15) is not linear in lambda: magnitude="full" raises ValueError (use
clarabel_socp). The solvers get P = 0 and qpsolvers' defaults unless `options` say otherwise.

Record: forces = sum_j lambda_ij g_ij as returned (not clipped: an OSQP iterate may have slightly
negative lambda), sigma = their objective, sigma_lower = NaN: the LP's dual bound bounds the
pyramid's minimum, which is above the exact one, so it certifies nothing about eq. (13).
Status: OSQP's info.status_val: solved -> "optimal", solved inaccurate -> "inaccurate", primal
infeasible (inaccurate) -> "infeasible", maximum iterations or time limit -> "max_iter" (frequent
at OSQP's defaults on these LPs), else "inaccurate"; iterations = info.iter. Clarabel: as in
clarabel_socp; iterations = 0 because qpsolvers does not pass Clarabel's count on.
"""
import numpy as np
import scipy.sparse as sp

from . import _status
from ._record import check_problem, check_wrench

SOLVERS = ("osqp", "clarabel")


def generators(contact, faces):
    """(k, 4) generators of the inscribed pyramid of one contact's friction cone, each with
    f_1 = 1 and on the boundary of the exact cone (module docstring)."""
    if contact.mu == 0.0:
        return np.array([[1.0, 0.0, 0.0, 0.0]])
    a = 2.0 * np.pi * np.arange(faces) / faces
    if contact.mu_spin == 0.0:
        return np.column_stack((np.ones(faces), contact.mu * np.cos(a), contact.mu * np.sin(a),
                                np.zeros(faces)))
    rings = faces // 4
    latitudes = 0.5 * np.pi * np.arange(-rings, rings + 1) / (rings + 1)
    u = np.vstack([np.column_stack((np.cos(p) * np.cos(a), np.cos(p) * np.sin(a),
                                    np.full(faces, np.sin(p)))) for p in latitudes]
                  + [[[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]])
    return np.column_stack((np.ones(len(u)), contact.mu * u[:, 0], contact.mu * u[:, 1],
                            contact.mu_spin * u[:, 2]))


def min_force(grasp, w_ext, norm="L1", magnitude="normal", solver="osqp", faces=8, **options):
    """Minimal normal forces on inscribed pyramids with `faces` >= 3, by qpsolvers' `solver`."""
    import qpsolvers

    objective = check_problem(grasp, norm, magnitude)
    contacts = objective.contacts
    w = check_wrench(w_ext)
    if magnitude != "normal":
        raise ValueError("magnitude: the pyramid baseline minimizes normal forces (eq. 13) only, "
                         "a linear objective in the generators' weights; use "
                         "graspforce.grasping.baselines.clarabel_socp for 'full'")
    if solver not in SOLVERS:
        raise ValueError(f"solver: must be one of {list(SOLVERS)} (whose statuses this module "
                         f"maps), got {solver!r}")
    if isinstance(faces, bool) or not isinstance(faces, (int, np.integer)) or faces < 3:
        raise ValueError(f"faces: must be an integer >= 3, got {faces!r}")

    gens = [generators(c, faces) for c in contacts]
    ends = np.cumsum([len(g) for g in gens])
    n_lambda = int(ends[-1])
    n = n_lambda + (norm == "Linf")
    A = np.zeros((6, n))
    A[:, :n_lambda] = np.hstack([Gi @ g.T for Gi, g in zip(objective.G, gens)])
    q = np.zeros(n)
    G = h = None
    if norm == "L1":
        q[:] = 1.0
    else:
        q[-1] = 1.0
        rows = np.zeros((len(contacts), n))       # sum_j lambda_ij - s <= 0
        for i, (start, end) in enumerate(zip(np.r_[0, ends[:-1]], ends)):
            rows[i, start:end] = 1.0
        rows[:, -1] = -1.0
        G, h = sp.csc_matrix(rows), np.zeros(len(contacts))
    problem = qpsolvers.Problem(sp.csc_matrix((n, n)), q, G, h, sp.csc_matrix(A), -w,
                                np.zeros(n), None)
    if solver == "osqp":
        # OSQP 1.x will raise on anything but "solved" by default in a future release; the
        # statuses are what this baseline reports, so ask for them (an explicit option wins)
        options = {"raise_error": False, **options}
    solution = qpsolvers.solve_problem(problem, solver=solver, **options)

    if solver == "osqp":
        info = solution.extras["info"]
        status, iterations = _status.osqp(info.status_val), info.iter
    else:
        status, iterations = _status.clarabel(solution.extras["status"]), 0
    forces = None
    x = solution.x
    if status != "infeasible" and x is not None and np.isfinite(x).all():
        forces = np.array([x[end - len(g):end] @ g for g, end in zip(gens, ends)])
    return objective.record(forces, status, np.nan, f"{solver}-pyramid", iterations)
