"""The solvers users would use instead of ray shooting: our yardstick (issue 3).

One module per solver family, one signature, the same `gf.MinForce` record as
`Grasp.min_force`:

    min_force(grasp, w_ext, norm="L1", magnitude="normal", **options) -> MinForce

- `clarabel_socp`: the exact problem (elliptic soft-finger cones, eq. 12) as a second-order cone
  program for Clarabel; `clarabel_socp.Prepared` builds it once per grasp and objective and only
  updates the wrench (Clarabel at its fastest).
- `pyramid`: the friction cones linearized into inscribed pyramids, solved as a linear program
  through qpsolvers (OSQP, Clarabel, ...) as users usually call them.

These modules need the `baselines` extra (clarabel, qpsolvers, osqp); the library does not.
"""
from . import clarabel_socp, pyramid

__all__ = ["clarabel_socp", "pyramid"]
