"""graspforce: exact grasp and contact analysis by ray shooting (Zheng & Yamane)."""
from .contact import Contact
from .distance import closest_point, cone_distance
from .grasp import Grasp
from .growth import GrowthDistance, growth_distance
from .ray_shoot import METHODS, ray_shoot
from .results import (ClosestPoint, ConeDistance, GraspQuality, GrowthDistanceResult, MinForce,
                      RayShot)
from .sets import (Ball, Box, Capsule, ConeCap, ConvexSet, Ellipsoid, Polytope, TruncatedCone,
                   affine, hull, minkowski_sum, pose)



def __getattr__(name):
    # graspforce.robots needs Pinocchio, an optional extra, and graspforce.batch loads its
    # helpers: both imported on first use only
    if name in ("robots", "batch"):
        import importlib
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'graspforce' has no attribute {name!r}")


__all__ = [
    "METHODS", "Ball", "Box", "Capsule", "ClosestPoint", "ConeCap", "ConeDistance", "Contact",
    "ConvexSet", "Ellipsoid", "Grasp", "GraspQuality", "GrowthDistance", "GrowthDistanceResult",
    "MinForce", "Polytope", "RayShot", "TruncatedCone", "affine", "closest_point",
    "cone_distance", "growth_distance", "hull", "minkowski_sum", "pose", "ray_shoot",
]
