"""graspforce: exact grasp and contact analysis by ray shooting (Zheng & Yamane)."""
from .sets import (ConvexSet, Polytope, Ellipsoid, Ball, Box, TruncatedCone, Capsule, hull,
                   minkowski_sum, affine, pose)
from .ray_shoot import ray_shoot, METHODS
from .results import RayShot, ClosestPoint, ConeDistance
from .distance import closest_point, cone_distance
