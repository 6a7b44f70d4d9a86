"""A Scenario: a robot model posed in a configuration, its contacts as a gf.Grasp, and the load
those contacts must hold.

The balanced body is the grasped object for a fixed-base robot (a hand, an arm) and the robot
itself for a floating-base one (it stands on terrain). The grasp's frame has the world's axes
and its origin at the reference point: the object's centre, or the robot's centre of mass in the
scenario's configuration, so that torques stay small next to forces.
"""
import numpy as np
import pinocchio as pin

from ..grasping.contact import Contact
from ..grasping.grasp import Grasp
from . import kinematics, models, shapes
from .scenario_file import FRAME_AXES
from .solution import joint_torques, RobotForces


class Scenario:
    """Built by graspforce.robots.load_scenario; see docs/robots.md."""

    def __init__(self, spec, model, q, contact_frames, contact_offsets, contact_specs):
        self.spec, self.model, self.q = spec, model, q
        self.data = model.createData()
        self.floating = models.is_floating(spec.robot)
        self.surface = shapes.surface(spec.object)
        # one entry per point contact (a patch is its four corners)
        self.contact_frames = contact_frames        # frame ids
        self.contact_offsets = contact_offsets      # (m, 3), in the frame
        self.contact_specs = contact_specs          # the ContactSpec each came from
        kinematics.place(model, self.data, q)
        self.points = np.array([self.data.oMf[f].act(o)
                                for f, o in zip(contact_frames, contact_offsets)])
        self.normals = np.array([self._normal(c, f, p) for c, f, p
                                 in zip(contact_specs, contact_frames, self.points)])
        if self.floating:
            self.mass = pin.computeTotalMass(model)
            self.reference = pin.centerOfMass(model, self.data, q).copy()
        else:
            self.mass = spec.object.mass
            self.reference = spec.object.center.copy()
        force = self.mass * spec.gravity
        self.external_wrench = spec.wrench + np.concatenate((force, np.zeros(3)))
        self.grasp = Grasp([Contact(p - self.reference, n, c.mu, c.mu_spin)
                            for p, n, c in zip(self.points, self.normals, contact_specs)])

    name = property(lambda self: self.spec.name)
    source = property(lambda self: self.spec.source)
    description = property(lambda self: self.spec.description)

    @property
    def contact_names(self):
        """A label per point contact: the frame's name, and the corner for a patch."""
        names, corner = [], {}
        for f, c in zip(self.contact_frames, self.contact_specs):
            name = self.model.frames[f].name
            if c.kind == "patch":
                corner[name] = corner.get(name, 0) + 1
                name = f"{name} corner {corner[name]}"
            names.append(name)
        return names

    def _normal(self, contact, frame_id, point):
        if isinstance(contact.normal, np.ndarray):
            return contact.normal
        if contact.normal == "object":
            return -self.surface.outward_normal(point)
        axis, sign = FRAME_AXES[contact.normal]
        return sign * self.data.oMf[frame_id].rotation[:, axis]

    def to_dict(self):
        """The scenario as JSON-ready values: its robot, configuration q, reference point, load
        and contacts (label, world point, normal, friction), what the service's
        GET /v1/robots/{name} sends."""
        return {"name": self.name, "description": self.description, "robot": self.spec.robot,
                "floating_base": bool(self.floating), "nq": int(self.model.nq),
                "nv": int(self.model.nv), "configuration": self.q.tolist(),
                "reference": self.reference.tolist(),
                "external_wrench": self.external_wrench.tolist(),
                "contacts": [{"name": name, "kind": c.kind, "point": p.tolist(),
                              "normal": n.tolist(), "mu": float(c.mu),
                              "mu_spin": float(c.mu_spin)}
                             for name, c, p, n in zip(self.contact_names, self.contact_specs,
                                                      self.points, self.normals)]}

    def with_configuration(self, q):
        """The same scenario at configuration q (no IK: the contacts follow their frames)."""
        q = np.array(q, dtype=float)
        if q.shape != (self.model.nq,) or not np.all(np.isfinite(q)):
            raise ValueError(f"q: must be {self.model.nq} finite numbers, got shape {q.shape}")
        return Scenario(self.spec, self.model, q, self.contact_frames, self.contact_offsets,
                        self.contact_specs)

    def solve(self, norm="L1", magnitude="normal", method="zc-ie", eps=1e-9, w_ext=None,
              v=None, a=None):
        """The minimal contact forces (Grasp.min_force) for the scenario's load, with their world
        forces and the joint torques that realize them: a RobotForces. w_ext replaces the load
        (a wrench about the reference point); for a floating base, a motion (v, a) at the
        scenario's q asks for the forces of centroidal_wrench(q, v, a), and the torques come
        from inverse dynamics of that motion."""
        moving = v is not None or a is not None
        if moving:
            v = np.zeros(self.model.nv) if v is None else np.asarray(v, dtype=float)
            a = np.zeros(self.model.nv) if a is None else np.asarray(a, dtype=float)
            if w_ext is not None:
                raise ValueError("w_ext: give either w_ext or a motion (v, a), not both")
            w_ext = self.centroidal_wrench(self.q, v, a)
        w = self.external_wrench if w_ext is None else np.asarray(w_ext, dtype=float)
        record = self.grasp.min_force(w, norm=norm, magnitude=magnitude, method=method, eps=eps)
        torques = joint_torques(self, record.wrenches, v, a)
        return RobotForces(self, record, torques)

    def centroidal_wrench(self, q, v, a):
        """The wrench about the reference point that the contacts must resist (the w_ext of
        min_force) for the robot to move with (q, v, a): its weight and the extra load, minus
        the rate of change of its centroidal momentum (pinocchio.
        computeCentroidalMomentumTimeVariation). With v = a = 0 it is the static load."""
        if not self.floating:
            raise ValueError("centroidal_wrench: defined for a floating-base robot; a hand "
                             "balances its object, not its own momentum")
        q, v, a = (np.asarray(x, dtype=float) for x in (q, v, a))
        for name, x, n in (("q", q, self.model.nq), ("v", v, self.model.nv),
                           ("a", a, self.model.nv)):
            if x.shape != (n,) or not np.all(np.isfinite(x)):
                raise ValueError(f"{name}: must be {n} finite numbers, got shape {x.shape}")
        dh = pin.computeCentroidalMomentumTimeVariation(self.model, self.data, q, v, a)
        com = self.data.com[0]
        # dh is about the centre of mass; move its moment to the reference point
        rate = np.concatenate((dh.linear, dh.angular + np.cross(com - self.reference, dh.linear)))
        weight = self.mass * self.spec.gravity
        gravity = np.concatenate((weight, np.cross(com - self.reference, weight)))
        return gravity + self.spec.wrench - rate

    def plot(self, path, forces=None):
        """Draw the scenario to the PNG file `path` (graspforce.robots.plot.draw)."""
        from .plot import draw
        return draw(self, path, self.solve() if forces is None else forces)

    def __repr__(self):
        return (f"Scenario({self.name!r}: {self.spec.robot}, {len(self.points)} contacts, "
                f"load {np.round(self.external_wrench, 3).tolist()})")
