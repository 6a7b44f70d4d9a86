"""Scenario files: TOML read with tomllib, checked field by field into a ScenarioSpec.

Only the file is judged here (types, ranges, required and unknown fields); whether its robot,
frames and joints exist is judged against the model by graspforce.robots.scenario. Every error
is a ValueError "<file>: <field>: <rule>", so a user editing a copied file knows where to look.
The format is documented in docs/robots.md and shown by the files in scenarios/.
"""
import dataclasses
import math
import pathlib
import tomllib

import numpy as np

from .models import ROBOTS

SHAPES = ("sphere", "box", "polyhedron", "terrain")
KINDS = ("point", "soft", "patch")
FRAME_AXES = {"frame x": (0, 1.0), "frame -x": (0, -1.0), "frame y": (1, 1.0),
              "frame -y": (1, -1.0), "frame z": (2, 1.0), "frame -z": (2, -1.0)}
NORMAL_WORDS = ("object",) + tuple(FRAME_AXES)


@dataclasses.dataclass(frozen=True)
class ContactSpec:
    frame: str
    kind: str                 # "point", "soft" or "patch" (four corner point contacts)
    mu: float
    mu_spin: float            # metres; 0 unless soft
    normal: object            # one of NORMAL_WORDS, or a unit (3,) array in the world frame
    offset: np.ndarray        # the contact point (or the patch centre) in the frame, metres
    size: tuple | None        # patch sides along the frame's x and y, metres
    target: np.ndarray | None  # where IK should put the contact, world frame


@dataclasses.dataclass(frozen=True)
class ObjectSpec:
    shape: str
    center: np.ndarray        # world position of the object's frame, its centre of mass
    rotation: np.ndarray      # world orientation of the object's frame
    radius: float | None = None
    vertices: np.ndarray | None = None   # box and polyhedron, in the object's frame
    mass: float = 0.0


@dataclasses.dataclass(frozen=True)
class ScenarioSpec:
    name: str
    source: str               # the file, for error messages
    description: str
    robot: str
    joints: dict              # joint name -> position (radians or metres)
    base_position: np.ndarray | None
    base_rotation: np.ndarray | None
    object: ObjectSpec
    gravity: np.ndarray
    wrench: np.ndarray        # extra wrench (force, torque) on the balanced body at its centre
    contacts: tuple
    ik_joints: tuple | None   # joints IK may move; None: all


class _Fields:
    """One TOML table being read: typed getters that name `prefix.key` in their errors and
    remember which keys were read, so unknown (misspelt) keys are reported too."""

    def __init__(self, source, prefix, table):
        self.source, self.prefix, self.table, self.read = source, prefix, table, set()
        if not isinstance(table, dict):
            self.fail("", "must be a table")

    def fail(self, key, rule):
        field = f"{self.prefix}.{key}" if self.prefix and key else self.prefix or key
        raise ValueError(f"{self.source}: {field}: {rule}")

    def get(self, key, required=True, default=None):
        self.read.add(key)
        if key not in self.table:
            if required:
                self.fail(key, "missing (required)")
            return default
        return self.table[key]

    def string(self, key, choices=None, **kw):
        if key not in self.table:
            return self.get(key, **kw)
        value = self.get(key)
        if not isinstance(value, str):
            self.fail(key, f"must be a string, got {value!r}")
        if choices is not None and value not in choices:
            self.fail(key, f"must be one of {list(choices)}, got {value!r}")
        return value

    def number(self, key, minimum=None, positive=False, **kw):
        if key not in self.table:
            return self.get(key, **kw)
        value = self.get(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            self.fail(key, f"must be a finite number, got {value!r}")
        if positive and not value > 0:
            self.fail(key, f"must be > 0, got {value}")
        if minimum is not None and value < minimum:
            self.fail(key, f"must be >= {minimum}, got {value}")
        return float(value)

    def vector(self, key, n, nonzero=False, **kw):
        if key not in self.table:
            return self.get(key, **kw)
        value = self.get(key)
        if (not isinstance(value, list) or len(value) != n or
                not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                        and math.isfinite(x) for x in value)):
            self.fail(key, f"must be a list of {n} finite numbers, got {value!r}")
        v = np.array(value, dtype=float)
        if nonzero and not np.linalg.norm(v) > 1e-12:
            self.fail(key, "must have nonzero length")
        return v

    def done(self):
        unknown = sorted(set(self.table) - self.read)
        if unknown:
            self.fail(unknown[0], "unknown field (check its spelling against docs/robots.md)")


def read(path):
    """The ScenarioSpec of the TOML file at `path`."""
    path = pathlib.Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ValueError(f"{path}: cannot be read ({exc.strerror})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: TOML syntax: {exc}") from None
    return parse(data, str(path), name=path.stem)


def parse(data, source, name="scenario"):
    """The ScenarioSpec of a TOML document already read into `data` (a dict); `source` names it
    in error messages."""
    top = _Fields(source, "", data)
    description = top.string("description", required=False, default="")
    robot = _Fields(source, "robot", top.get("robot"))
    model = robot.string("model", choices=sorted(ROBOTS))
    robot.done()

    config = _Fields(source, "configuration", top.get("configuration", required=False, default={}))
    joints = config.get("joints", required=False, default={})
    joint_fields = _Fields(source, "configuration.joints", joints)
    joints = {key: joint_fields.number(key) for key in joints}
    base_position = config.vector("base_position", 3, required=False)
    base_rpy = config.vector("base_rpy", 3, required=False)
    config.done()

    obj = _object(_Fields(source, "object", top.get("object")))
    load = _Fields(source, "load", top.get("load", required=False, default={}))
    gravity = load.vector("gravity", 3, required=False, default=np.array([0.0, 0.0, -9.81]))
    wrench = load.vector("wrench", 6, required=False, default=np.zeros(6))
    load.done()

    raw = top.get("contact")
    if not isinstance(raw, list) or not raw:
        top.fail("contact", "must be one or more [[contact]] tables")
    contacts = tuple(_contact(_Fields(source, f"contact[{i}]", c), obj) for i, c in enumerate(raw))

    ik = _Fields(source, "ik", top.get("ik", required=False, default={}))
    ik_joints = ik.get("joints", required=False)
    if ik_joints is not None and (not isinstance(ik_joints, list) or not ik_joints or
                                  not all(isinstance(j, str) for j in ik_joints)):
        ik.fail("joints", f"must be a non-empty list of joint names, got {ik_joints!r}")
    ik.done()
    top.done()
    return ScenarioSpec(
        name=name, source=source, description=description, robot=model, joints=joints,
        base_position=base_position, base_rotation=None if base_rpy is None else rpy_matrix(base_rpy),
        object=obj, gravity=gravity, wrench=wrench, contacts=contacts,
        ik_joints=None if ik_joints is None else tuple(ik_joints))


def _object(f):
    shape = f.string("shape", choices=SHAPES)
    if shape == "terrain":
        f.done()
        return ObjectSpec(shape, np.zeros(3), np.eye(3))
    center = f.vector("center", 3)
    rpy = f.vector("rpy", 3, required=False, default=np.zeros(3))
    mass = f.number("mass", minimum=0.0)
    radius = vertices = None
    if shape == "sphere":
        radius = f.number("radius", positive=True)
    elif shape == "box":
        size = f.vector("size", 3)
        if not np.all(size > 0):
            f.fail("size", f"every side must be > 0, got {size.tolist()}")
        corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
        vertices = 0.5 * corners * size
    else:
        raw = f.get("vertices")
        if (not isinstance(raw, list) or len(raw) < 4 or not all(
                isinstance(v, list) and len(v) == 3 and all(
                    isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)
                    for x in v) for v in raw)):
            f.fail("vertices", "must be a list of at least four [x, y, z] points")
        vertices = np.array(raw, dtype=float)
        spread = np.linalg.svd(vertices - vertices.mean(axis=0), compute_uv=False)
        if not spread[-1] > 1e-9 * max(spread[0], 1e-300):
            f.fail("vertices", "must span a solid (they lie in a plane)")
    f.done()
    return ObjectSpec(shape, center, rpy_matrix(rpy), radius, vertices, mass)


def _contact(f, obj):
    frame = f.string("frame")
    kind = f.string("kind", choices=KINDS)
    mu = f.number("mu", minimum=0.0)
    mu_spin = 0.0
    if kind == "soft":
        mu_spin = f.number("mu_spin", positive=True)
        if mu == 0.0:
            f.fail("mu", "must be > 0 for a soft finger (torsional friction needs friction)")
    raw = f.get("normal")
    if isinstance(raw, str):
        if raw not in NORMAL_WORDS:
            f.fail("normal", f"must be [x, y, z] or one of {list(NORMAL_WORDS)}, got {raw!r}")
        if raw == "object" and obj.shape == "terrain":
            f.fail("normal", "'object' needs an object with a surface, not terrain")
        normal = raw
    else:
        normal = f.vector("normal", 3, nonzero=True)
        normal = normal / np.linalg.norm(normal)
    offset = f.vector("offset", 3, required=False, default=np.zeros(3))
    size = None
    if kind == "patch":
        size = f.vector("size", 2)
        if not np.all(size > 0):
            f.fail("size", f"both sides must be > 0, got {size.tolist()}")
        size = tuple(size)
    target = f.vector("target", 3, required=False)
    if target is not None and obj.shape == "terrain":
        f.fail("target", "IK targets lie on an object's surface; terrain has none")
    f.done()
    return ContactSpec(frame, kind, mu, mu_spin, normal, offset, size, target)


def rpy_matrix(rpy):
    """The rotation R = Rz(yaw) Ry(pitch) Rx(roll) of URDF's roll-pitch-yaw (radians)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])
