"""Baseline (a): the exact problem of section 5.1 as a second-order cone program for Clarabel.

    min_force(grasp, w_ext, norm="L1", magnitude="normal", tight=False, **options) -> MinForce
    Prepared(grasp, norm="L1", magnitude="normal", tight=False, **options).solve(w_ext)

`min_force` builds the problem and a solver on every call, with Clarabel's default settings
(verbose off): how it is usually called. `Prepared` builds both once per grasp and objective;
`solve` only replaces the wrench with `solver.update(b=...)`, Clarabel at its fastest (presolve is
off there: Clarabel refuses data updates with it on; it would only drop rows with infinite bounds,
of which this problem has none). tight=True tightens the gap and feasibility tolerances from 1e-8
to 1e-10 for reference values; `options` are any other Clarabel settings by name.

Variables: each contact's free force components x_i (soft finger f_1..f_4, point contact f_1..f_3,
frictionless f_1), then the epigraph variables of the objective. Constraints, in Clarabel's form
b - A x in a cone:
    sum_i G_i f_i = -w_ext                                   zero cone (eq. 11); only b varies
    (f_1, f_2/mu, f_3/mu, f_4/mu_s) in SOC                   friction cone F_i (eq. 12); point
                                                             contacts drop f_4, frictionless
                                                             ones keep f_1 >= 0
    L1 normal:   minimize sum_i f_i1                         (eq. 13)
    Linf normal: minimize s,  s - f_i1 >= 0
    L1 full:     minimize sum_i tau_i,  (tau_i, D f_i) in SOC,  D = diag(1, 1, 1, mu/mu_s)
    Linf full:   minimize s,  (s, D f_i) in SOC              (eq. 15: ||f_i|| = ||D f_i||)
The record's sigma is the objective of the returned forces; sigma_lower is Clarabel's dual
objective when it reports Solved (a lower bound to its feasibility tolerance), else NaN. Status:
Solved -> "optimal", AlmostSolved -> "inaccurate", (Almost)PrimalInfeasible -> "infeasible",
MaxIterations and MaxTime -> "max_iter", anything else -> "inaccurate" with the last iterate
(graspforce.grasping.baselines._status).
"""
import numpy as np
import scipy.sparse as sp

from . import _status
from ._record import check_problem, check_wrench

METHOD = "clarabel-socp"
TIGHT = {"tol_gap_abs": 1e-10, "tol_gap_rel": 1e-10, "tol_feas": 1e-10, "tol_ktratio": 1e-8}


def min_force(grasp, w_ext, norm="L1", magnitude="normal", tight=False, **options):
    """The minimal contact forces, from a problem and a Clarabel solver built in this call."""
    import clarabel
    socp = _Socp(check_problem(grasp, norm, magnitude))
    settings = _settings(clarabel, tight, options)
    solver = clarabel.DefaultSolver(*socp.data(check_wrench(w_ext)), settings)
    return socp.result(solver.solve())


class Prepared:
    """The SOCP of one grasp and objective with its Clarabel solver, built once;
    `solve(w_ext)` per wrench."""

    def __init__(self, grasp, norm="L1", magnitude="normal", tight=False, **options):
        import clarabel
        if options.get("presolve_enable", False):
            raise ValueError("presolve_enable: must be False here: Clarabel refuses data "
                             "updates with presolve on")
        self._socp = _Socp(check_problem(grasp, norm, magnitude))
        settings = _settings(clarabel, tight, {**options, "presolve_enable": False})
        self.solver = clarabel.DefaultSolver(*self._socp.data(np.zeros(6)), settings)

    def solve(self, w_ext):
        """The MinForce for w_ext: only b changes, the KKT structure is reused."""
        return self._socp.result(self.solve_raw(w_ext))

    def solve_raw(self, w_ext):
        """Clarabel's own solution for w_ext, without the MinForce record that `solve` builds
        from it: the solver's cost alone, for timing against."""
        self.solver.update(b=self._socp.data(check_wrench(w_ext))[3])
        return self.solver.solve()


class _Socp:
    """Clarabel's (P, q, A, b, cones) for one grasp and objective, and the record of a solution."""

    def __init__(self, objective):
        import clarabel
        self.objective = objective
        contacts, norm, magnitude = objective.contacts, objective.norm, objective.magnitude
        sizes = [1 if c.mu == 0.0 else 4 if c.mu_spin > 0.0 else 3 for c in contacts]
        starts = np.concatenate(([0], np.cumsum(sizes))).astype(int)
        m, nf = len(contacts), int(starts[-1])
        # epigraph variables: one per contact for a sum of norms, one shared bound for a maximum
        n_epigraph = {("L1", "normal"): 0, ("L1", "full"): m}.get((norm, magnitude), 1)
        nx = nf + n_epigraph

        equilibrium = np.zeros((6, nx))
        rows, cones = [equilibrium], [clarabel.ZeroConeT(6)]
        for c, G, start, k in zip(contacts, objective.G, starts, sizes):
            equilibrium[:, start:start + k] = G[:, :k]
            # b = 0 on these rows, so -A x is the cone's point: minus the scaled forces
            scale = [1.0] if k == 1 else [1.0, 1.0 / c.mu, 1.0 / c.mu] + (
                [1.0 / c.mu_spin] if k == 4 else [])
            cone_rows = np.zeros((k, nx))
            cone_rows[:, start:start + k] = -np.diag(scale)
            rows.append(cone_rows)
            cones.append(clarabel.SecondOrderConeT(k) if k > 1 else clarabel.NonnegativeConeT(1))

        q = np.zeros(nx)
        if magnitude == "normal" and norm == "L1":
            q[starts[:-1]] = 1.0
        elif magnitude == "normal":
            q[nf] = 1.0
            bound = np.zeros((m, nx))                 # -A x = s - f_i1 >= 0
            bound[np.arange(m), starts[:-1]] = 1.0
            bound[:, nf] = -1.0
            rows.append(bound)
            cones.append(clarabel.NonnegativeConeT(m))
        else:
            q[nf:] = 1.0
            for i, (c, start, k) in enumerate(zip(contacts, starts, sizes)):
                norm_rows = np.zeros((1 + k, nx))     # -A x = (tau_i or s, D f_i)
                norm_rows[0, nf + (i if norm == "L1" else 0)] = -1.0
                weight = [1.0, 1.0, 1.0, c.mu / c.mu_spin] if k == 4 else [1.0] * k
                norm_rows[1:, start:start + k] = -np.diag(weight)
                rows.append(norm_rows)
                cones.append(clarabel.SecondOrderConeT(1 + k))

        A = np.vstack(rows)
        self._P, self._q, self._A = sp.csc_matrix((nx, nx)), q, sp.csc_matrix(A)
        self._b, self._cones = np.zeros(A.shape[0]), cones
        # x -> forces (m, 4): the index of each force component in x, or nx (a zero appended)
        take = np.full((m, 4), nx)
        for i, (start, k) in enumerate(zip(starts, sizes)):
            take[i, :k] = np.arange(start, start + k)
        self._take = take

    def data(self, w):
        """(P, q, A, b, cones) for the wrench w; b is one buffer, rewritten per call."""
        self._b[:6] = -w
        return self._P, self._q, self._A, self._b, self._cones

    def result(self, solution):
        status = _status.clarabel(solution.status)
        x = np.append(solution.x, 0.0)
        forces = x[self._take] if status != "infeasible" and np.isfinite(x).all() else None
        # the dual objective bounds the minimum only once Clarabel's full tolerances are met
        lower = float(solution.obj_val_dual) if status == "optimal" else np.nan
        return self.objective.record(forces, status, lower, METHOD, solution.iterations)


def _settings(clarabel, tight, options):
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    for key, value in {**(TIGHT if tight else {}), **options}.items():
        if not hasattr(settings, key):
            raise ValueError(f"{key}: not a Clarabel setting")
        setattr(settings, key, value)
    return settings
