"""Baseline (a): the exact problem as a second-order cone program, solved by Clarabel.

Variables: per contact its free force components x_i (soft finger f_1..f_4, point contact
f_1..f_3, frictionless f_1), plus the epigraph variables of the objective. Constraints (Clarabel's
form A x + s = b, s in a cone):
    sum_i G_i f_i = -w_ext                                  (zero cone, eq. 11)
    (f_1, f_2/mu, f_3/mu, f_4/mu_s) in SOC                  (friction cone, eq. 12)
    L1 normal:   minimize sum_i f_i1
    Linf normal: minimize s,  s - f_i1 >= 0
    L1 full:     minimize sum_i tau_i,  (tau_i, D f_i) in SOC,  D = diag(1, 1, 1, mu/mu_s)
    Linf full:   minimize s,  (s, D f_i) in SOC               (eq. 15)
Only b depends on the wrench, so `Prepared` builds the solver once and calls
`solver.update(b=...)` per wrench (presolve off: Clarabel refuses data updates with it on).
sigma_lower is Clarabel's dual objective.
"""
import numpy as np
import scipy.sparse as sp

from .._validate import finite_vector
from ._record import Objective, check_problem

_TIGHT = {"tol_gap_abs": 1e-10, "tol_gap_rel": 1e-10, "tol_feas": 1e-10, "tol_ktratio": 1e-8,
          "max_iter": 200}


class Prepared:
    """The SOCP of one grasp and objective, built once; `solve(w_ext)` per wrench.

    tight=True sets gap and feasibility tolerances to 1e-10 (defaults are 1e-8), for reference
    values; options are any other Clarabel settings.
    """

    def __init__(self, grasp, norm="L1", magnitude="normal", tight=False, **options):
        import clarabel
        self._clarabel = clarabel
        contacts, _ = check_problem(grasp, np.zeros(6), norm, magnitude)
        self.contacts, self.norm, self.magnitude = contacts, norm, magnitude
        self._objective = Objective(contacts, norm, magnitude)
        sizes = [_free_size(c) for c in contacts]
        starts = np.concatenate(([0], np.cumsum(sizes)))
        m, nf = len(contacts), int(starts[-1])
        n_extra = m if (norm, magnitude) == ("L1", "full") else (1 if norm == "Linf" else 0)
        nx = nf + n_extra
        rows, cones, q = [], [clarabel.ZeroConeT(6)], np.zeros(nx)
        eq = np.zeros((6, nx))
        for i, c in enumerate(contacts):
            eq[:, starts[i]:starts[i + 1]] = c.matrix[:, :sizes[i]]
        rows.append(eq)
        for i, c in enumerate(contacts):
            block = np.zeros((sizes[i], nx))
            scale = [1.0] if c.mu == 0.0 else [1.0, 1.0 / c.mu, 1.0 / c.mu]
            if c.mu_spin > 0.0:
                scale.append(1.0 / c.mu_spin)
            for a in range(sizes[i]):
                block[a, starts[i] + a] = -scale[a]
            rows.append(block)
            cones.append(clarabel.SecondOrderConeT(sizes[i]) if sizes[i] > 1
                         else clarabel.NonnegativeConeT(1))
        if magnitude == "normal":
            if norm == "L1":
                q[starts[:-1]] = 1.0
            else:
                q[nf] = 1.0
                block = np.zeros((m, nx))
                block[np.arange(m), starts[:-1]] = 1.0
                block[:, nf] = -1.0
                rows.append(block)
                cones.append(clarabel.NonnegativeConeT(m))
        else:
            for i, c in enumerate(contacts):
                epigraph = nf + (i if norm == "L1" else 0)
                q[epigraph] = 1.0
                block = np.zeros((1 + sizes[i], nx))
                block[0, epigraph] = -1.0
                weight = [1.0, 1.0, 1.0, c.mu / c.mu_spin if c.mu_spin > 0 else 0.0]
                for a in range(sizes[i]):
                    block[1 + a, starts[i] + a] = -weight[a]
                rows.append(block)
                cones.append(clarabel.SecondOrderConeT(1 + sizes[i]))
        A = np.vstack(rows)
        self._starts, self._sizes = starts, sizes
        self._b = np.zeros(A.shape[0])
        settings = clarabel.DefaultSettings()
        settings.verbose = False
        settings.presolve_enable = False
        for key, value in {**(_TIGHT if tight else {}), **options}.items():
            setattr(settings, key, value)
        self._args = (sp.csc_matrix((nx, nx)), q, sp.csc_matrix(A), cones, settings)
        self.solver = clarabel.DefaultSolver(*self._args[:3], self._b, *self._args[3:])
        self._status = _status_map(clarabel)

    def solve(self, w_ext):
        """MinForce for w_ext, reusing the factorization structure (only b changes)."""
        w, _ = finite_vector(w_ext, "w_ext", 6)
        self._b[:6] = -w
        self.solver.update(b=self._b)
        return self._result(self.solver.solve())

    def solve_new(self, w_ext):
        """MinForce for w_ext from a solver built for this call (how it is usually called)."""
        w, _ = finite_vector(w_ext, "w_ext", 6)
        b = self._b.copy()
        b[:6] = -w
        P, q, A, cones, settings = self._args
        return self._result(self._clarabel.DefaultSolver(P, q, A, b, cones, settings).solve())

    def _result(self, sol):
        status = self._status.get(str(sol.status), "inaccurate")
        forces = None
        if status in ("optimal", "max_iter", "inaccurate"):
            x = np.asarray(sol.x)
            forces = np.zeros((len(self.contacts), 4))
            for i, size in enumerate(self._sizes):
                forces[i, :size] = x[self._starts[i]:self._starts[i] + size]
        return self._objective.record(forces, status, float(sol.obj_val_dual), "clarabel-socp",
                                      sol.iterations)


def min_force(grasp, w_ext, norm="L1", magnitude="normal", tight=False, **options):
    """The minimal contact forces as an SOCP, built and solved by Clarabel in this call."""
    return Prepared(grasp, norm, magnitude, tight, **options).solve_new(w_ext)


def _free_size(contact):
    if contact.mu == 0.0:
        return 1
    return 4 if contact.mu_spin > 0.0 else 3


def _status_map(clarabel):
    S = clarabel.SolverStatus
    return {str(S.Solved): "optimal", str(S.AlmostSolved): "inaccurate",
            str(S.PrimalInfeasible): "infeasible", str(S.AlmostPrimalInfeasible): "infeasible",
            str(S.MaxIterations): "max_iter", str(S.MaxTime): "max_iter"}
