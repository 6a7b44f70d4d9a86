"""The objects a hand holds, as surfaces: signed distance, inward normal, and lines to draw.

A contact with normal "object" pushes along the inward surface normal at its point, and IK puts
fingertips on the surface where the signed distance is zero. Boxes and polyhedra are convex
hulls of their vertices, held as half-spaces a.x <= b (unit a): the signed distance
max(a.x - b) is exact on the surface and near a face, which is all IK and the normals need.
"""
import numpy as np


class Sphere:
    def __init__(self, center, radius):
        self.center, self.radius = np.asarray(center, float), float(radius)

    def signed_distance(self, p):
        return float(np.linalg.norm(p - self.center) - self.radius)

    def outward_normal(self, p):
        d = p - self.center
        return d / np.linalg.norm(d)

    def edges(self, n=24):
        """Three great circles, as a list of (k, 3) polylines."""
        a = np.linspace(0.0, 2.0 * np.pi, 4 * n + 1)
        c, s = np.cos(a), np.sin(a)
        z = np.zeros_like(a)
        return [self.center + self.radius * np.column_stack(v)
                for v in ((c, s, z), (c, z, s), (z, c, s))]


class Polyhedron:
    """The convex hull of `vertices` given in the object's frame, placed at (center, rotation)."""

    def __init__(self, center, rotation, vertices):
        from scipy.spatial import ConvexHull
        self.vertices = np.asarray(center) + np.asarray(vertices) @ np.asarray(rotation).T
        hull = ConvexHull(self.vertices)
        # Qhull splits each face into triangles with equal planes: keep one plane per face
        planes = np.unique(np.round(hull.equations, 12), axis=0)
        self.normals, self.offsets = planes[:, :3], -planes[:, 3]
        self.triangles = self.vertices[hull.simplices]

    def signed_distance(self, p):
        return float(np.max(self.normals @ p - self.offsets))

    def outward_normal(self, p):
        return self.normals[np.argmax(self.normals @ p - self.offsets)]

    def edges(self):
        """The edges between faces of different planes, as a list of (2, 3) segments."""
        segments = []
        for tri in self.triangles:
            for a, b in ((0, 1), (1, 2), (2, 0)):
                mid = 0.5 * (tri[a] + tri[b])
                on = np.abs(self.normals @ mid - self.offsets) < 1e-9
                if on.sum() >= 2:
                    segments.append(np.array([tri[a], tri[b]]))
        return segments


def surface(obj):
    """The Sphere or Polyhedron of an ObjectSpec, or None for terrain."""
    if obj.shape == "sphere":
        return Sphere(obj.center, obj.radius)
    if obj.shape in ("box", "polyhedron"):
        return Polyhedron(obj.center, obj.rotation, obj.vertices)
    return None
