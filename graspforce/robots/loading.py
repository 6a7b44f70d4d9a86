"""Finding and loading scenario files: the checked file becomes a posed Scenario.

The shipped files live in this package (graspforce/robots/scenarios/), so the same code finds
them in a source checkout and in an installed wheel; the repository's top-level robots/ folder
is a link to it, for users browsing the sources.
"""
import pathlib

import numpy as np
import pinocchio as pin

from . import kinematics, models, scenario_file, shapes
from .scenario import Scenario

SCENARIOS = pathlib.Path(__file__).parent / "scenarios"


def list_scenarios():
    """The names of the shipped scenarios (the stems of scenarios/*.toml), sorted."""
    return sorted(p.stem for p in SCENARIOS.glob("*.toml"))


def scenario_path(name_or_path):
    """The file of a shipped scenario's name, or the path given."""
    if not isinstance(name_or_path, (str, pathlib.PurePath)):
        raise TypeError(f"name_or_path: expected a scenario name or a path, got "
                        f"{type(name_or_path).__name__}")
    shipped = SCENARIOS / f"{name_or_path}.toml"
    if isinstance(name_or_path, str) and "/" not in name_or_path and shipped.is_file():
        return shipped
    path = pathlib.Path(name_or_path)
    if not path.is_file():
        raise ValueError(f"{name_or_path}: neither a shipped scenario {list_scenarios()} "
                         f"nor a file")
    return path


def load_scenario(name_or_path):
    """The Scenario of a shipped scenario's name or of a TOML file's path. A bad file raises
    ValueError "<file>: <field>: <rule>" and nothing is kept."""
    return build(scenario_file.read(scenario_path(name_or_path)))


def build(spec):
    """The posed Scenario of a ScenarioSpec: its model, configuration, contacts and IK."""
    def fail(field, rule):
        raise ValueError(f"{spec.source}: {field}: {rule}")

    model = models.load_model(spec.robot)
    model.gravity = pin.Motion(spec.gravity, np.zeros(3))
    floating = models.is_floating(spec.robot)
    if floating and spec.object.shape != "terrain":
        fail("object.shape", "a floating-base robot balances itself on terrain: must be 'terrain'")
    if not floating and spec.object.shape == "terrain":
        fail("object.shape", f"{spec.robot} is fixed to the world and holds an object: "
                             f"must be one of ['sphere', 'box', 'polyhedron']")
    if not floating and (spec.base_position is not None or spec.base_rotation is not None):
        fail("configuration.base_position", f"{spec.robot} has no floating base")

    q = pin.neutral(model)
    for name, value in spec.joints.items():
        if not model.existJointName(name) or name == "root_joint":
            fail(f"configuration.joints.{name}", f"no such joint in {spec.robot}")
        joint = model.joints[model.getJointId(name)]
        if joint.nq != 1:
            fail(f"configuration.joints.{name}", "only one-degree-of-freedom joints are set by name")
        lo, hi = model.lowerPositionLimit[joint.idx_q], model.upperPositionLimit[joint.idx_q]
        if not lo - 1e-12 <= value <= hi + 1e-12:
            fail(f"configuration.joints.{name}", f"must lie within the joint's limits "
                                                 f"[{lo:g}, {hi:g}], got {value:g}")
        q[joint.idx_q] = value
    if floating:
        q[:3] = np.zeros(3) if spec.base_position is None else spec.base_position
        rotation = np.eye(3) if spec.base_rotation is None else spec.base_rotation
        q[3:7] = pin.Quaternion(rotation).coeffs()

    frames, offsets, specs = [], [], []
    for i, c in enumerate(spec.contacts):
        if not model.existFrame(c.frame):
            fail(f"contact[{i}].frame", f"no frame {c.frame!r} in {spec.robot}")
        frame_id = model.getFrameId(c.frame)
        corners = [c.offset]
        if c.kind == "patch":
            hx, hy = 0.5 * np.array(c.size)
            corners = [c.offset + np.array([sx * hx, sy * hy, 0.0])
                       for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
        for offset in corners:
            frames.append(frame_id)
            offsets.append(offset)
            specs.append(c)

    q = _reach(spec, model, q, frames, offsets, specs, fail)
    return Scenario(spec, model, q, frames, np.array(offsets), specs)


def _reach(spec, model, q, frames, offsets, specs, fail):
    """q after IK puts every contact with a target on the object's surface."""
    placed = [(f, o, c.target) for f, o, c in zip(frames, offsets, specs) if c.target is not None]
    if not placed:
        return q
    movable = np.ones(model.nv, dtype=bool)
    if spec.ik_joints is not None:
        movable[:] = False
        for name in spec.ik_joints:
            if not model.existJointName(name):
                fail("ik.joints", f"no joint {name!r} in {spec.robot}")
            joint = model.joints[model.getJointId(name)]
            movable[joint.idx_v:joint.idx_v + joint.nv] = True
    surface = shapes.surface(spec.object)
    q, miss = kinematics.reach_surface(model, model.createData(), q, placed, surface, movable)
    if miss > 1e-9:
        fail("contact.target", f"IK leaves a contact {miss:.3g} m off the object's surface "
                               f"(targets out of reach or joint limits): move the targets")
    return q
