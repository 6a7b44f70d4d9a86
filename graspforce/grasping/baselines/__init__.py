"""The solvers users would use instead of ray shooting: our yardstick.

One module per solver family, one signature, the same `gf.MinForce` record as
`Grasp.min_force` (shot None, support_calls 0):

    min_force(grasp, w_ext, norm="L1", magnitude="normal", **options) -> MinForce

`grasp` is a gf.Grasp or a sequence of gf.Contact.

- `clarabel_socp`: the exact problem (elliptic soft-finger cones, eq. 12; all four objectives)
  as a second-order cone program for Clarabel's own API; `clarabel_socp.Prepared` builds it once
  per grasp and objective and only updates the wrench (Clarabel at its fastest).
- `pyramid`: the friction cones linearized into inscribed pyramids, a linear program solved
  through qpsolvers by OSQP or Clarabel as users usually call them (normal magnitude only).

These modules need the `baselines` extra (clarabel, qpsolvers, osqp); the library does not.
"""
from . import clarabel_socp, pyramid

__all__ = ["clarabel_socp", "pyramid"]
