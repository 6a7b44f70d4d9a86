"""graspforce: exact grasp and contact analysis by ray shooting (Zheng & Yamane)."""
from .distance import closest_point, cone_distance
from .ray_shoot import METHODS, ray_shoot
from .results import ClosestPoint, ConeDistance, RayShot
from .sets import (Ball, Box, Capsule, ConvexSet, Ellipsoid, Polytope, TruncatedCone, affine, hull,
                   minkowski_sum, pose)

__all__ = [
    "Ball", "Box", "Capsule", "ClosestPoint", "ConeDistance", "ConvexSet", "Ellipsoid", "METHODS",
    "Polytope", "RayShot", "TruncatedCone", "affine", "closest_point", "cone_distance", "hull",
    "minkowski_sum", "pose", "ray_shoot",
]
