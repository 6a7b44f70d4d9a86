"""graspforce: exact grasp and contact analysis by ray shooting (Zheng & Yamane)."""
from .geometry.sets import (Ball, Box, Capsule, ConeCap, ConvexSet, Ellipsoid, Polytope,
                            TruncatedCone, affine, hull, minkowski_sum, pose)
from .grasping.contact import Contact
from .grasping.grasp import Grasp
from .growth.growth import GrowthDistance, growth_distance
from .records.results import (ClosestPoint, ConeDistance, GraspQuality, GrowthDistanceResult,
                              MinForce, RayShot)
from .shooting.distance import closest_point, cone_distance
from .shooting.ray_shoot import METHODS, ray_shoot



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
