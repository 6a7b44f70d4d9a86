"""Joint torques that realize contact forces, and the record of a scenario's solve.

The contact wrenches of a MinForce act on the balanced body. A fixed-base robot applies them to
its object, so its motors supply tau = sum_i J_i^T w_i (frame Jacobians in LOCAL_WORLD_ALIGNED,
each wrench taken about its frame's origin); the links' own weight is left out, as it depends on
how the hand is mounted, not on the grasp (pinocchio.computeGeneralizedGravity adds it). A
floating-base robot receives them from the terrain, so its torques are inverse dynamics with the
contact wrenches as external forces (pinocchio.rnea with fext): the six free-flyer entries are
the base wrench nothing actuates, and vanish exactly when the forces balance the load.
"""
import dataclasses

import numpy as np
import pinocchio as pin

from ..records.results import MinForce


def joint_torques(scenario, wrenches, v=None, a=None):
    """(nv,) joint torques for contact wrenches (m, 6) about the scenario's reference point."""
    model, data, q = scenario.model, scenario.data, scenario.q
    forces = np.asarray(wrenches)[:, :3]
    # moments about the world origin, the frame pin.Force uses for world quantities
    moments = np.asarray(wrenches)[:, 3:] + np.cross(scenario.reference, forces)
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    if not scenario.floating:
        tau = np.zeros(model.nv)
        for frame_id, f, n in zip(scenario.contact_frames, forces, moments):
            origin = data.oMf[frame_id].translation
            J = pin.getFrameJacobian(model, data, frame_id, pin.LOCAL_WORLD_ALIGNED)
            tau += J.T @ np.concatenate((f, n - np.cross(origin, f)))
        return tau
    local = [pin.Force.Zero() for _ in range(model.njoints)]
    for frame_id, f, n in zip(scenario.contact_frames, forces, moments):
        joint = model.frames[frame_id].parentJoint
        local[joint] = local[joint] + data.oMi[joint].actInv(pin.Force(f, n))
    # the extra load acts on the base at the reference point
    w = scenario.spec.wrench
    local[1] = local[1] + data.oMi[1].actInv(
        pin.Force(w[:3], w[3:] + np.cross(scenario.reference, w[:3])))
    fext = pin.StdVec_Force()
    for force in local:
        fext.append(force)
    v = np.zeros(model.nv) if v is None else v
    a = np.zeros(model.nv) if a is None else a
    return pin.rnea(model, data, q, v, a, fext).copy()


@dataclasses.dataclass(frozen=True)
class RobotForces:
    """Scenario.solve's answer. record: the gf.MinForce; forces (m, 3): each contact's force on
    the balanced body, world frame; points (m, 3): where they act; torques (nv,): the joint
    torques (entries in the order of the model's velocity vector; the first six of a floating
    base are the unactuated base wrench); effort_limit (nv,) from the URDF (inf where none);
    over_limit (nv,) bool: |torque| > limit."""
    scenario: object = dataclasses.field(repr=False)
    record: MinForce
    torques: np.ndarray

    @property
    def status(self):
        return self.record.status

    def to_dict(self):
        """JSON-ready values: the MinForce record (MinForce.to_dict), world forces and points,
        joint torques, effort limits (None where there is none) and the joints over them."""
        limit = self.effort_limit
        return {"status": self.status, "record": self.record.to_dict(),
                "forces": self.forces.tolist(), "points": self.points.tolist(),
                "torques": self.torques.tolist(),
                "effort_limit": [float(x) if np.isfinite(x) else None for x in limit],
                "over_limit": self.over_limit.tolist(), "exceeded": list(self.exceeded)}

    @property
    def forces(self):
        return self.record.world_forces

    @property
    def points(self):
        return self.scenario.points

    @property
    def effort_limit(self):
        model = self.scenario.model
        limit = np.array(model.effortLimit, dtype=float)
        limit[limit <= 0] = np.inf
        if self.scenario.floating:
            limit[:6] = np.inf
        return limit

    @property
    def over_limit(self):
        return np.abs(self.torques) > self.effort_limit

    @property
    def exceeded(self):
        """Names of the joints whose torque exceeds its effort limit."""
        return [name for name, over in zip(velocity_names(self.scenario.model), self.over_limit)
                if over]


def velocity_names(model):
    """The joint name of each entry of the velocity vector (a free flyer's six share one)."""
    names = []
    for joint, name in zip(model.joints[1:], model.names[1:]):
        names += [name] * joint.nv
    return names
