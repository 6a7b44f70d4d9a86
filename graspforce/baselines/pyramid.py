"""Baseline (b): friction cones linearized into pyramids, solved as an LP through qpsolvers.

This is what most grasping code does: replace each cone by a polyhedral cone spanned by a few
generators and hand the linear program to a generic solver. The pyramid is INSCRIBED: its
generators lie on the exact cone, so its forces are feasible for the exact problem and its
minimum is >= the exact one (it converges as `faces` grows):
- point contact: f = sum_j lambda_j (1, mu cos a_j, mu sin a_j, 0), a_j = 2 pi j / faces;
- soft finger: the cross-section at f_1 = 1 is the ellipsoid of eq. (12) in (f_2, f_3, f_4);
  its generators are `faces` points on each of 2 (faces // 4) + 1 latitude rings and the two
  poles (the spin-only forces (1, 0, 0, +-mu_s)): a polytope inside the ellipsoid;
- frictionless: f = lambda (1, 0, 0, 0).
Every generator has f_1 = 1, so sum_j lambda_ij = f_i1 and the objectives of eq. (13) are linear:
    L1:   minimize sum lambda,            sum_i G_i f_i = -w_ext, lambda >= 0
    Linf: minimize s,  sum_j lambda_ij <= s,  same constraints.
The full magnitude of eq. (15) is not linear in lambda: use clarabel_socp for it.
The QP solvers see P = 0 (an LP). Solver settings are qpsolvers' defaults unless given, as users
call them; OSQP's default tolerances (1e-3) and iteration limit often end at "max_iter" here.
"""
import numpy as np
import scipy.sparse as sp

from ._record import Objective, check_problem


def generators(contact, faces):
    """(k, 4) generators of the inscribed pyramid of one contact's friction cone, all with f_1 = 1."""
    if contact.mu == 0.0:
        return np.array([[1.0, 0.0, 0.0, 0.0]])
    a = 2.0 * np.pi * np.arange(faces) / faces
    if contact.mu_spin == 0.0:
        return np.column_stack((np.ones(faces), contact.mu * np.cos(a), contact.mu * np.sin(a),
                                np.zeros(faces)))
    # soft finger: latitude rings of `faces` points on the unit sphere of
    # (f_2/mu, f_3/mu, f_4/mu_s), faces // 4 rings per hemisphere, plus the two poles
    rings = max(1, faces // 4)
    lat = 0.5 * np.pi * np.arange(-rings, rings + 1) / (rings + 1)
    u = np.vstack([np.column_stack((np.cos(p) * np.cos(a), np.cos(p) * np.sin(a),
                                    np.full(faces, np.sin(p)))) for p in lat]
                  + [[[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]])
    return np.column_stack((np.ones(len(u)), contact.mu * u[:, 0], contact.mu * u[:, 1],
                            contact.mu_spin * u[:, 2]))


def min_force(grasp, w_ext, norm="L1", magnitude="normal", solver="osqp", faces=8, **options):
    """Minimal normal forces on inscribed pyramids (`faces` >= 3) with qpsolvers' `solver`."""
    import qpsolvers

    contacts, w = check_problem(grasp, w_ext, norm, magnitude)
    if magnitude != "normal":
        raise ValueError("magnitude: the pyramid baseline minimizes normal forces (eq. 13) only; "
                         "use graspforce.baselines.clarabel_socp for 'full'")
    if isinstance(faces, bool) or not isinstance(faces, (int, np.integer)) or faces < 3:
        raise ValueError(f"faces: must be an integer >= 3, got {faces!r}")
    gens = [generators(c, faces) for c in contacts]
    counts = [len(g) for g in gens]
    n_lambda = sum(counts)
    n = n_lambda + (norm == "Linf")
    A = np.zeros((6, n))
    col = 0
    for c, g in zip(contacts, gens):
        A[:, col:col + len(g)] = c.matrix @ g.T
        col += len(g)
    q = np.zeros(n)
    G = h = None
    if norm == "L1":
        q[:n_lambda] = 1.0
    else:
        q[-1] = 1.0
        G = np.zeros((len(contacts), n))
        col = 0
        for i, k in enumerate(counts):
            G[i, col:col + k] = 1.0
            col += k
        G[:, -1] = -1.0
        G, h = sp.csc_matrix(G), np.zeros(len(contacts))
    lb = np.zeros(n)
    if norm == "Linf":
        lb[-1] = -np.inf
    problem = qpsolvers.Problem(sp.csc_matrix((n, n)), q, G, h, sp.csc_matrix(A), -w, lb, None)
    solution = qpsolvers.solve_problem(problem, solver=solver, **options)
    status, iterations = _status(solver, solution)
    forces = None
    if solution.x is not None and status != "infeasible":
        lam = np.asarray(solution.x)[:n_lambda]
        forces = np.zeros((len(contacts), 4))
        col = 0
        for i, g in enumerate(gens):
            forces[i] = lam[col:col + len(g)] @ g
            col += len(g)
    # the LP's optimum bounds the pyramid's problem, not the exact one: no certified lower bound
    return Objective(contacts, norm, magnitude).record(forces, status, np.nan,
                                                       f"{solver}-pyramid", iterations)


def _status(solver, solution):
    """The solver's own verdict as (status, iterations)."""
    extras = solution.extras or {}
    if solver == "osqp" and "info" in extras:
        info = extras["info"]
        text = str(info.status).lower()
        if "max" in text and "iter" in text:
            return "max_iter", info.iter
        if "infeasible" in text and "dual" not in text:
            return "infeasible", info.iter
        if text == "solved":
            return "optimal", info.iter
        return "inaccurate", info.iter
    if solver == "clarabel" and "status" in extras:
        text = str(extras["status"])
        if "PrimalInfeasible" in text:
            return "infeasible", 0
        if text == "Solved":
            return "optimal", 0
        return ("max_iter" if "Max" in text else "inaccurate"), 0
    if solution.found:
        return "optimal", 0
    return ("infeasible" if solution.x is None else "inaccurate"), 0
