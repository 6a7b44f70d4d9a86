"""JSON forms of the library's inputs: convex sets, contacts, grasps and poses.

The service (server/) and its client (graspforce.client) send problems as these plain dicts of
lists and numbers, so a problem rebuilt from its JSON form is the same problem, to the bit:
floats survive JSON unchanged (Python writes the shortest repr that reads back exactly).

A set is a tagged dict, one tag per constructor of graspforce.geometry.sets:
    {"type": "polytope", "vertices": [[...], ...]}
    {"type": "ellipsoid", "center": [...], "shape": [[...], ...]}
    {"type": "ball", "center": [...], "radius": r}
    {"type": "box", "half_extents": [...], "center": [...] | null, "rotation": [[...]] | null}
    {"type": "truncated_cone", "bottom_radius": a, "top_radius": b, "height": h}
    {"type": "capsule", "radius": r, "length": l}
    {"type": "cone_cap", "mu": mu, "dim": n}
    {"type": "hull", "sets": [set, ...]}
    {"type": "minkowski_sum", "sets": [set, ...]}
    {"type": "affine", "matrix": [[...]], "set": set, "offset": [...] | null}
set_to_dict writes the tree a set was built as (a Box with a pose is an affine image of a box, a
Capsule a sum of a segment and a ball), which set_from_dict rebuilds into the same program.
"""
import numpy as np

from .geometry import sets as S
from .grasping.contact import Contact

SET_TYPES = ("polytope", "ellipsoid", "ball", "box", "truncated_cone", "capsule", "cone_cap",
             "hull", "minkowski_sum", "affine")


def set_to_dict(A):
    """The JSON form of a graspforce convex set (module docstring)."""
    if isinstance(A, S.Polytope):
        return {"type": "polytope", "vertices": A.vertices.tolist()}
    if isinstance(A, S.Ball):
        return {"type": "ball", "center": A.center.tolist(), "radius": A.radius}
    if isinstance(A, S.Ellipsoid):
        return {"type": "ellipsoid", "center": A.center.tolist(), "shape": A.shape.tolist()}
    if isinstance(A, S._AxisBox):
        return {"type": "box", "half_extents": A.half.tolist(), "center": None, "rotation": None}
    if isinstance(A, S.TruncatedCone):
        return {"type": "truncated_cone", "bottom_radius": A.bottom_radius,
                "top_radius": A.top_radius, "height": A.height}
    if isinstance(A, S.ConeCap):
        return {"type": "cone_cap", "mu": A.mu, "dim": A.dim}
    if isinstance(A, S.Hull):
        return {"type": "hull", "sets": [set_to_dict(X) for X in A.sets]}
    if isinstance(A, S.MinkowskiSum):
        return {"type": "minkowski_sum", "sets": [set_to_dict(X) for X in A.sets]}
    if isinstance(A, S.Affine):
        return {"type": "affine", "matrix": A.matrix.tolist(), "set": set_to_dict(A.inner),
                "offset": A.offset.tolist()}
    raise TypeError(f"A: expected a graspforce convex set, got {type(A).__name__}")


def set_from_dict(d, name="set"):
    """The convex set of a JSON form (module docstring); errors name the field and the rule."""
    if not isinstance(d, dict):
        raise TypeError(f"{name}: expected an object with a 'type'")
    kind = d.get("type")
    if kind not in SET_TYPES:
        raise ValueError(f"{name}.type: must be one of {list(SET_TYPES)}, got {kind!r}")
    try:
        return _build(kind, d, name)
    except KeyError as missing:
        raise ValueError(f"{name}.{missing.args[0]}: required for a {kind}") from None
    except (TypeError, ValueError) as error:
        message = str(error)
        if message.startswith(name + "."):      # a child's error, already named by its path
            raise
        field, _, rule = message.partition(": ")
        field = _FIELDS.get(field, field)
        raise type(error)(f"{name}.{field}: {rule}") from None


# the library's names for what the JSON form calls otherwise
_FIELDS = {"hull": "sets", "minkowski_sum": "sets", "M": "matrix", "t": "offset", "A": "set"}


def _build(kind, d, name):
    if kind == "polytope":
        return S.Polytope(d["vertices"])
    if kind == "ellipsoid":
        return S.Ellipsoid(d["center"], d["shape"])
    if kind == "ball":
        return S.Ball(d["center"], d["radius"])
    if kind == "box":
        return S.Box(d["half_extents"], d.get("center"), d.get("rotation"))
    if kind == "truncated_cone":
        return S.TruncatedCone(d["bottom_radius"], d["top_radius"], d["height"])
    if kind == "capsule":
        return S.Capsule(d["radius"], d["length"])
    if kind == "cone_cap":
        return S.ConeCap(d["mu"], d["dim"])
    if kind in ("hull", "minkowski_sum"):
        children = d["sets"]
        if not isinstance(children, list):
            raise TypeError(f"{name}.sets: expected a list of sets")
        parts = [set_from_dict(X, f"{name}.sets[{i}]") for i, X in enumerate(children)]
        return S.hull(*parts) if kind == "hull" else S.minkowski_sum(*parts)
    return S.affine(d["matrix"], set_from_dict(d["set"], f"{name}.set"), d.get("offset"))


def contact_to_dict(c):
    """{position, normal, mu, mu_spin, tangents} of a gf.Contact (normal as normalized)."""
    return {"position": c.position.tolist(), "normal": c.normal.tolist(), "mu": c.mu,
            "mu_spin": c.mu_spin, "tangents": [c.tangents[0].tolist(), c.tangents[1].tolist()]}


def contact_from_dict(d, name="contact"):
    """The gf.Contact of a JSON form; errors name the field and the rule."""
    if not isinstance(d, dict):
        raise TypeError(f"{name}: expected an object with position, normal, mu")
    try:
        return Contact(d["position"], d["normal"], d["mu"], d.get("mu_spin", 0.0),
                       d.get("tangents"))
    except KeyError as missing:
        raise ValueError(f"{name}.{missing.args[0]}: required") from None
    except (TypeError, ValueError) as error:
        raise type(error)(f"{name}.{error}") from None


def grasp_to_dict(grasp):
    """{"contacts": [contact, ...], "length": L}: a grasp's JSON form. The contacts keep their
    tangents, so the rebuilt grasp has the same local force frames, hence the same forces; the
    characteristic length (Grasp.length) the same units, hence the same answers."""
    return {"contacts": [contact_to_dict(c) for c in grasp.contacts], "length": grasp.length}


def grasp_from_dict(d):
    """The gf.Grasp of {"contacts": [...], "length": L}; without a length (or with null) the
    grasp derives its own."""
    from .grasping.grasp import Grasp
    contacts = d.get("contacts") if isinstance(d, dict) else None
    if not isinstance(contacts, list) or not contacts:
        raise ValueError("contacts: required, a non-empty list of contacts")
    return Grasp((contact_from_dict(c, f"contacts[{i}]") for i, c in enumerate(contacts)),
                 length=d.get("length"))


def pose_to_dict(pose, name="pose"):
    """{"rotation": 3x3, "translation": 3} of (R, p), a 4x4 matrix or a pinocchio.SE3."""
    from .growth.growth import parse_pose
    R, p = parse_pose(pose, name)
    return {"rotation": R.tolist(), "translation": p.tolist()}


def pose_from_dict(d):
    return (np.array(d["rotation"], dtype=float), np.array(d["translation"], dtype=float))
