"""What every baseline shares: the input checks of Grasp.min_force, and the MinForce record
derived from a solver's forces alone (so that sigma, the resultant and the cone test judge the
forces actually returned, not the solver's own objective value)."""
import math

import numpy as np

from ..._validate import check_choice, finite_vector
from ..contact import Contact
from ..grasp import Grasp
from ...records.results import MinForce
from ..wrench_space import MAGNITUDES, NORMS


def check_problem(grasp, norm, magnitude):
    """The Objective of a gf.Grasp or of a sequence of gf.Contact, after the input checks."""
    if isinstance(grasp, Grasp):
        contacts = grasp.contacts
    else:
        contacts = tuple(grasp)
        if not contacts or not all(isinstance(c, Contact) for c in contacts):
            raise ValueError("grasp: must be a gf.Grasp or a non-empty sequence of gf.Contact")
    check_choice(norm, NORMS, "norm")
    check_choice(magnitude, MAGNITUDES, "magnitude")
    # a Grasp keeps its G_i: reading them is free, rebuilding them costs ~15 us per contact,
    # which would be charged to the baselines built per call
    matrices = (grasp.contact_matrices if isinstance(grasp, Grasp)
                else np.array([c.matrix for c in contacts]))
    return Objective(contacts, matrices, norm, magnitude)


def check_wrench(w_ext):
    """w_ext as a finite (6,) float array."""
    return finite_vector(w_ext, "w_ext", 6)[0]


class Objective:
    """sigma of eq. (13) or (15) and the MinForce record, for one grasp and objective."""

    def __init__(self, contacts, matrices, norm, magnitude):
        self.contacts, self.norm, self.magnitude = contacts, norm, magnitude
        self.G = matrices                     # (m, 6, 4): G_i of eq. (11)
        # (mu / mu_s)^2 weighs the spin moment in ||f|| of eq. (15); point contacts have f_4 = 0
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
        """The MinForce of a solver's local forces (m, 4), or of none (forces None: infeasible,
        or no finite iterate), which gives zero forces and sigma = sigma_lower = inf."""
        feasible = forces is not None
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
