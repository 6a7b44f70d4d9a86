"""gf.batch: many wrenches against one grasp, many grasps against one load, many poses of two
shapes; locally on all cores, or in chunks on a Dask cluster (client=). docs/batch.md."""
from . import wrenches
from .coverage import Coverage, coverage, coverage_curve, coverage_of, wilson_interval
from .forces import min_force, min_force_grasps
from .growth import growth_distance
from .result import STATUSES, BatchForces, BatchGrowth
from .wrenches import ball, ellipsoid, gaussian, table5

__all__ = ["STATUSES", "BatchForces", "BatchGrowth", "Coverage", "ball", "coverage",
           "coverage_curve", "coverage_of", "ellipsoid", "gaussian", "growth_distance",
           "min_force", "min_force_grasps", "table5", "wilson_interval", "wrenches"]
