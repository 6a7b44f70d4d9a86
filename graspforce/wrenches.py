"""External wrenches drawn from a seeded distribution, for batches of min_force problems."""
import numpy as np

from ._validate import finite_scalar, positive_int


def sample_wrenches(count, seed=0, force_scale=1.0, torque_scale=0.05, mean=None):
    """(count, 6) wrenches (force, torque): mean + independent normal entries with standard
    deviation force_scale for the forces and torque_scale for the torques, from
    numpy.random.default_rng(seed); the same arguments give the same wrenches everywhere."""
    count = positive_int(count, "count")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed: must be a non-negative integer, got {seed!r}")
    fs = finite_scalar(force_scale, "force_scale", minimum=0.0)
    ts = finite_scalar(torque_scale, "torque_scale", minimum=0.0)
    rng = np.random.default_rng(int(seed))
    W = rng.standard_normal((count, 6)) * np.array([fs, fs, fs, ts, ts, ts])
    if mean is not None:
        from ._validate import finite_array
        W += finite_array(mean, "mean", shape=(6,))
    return W
