"""The MinForce record of a baseline: everything derived from the solver's forces alone."""
import math

import numpy as np

from ..results import MinForce
from ..wrench_space import MAGNITUDES, NORMS


def check_problem(grasp, w_ext, norm, magnitude):
    """(contacts, w) after the same input checks as Grasp.min_force."""
    from .._validate import finite_vector
    contacts = tuple(getattr(grasp, "contacts", grasp))
    if not contacts:
        raise ValueError("grasp: needs at least one contact")
    if norm not in NORMS:
        raise ValueError(f"norm: must be one of {list(NORMS)}, got {norm!r}")
    if magnitude not in MAGNITUDES:
        raise ValueError(f"magnitude: must be one of {list(MAGNITUDES)}, got {magnitude!r}")
    w, _ = finite_vector(w_ext, "w_ext", 6)
    return contacts, w


class Objective:
    """What a baseline needs to turn its forces into a MinForce: the contacts' G_i of eq. (11)
    and the spin weights of eq. (15), computed once per grasp."""

    def __init__(self, contacts, norm, magnitude):
        self.contacts, self.norm, self.magnitude = contacts, norm, magnitude
        self.G = np.array([c.matrix for c in contacts])
        self.spin_weight = np.array([(c.mu / c.mu_spin) ** 2 if c.mu_spin > 0 else 0.0
                                     for c in contacts])

    def sigma(self, forces):
        """sigma of eq. (13) or (15) for local forces (m, 4)."""
        if self.magnitude == "normal":
            values = forces[:, 0]
        else:
            values = np.sqrt((forces[:, :3] ** 2).sum(axis=1)
                             + self.spin_weight * forces[:, 3] ** 2)
        return float(values.sum() if self.norm == "L1" else values.max())

    def record(self, forces, status, sigma_lower, method, iterations):
        """A MinForce from a solver's forces; zero forces and sigma = inf unless feasible."""
        feasible = status in ("optimal", "max_iter", "inaccurate") and forces is not None
        if not feasible:
            forces = np.zeros((len(self.contacts), 4))
        wrenches = np.einsum("ijk,ik->ij", self.G, forces)
        return MinForce(
            feasible=feasible, status=status,
            sigma=self.sigma(forces) if feasible else math.inf,
            sigma_lower=sigma_lower if feasible else math.inf, forces=forces,
            world_forces=wrenches[:, :3], wrenches=wrenches, resultant=wrenches.sum(axis=0),
            norm=self.norm, magnitude=self.magnitude, method=method,
            iterations=int(iterations), support_calls=0, ray=None)
