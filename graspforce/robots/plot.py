"""A picture of a scenario: the robot's kinematic skeleton, the object or terrain, each contact's
friction cone, and the optimal contact forces as arrows (matplotlib, Agg backend, PNG)."""
import numpy as np

from .kinematics import place


def draw(scenario, path, answer):
    """Write the PNG of `scenario` with the forces of `answer` (a RobotForces) to `path`;
    returns the path."""
    import matplotlib
    matplotlib.use("Agg")     # files only: no display is needed or opened
    import matplotlib.pyplot as plt

    model, data = scenario.model, scenario.data
    place(model, data, scenario.q)
    fig = plt.figure(figsize=(7, 7))
    ax = fig.add_subplot(projection="3d")

    # skeleton: a segment from each joint to its parent, and from a contact's joint to the contact
    origins = np.array([M.translation for M in data.oMi])
    for j in range(2, model.njoints):
        parent = model.parents[j]
        if parent > 0 or not scenario.floating:
            ax.plot(*origins[[parent, j]].T, color="0.3", lw=1.5)
    ax.scatter(*origins[1:].T, color="0.2", s=6)
    for frame_id, p in zip(scenario.contact_frames, scenario.points):
        joint = model.frames[frame_id].parentJoint
        ax.plot(*np.array([origins[joint], p]).T, color="0.5", lw=1.0)

    scale = _length_scale(scenario)
    if scenario.surface is not None:
        for line in scenario.surface.edges():
            ax.plot(*line.T, color="tab:blue", lw=0.8)
    else:
        for p, n in zip(scenario.points, scenario.normals):
            ax.plot(*_square(p, n, 0.6 * scale).T, color="tab:brown", lw=0.8)

    cone_length = 0.5 * scale
    for c, p in zip(scenario.grasp.contacts, scenario.points):
        for line in _cone(p, c, cone_length):
            ax.plot(*line.T, color="tab:green", lw=0.6, alpha=0.7)

    forces = answer.forces
    largest = np.max(np.linalg.norm(forces, axis=1)) if answer.record.feasible else 0.0
    if largest > 0:
        arrows = forces * (1.5 * scale / largest)
        ax.quiver(*scenario.points.T, *arrows.T, color="tab:red", lw=1.5,
                  arrow_length_ratio=0.2)

    _equal_axes(ax, np.vstack((origins[1:], scenario.points)))
    ax.set_xlabel("x (m)"), ax.set_ylabel("y (m)"), ax.set_zlabel("z (m)")
    status = (f"sigma = {answer.record.sigma:.4g} N" if answer.record.feasible
              else answer.record.status)
    ax.set_title(f"{scenario.name}: {len(scenario.points)} contacts, {status}\n"
                 f"red: optimal forces (largest {largest:.3g} N), green: friction cones",
                 fontsize=9)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _length_scale(scenario):
    """A drawing length for cones and arrows: a fraction of the contacts' spread."""
    spread = np.ptp(scenario.points, axis=0).max() if len(scenario.points) > 1 else 0.0
    return max(0.15 * spread, 0.01)


def _cone(p, contact, length, k=12):
    """Generator lines and the rim of the friction cone at p, pointing along the force."""
    o, t = contact.tangents
    a = np.linspace(0.0, 2.0 * np.pi, k, endpoint=False)
    rim = p + length * (contact.normal + contact.mu * (np.outer(np.cos(a), o)
                                                       + np.outer(np.sin(a), t)))
    lines = [np.array([p, r]) for r in rim]
    return lines + [np.vstack((rim, rim[:1]))]


def _square(p, n, half):
    """A square of half-side `half` through p, normal to n: a patch of terrain."""
    o = np.cross(n, [1.0, 0.0, 0.0])
    if np.linalg.norm(o) < 0.1:
        o = np.cross(n, [0.0, 1.0, 0.0])
    o /= np.linalg.norm(o)
    t = np.cross(n, o)
    corners = [p + half * (sx * o + sy * t) for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1), (1, 1))]
    return np.array(corners)


def _equal_axes(ax, points):
    centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
    radius = 0.55 * np.ptp(points, axis=0).max()
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
        setter(c - radius, c + radius)
