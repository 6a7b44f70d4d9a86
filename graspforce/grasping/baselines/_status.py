"""The solvers' own verdicts mapped onto MinForce.status ("optimal", "infeasible", "max_iter",
"inaccurate"), never upgraded: a solver that stopped at its iteration limit says "max_iter"
even when its last iterate happens to be good."""
import functools


@functools.cache
def _clarabel_statuses():
    from clarabel import SolverStatus as S
    # "almost" infeasible is still the solver's claim that no forces exist (its iterate is a
    # certificate, not a solution), so it is reported as infeasible, not as an inaccurate optimum
    return {S.Solved: "optimal", S.AlmostSolved: "inaccurate",
            S.PrimalInfeasible: "infeasible", S.AlmostPrimalInfeasible: "infeasible",
            S.MaxIterations: "max_iter", S.MaxTime: "max_iter"}


@functools.cache
def _osqp_statuses():
    # the enum qpsolvers itself compares against; its integer values changed between OSQP 0.6
    # and 1.0, its names did not
    from osqp import SolverStatus as S
    return {S.OSQP_SOLVED: "optimal", S.OSQP_SOLVED_INACCURATE: "inaccurate",
            S.OSQP_PRIMAL_INFEASIBLE: "infeasible", S.OSQP_PRIMAL_INFEASIBLE_INACCURATE: "infeasible",
            S.OSQP_MAX_ITER_REACHED: "max_iter", S.OSQP_TIME_LIMIT_REACHED: "max_iter"}


def clarabel(status):
    """MinForce.status for a clarabel.SolverStatus. The rest (NumericalError,
    InsufficientProgress, and dual infeasibility, which a problem bounded below by 0 cannot
    have) leave the solver's last iterate: "inaccurate"."""
    return _clarabel_statuses().get(status, "inaccurate")


def osqp(status_val):
    """MinForce.status for OSQP's info.status_val; the rest (dual infeasible, non-convex,
    interrupted, unsolved) are "inaccurate"."""
    return _osqp_statuses().get(status_val, "inaccurate")
