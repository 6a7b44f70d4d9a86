"""Robot models from example-robot-data, loaded with Pinocchio's URDF parser.

example-robot-data 6 ships its URDFs and meshes inside the wheel, under
`cmeel.prefix/share/example-robot-data/robots/` of site-packages, with no Python loader: the
folder is found through the installed distribution's metadata, so any install layout (venv,
user site, system) works without a hard-coded path.
"""
import functools
import importlib.metadata
import pathlib

# name -> (URDF path under the robots folder, floating base). A floating base is a free-flyer
# root joint: the robot stands on its contacts instead of being bolted to the world.
ROBOTS = {
    "allegro_right_hand": ("allegro_hand_description/urdf/allegro_right_hand.urdf", False),
    "allegro_left_hand": ("allegro_hand_description/urdf/allegro_left_hand.urdf", False),
    "panda": ("panda_description/urdf/panda.urdf", False),
    "talos": ("talos_data/robots/talos_reduced.urdf", True),
    "talos_full": ("talos_data/robots/talos_full_v2.urdf", True),
    "go1": ("go1_description/urdf/go1.urdf", True),
    "anymal_b": ("anymal_b_simple_description/robots/anymal.urdf", True),
    "solo12": ("solo_description/robots/solo12.urdf", True),
}


@functools.cache
def robots_folder():
    """The `robots/` folder of the installed example-robot-data distribution."""
    try:
        dist = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        raise ImportError("graspforce.robots needs example-robot-data: "
                          "pip install 'graspforce[robots]'") from None
    folder = pathlib.Path(dist.locate_file("cmeel.prefix/share/example-robot-data/robots"))
    if not folder.is_dir():
        raise ImportError(f"example-robot-data {dist.version}: no robots folder at {folder}")
    return folder


def urdf_path(name):
    """The URDF file of robot `name` (one of ROBOTS)."""
    if name not in ROBOTS:
        raise ValueError(f"robot.model: must be one of {sorted(ROBOTS)}, got {name!r}")
    return robots_folder() / ROBOTS[name][0]


def is_floating(name):
    """Whether robot `name` stands on its contacts (a free-flyer root) or is fixed to the world."""
    urdf_path(name)
    return ROBOTS[name][1]


@functools.cache
def _load(name):
    import pinocchio as pin
    path = str(urdf_path(name))
    if ROBOTS[name][1]:
        return pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
    return pin.buildModelFromUrdf(path)


def load_model(name):
    """A fresh copy of robot `name`'s pinocchio.Model (the parsed URDF is cached: a copy costs
    microseconds, parsing a humanoid milliseconds), so a caller may change its gravity."""
    import pinocchio as pin
    return pin.Model(_load(name))
