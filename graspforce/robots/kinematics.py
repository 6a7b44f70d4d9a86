"""Where the contacts are, and the joint configuration that puts fingertips on an object.

Placements come from pinocchio.forwardKinematics and updateFramePlacements; velocities of a
contact point from the frame Jacobian in LOCAL_WORLD_ALIGNED (the frame's origin, world axes).
"""
import numpy as np
import pinocchio as pin


def place(model, data, q):
    """Forward kinematics of q into data: joint and frame placements."""
    pin.forwardKinematics(model, data, q)
    pin.updateFramePlacements(model, data)


def point_jacobian(model, data, frame_id, point):
    """(3, nv) Jacobian of the world point `point` riding on frame `frame_id`, after
    computeJointJacobians: v_p = v_o + w x (p - o)."""
    J = pin.getFrameJacobian(model, data, frame_id, pin.LOCAL_WORLD_ALIGNED)
    r = point - data.oMf[frame_id].translation
    return J[:3] - _skew(r) @ J[3:]


def _skew(r):
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def reach_surface(model, data, q, points, surface, movable, damping=1e-4, tol=1e-10,
                  max_iter=200):
    """A configuration near q that puts every contact point on `surface`.

    points: list of (frame_id, offset in the frame, target in the world). movable: boolean mask
    over the velocity entries IK may change. Two damped least-squares passes: first toward the
    targets (a reachable neighbourhood of where the user wants the fingertips), then onto the
    surface, where only the signed distances must vanish: one equation per contact leaves the
    fingertips free to slide, so an approximate target is enough. Joint limits are kept by
    clamping. Returns (q, the largest |signed distance|)."""
    lower, upper = model.lowerPositionLimit, model.upperPositionLimit

    def step(q, residual_and_jacobian):
        r, J = residual_and_jacobian(q)
        J = J[:, movable]
        dv = np.zeros(model.nv)
        dv[movable] = -J.T @ np.linalg.solve(J @ J.T + damping * np.eye(len(r)), r)
        return np.clip(pin.integrate(model, q, dv), lower, upper), r

    def to_targets(q):
        place(model, data, q)
        pin.computeJointJacobians(model, data, q)
        r, J = [], []
        for frame_id, offset, target in points:
            p = data.oMf[frame_id].act(offset)
            r.append(p - target)
            J.append(point_jacobian(model, data, frame_id, p))
        return np.concatenate(r), np.vstack(J)

    def to_surface(q):
        place(model, data, q)
        pin.computeJointJacobians(model, data, q)
        r, J = [], []
        for frame_id, offset, _ in points:
            p = data.oMf[frame_id].act(offset)
            r.append(surface.signed_distance(p))
            J.append(surface.outward_normal(p) @ point_jacobian(model, data, frame_id, p))
        return np.array(r), np.array(J)

    for _ in range(max_iter):
        q_next, r = step(q, to_targets)
        if np.max(np.abs(q_next - q)) < 1e-9:
            break
        q = q_next
    r = np.array([np.inf])
    for _ in range(max_iter):
        r, _J = to_surface(q)
        if np.max(np.abs(r)) <= tol:
            break
        q, r = step(q, to_surface)
    r, _J = to_surface(q)
    return q, float(np.max(np.abs(r)))
