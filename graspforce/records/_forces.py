"""How min_force's contact forces are read off the final simplex Z_W(r): the force reader's layout
(the compiled reading is core/grasping/forces.hpp's `contact_forces`, run on every min_force
call)."""
import numpy as np

from .._core.forces import LENGTH, READER_HEAD

# rows of a wrench space's leaf table (graspforce.grasping.wrench_space.Target._table)
CONTACT, SLOT, SIZE, MAP = 0, 1, 2, 3

# A Target's force reader (graspforce.grasping.wrench_space): how forces are read off witnesses, as
# one float array read by offsets, since each array a min_force call hands to the compiled code
# costs ~50 ns to cross from Python (a zero-wrench call 641 -> 398 ns with the six gathered here)
# and each view of one costs reference counting. Layout: [witness size, linf, full, m, leaves L,
# length, table (4, L) by rows CONTACT, SLOT, SIZE, MAP, G (m, 6, 4), spin_weight (m,), mu (m,),
# mu_spin (m,), maps].
def force_reader(witness_size, linf, full, G, table, maps, spin_weight, friction, length):
    """The reader array of a shot set (layout above): its witness size, the objective (linf,
    full), the grasp's length L and the contacts' G_i (m, 6, 4) in the units (force, torque / L)
    of the set, the leaf table and maps of `contact_forces`, the weights of f_4^2 (full
    magnitude) and the contacts' (mu, mu_spin) (m, 2), whose friction cones the forces'
    certificate checks (`forces_hold`)."""
    return np.concatenate(([witness_size, linf, full, G.shape[0], table.shape[1], length],
                           table.ravel(), G.ravel(), spin_weight, friction[:, 0], friction[:, 1],
                           maps)).astype(float)


def force_views(packed, m):
    """(forces (m, 4), wrenches (m, 6), resultant (6,)): views of those entries of a packed
    answer, for the Python reader."""
    return (packed[1:1 + 4 * m].reshape(m, 4), packed[1 + 4 * m:1 + 10 * m].reshape(m, 6),
            packed[1 + 10 * m:7 + 10 * m])
