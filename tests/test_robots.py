"""graspforce.robots: the shipped scenarios load and pose their contacts on the model's frames,
IK puts fingertips on their objects, the forces obey physics anyone can check and agree with
Clarabel's SOCP, inverse dynamics closes, and bad scenario files are refused with the file, the
field and the rule named."""
import importlib.metadata
import math
import pathlib
import subprocess
import sys
import tomllib

import numpy as np
import pytest

pin = pytest.importorskip("pinocchio")
try:
    importlib.metadata.distribution("example-robot-data")
except importlib.metadata.PackageNotFoundError:
    pytest.skip("needs example-robot-data (the robots extra)", allow_module_level=True)

import graspforce as gf  # noqa: E402
from graspforce.grasping.baselines import clarabel_socp  # noqa: E402
from graspforce.robots import scenario_file  # noqa: E402

SCENARIOS = gf.robots.list_scenarios()
SHIPPED = ("allegro_ingot", "allegro_sphere", "go1_uneven_terrain", "panda_pinch_box",
           "talos_double_support", "talos_hand_on_wall")


@pytest.fixture(scope="module")
def loaded():
    return {name: gf.robots.load_scenario(name) for name in SCENARIOS}


@pytest.fixture(scope="module")
def solved(loaded):
    return {name: s.solve() for name, s in loaded.items()}


def from_dict(name, edit):
    """A shipped scenario's file, read as a dict, changed by `edit`, then built."""
    path = gf.robots.scenario_path(name)
    data = tomllib.loads(path.read_text())
    edit(data)
    return gf.robots.build(scenario_file.parse(data, f"{name} (edited)"))


def test_every_scenario_is_shipped_and_the_top_level_folder_holds_them():
    assert set(SHIPPED) <= set(SCENARIOS)
    top = pathlib.Path(__file__).parent.parent / "robots"
    assert sorted(p.stem for p in top.glob("*.toml")) == SCENARIOS


@pytest.mark.parametrize("name", SCENARIOS)
def test_contacts_sit_on_the_model_frames(loaded, name):
    s = loaded[name]
    model = s.model
    data = model.createData()
    pin.forwardKinematics(model, data, s.q)
    pin.updateFramePlacements(model, data)
    for contact, frame_id, offset, point in zip(s.grasp.contacts, s.contact_frames,
                                                s.contact_offsets, s.points):
        expected = data.oMf[frame_id].act(offset)
        assert np.abs(point - expected).max() <= 1e-12
        assert np.abs(contact.position + s.reference - expected).max() <= 1e-12
    assert len(s.grasp.contacts) == len(s.points) <= 9


def _surface_distance(obj, p):
    """Signed distance to the object's surface, computed here from the file's data."""
    if obj.shape == "sphere":
        return np.linalg.norm(p - obj.center) - obj.radius
    from scipy.spatial import ConvexHull
    hull = ConvexHull(obj.center + obj.vertices @ obj.rotation.T)
    return np.max(hull.equations[:, :3] @ p + hull.equations[:, 3])


@pytest.mark.parametrize("name", [n for n in SCENARIOS if n.startswith(("allegro", "panda"))])
def test_ik_puts_fingertips_on_the_object(loaded, name):
    s = loaded[name]
    targeted = [p for p, c in zip(s.points, s.contact_specs) if c.target is not None]
    assert targeted
    for p in targeted:
        assert abs(_surface_distance(s.spec.object, p)) <= 1e-6
    # and the configuration respects the joint limits
    assert np.all(s.q >= s.model.lowerPositionLimit - 1e-12)
    assert np.all(s.q <= s.model.upperPositionLimit + 1e-12)


@pytest.mark.parametrize("name", SCENARIOS)
def test_forces_are_feasible_in_their_cones_and_balance_the_load(loaded, solved, name):
    s, answer = loaded[name], solved[name]
    r = answer.record
    assert r.status == "optimal"
    w = s.external_wrench
    assert np.linalg.norm(r.resultant + w) <= 1e-9 * np.linalg.norm(w)
    # 1e-9 of the largest normal force: an unused contact's f_1 ~ 0 has no scale of its own
    scale = r.forces[:, 0].max()
    for c, f in zip(s.grasp.contacts, r.forces):
        assert c.contains(f / scale, tol=1e-9)
    assert np.allclose(answer.forces, r.world_forces)
    assert answer.torques.shape == (s.model.nv,)


@pytest.mark.parametrize("name", SCENARIOS)
@pytest.mark.parametrize("norm", ["L1", "Linf"])
def test_agrees_with_clarabel_socp(loaded, name, norm):
    s = loaded[name]
    ours = s.solve(norm=norm)
    ref = clarabel_socp.min_force(s.grasp, s.external_wrench, norm=norm, tight=True)
    assert ref.status == "optimal"
    assert abs(ours.record.sigma - ref.sigma) <= 1e-6 * ref.sigma


def test_talos_normal_forces_add_up_to_its_weight(loaded, solved):
    s, answer = loaded["talos_double_support"], solved["talos_double_support"]
    weight = s.mass * 9.81
    assert math.isclose(pin.computeTotalMass(s.model), s.mass)
    assert abs(answer.record.forces[:, 0].sum() - weight) <= 1e-9 * weight
    assert abs(answer.forces[:, 2].sum() - weight) <= 1e-9 * weight


@pytest.mark.parametrize("name", ["talos_double_support", "go1_uneven_terrain"])
def test_standing_is_feasible_at_mu_06_and_not_on_a_60_degree_slope_at_mu_03(name):
    def flat(data):
        for c in data["contact"]:
            c["mu"], c["normal"] = 0.6, [0.0, 0.0, 1.0]

    def slope(data):
        for c in data["contact"]:
            c["mu"] = 0.3
            c["normal"] = [math.sin(math.radians(60)), 0.0, math.cos(math.radians(60))]

    assert from_dict(name, flat).solve().record.status == "optimal"
    steep = from_dict(name, slope)
    assert steep.solve().record.status == "infeasible"
    assert clarabel_socp.min_force(steep.grasp, steep.external_wrench).status == "infeasible"


@pytest.mark.parametrize("name", [n for n in SCENARIOS if n.startswith(("talos", "go1"))])
def test_free_flyer_entries_of_inverse_dynamics_vanish(loaded, solved, name):
    assert np.abs(solved[name].torques[:6]).max() <= 1e-8
    assert loaded[name].floating


def test_a_motion_needs_its_centroidal_wrench_and_inverse_dynamics_closes(loaded):
    s = loaded["talos_double_support"]
    assert np.allclose(s.centroidal_wrench(s.q, np.zeros(s.model.nv), np.zeros(s.model.nv)),
                       s.external_wrench, atol=1e-9)
    rng = np.random.default_rng(1)
    v, a = 0.2 * rng.standard_normal(s.model.nv), 0.5 * rng.standard_normal(s.model.nv)
    answer = s.solve(v=v, a=a)
    assert answer.record.status == "optimal"
    assert np.abs(answer.torques[:6]).max() <= 1e-8
    assert not np.allclose(s.centroidal_wrench(s.q, v, a), s.external_wrench)


def test_hand_torques_are_the_jacobian_transpose_of_the_contact_wrenches(loaded, solved):
    s, answer = loaded["allegro_sphere"], solved["allegro_sphere"]
    data = s.model.createData()
    pin.computeJointJacobians(s.model, data, s.q)
    pin.updateFramePlacements(s.model, data)
    tau = np.zeros(s.model.nv)
    for frame_id, p, f in zip(s.contact_frames, s.points, answer.record.wrenches):
        J = pin.computeFrameJacobian(s.model, data, s.q, frame_id, pin.LOCAL_WORLD_ALIGNED)
        # the wrench about the frame's origin: the torque about the reference point moved there
        moment = f[3:] + np.cross(s.reference - data.oMf[frame_id].translation, f[:3])
        tau += J.T @ np.concatenate((f[:3], moment))
    assert np.allclose(answer.torques, tau, atol=1e-12)
    assert answer.exceeded == []


def test_effort_limits_are_flagged():
    heavy = from_dict("panda_pinch_box", lambda d: d["object"].update(mass=60.0))
    answer = heavy.solve()
    assert answer.record.status == "optimal"
    assert "panda_finger_joint1" in answer.exceeded and "panda_joint1" not in answer.exceeded


def test_with_configuration_re_poses_the_contacts(loaded):
    s = loaded["go1_uneven_terrain"]
    q = s.q.copy()
    q[2] += 0.05
    moved = s.with_configuration(q)
    assert np.allclose(moved.points - s.points, [0.0, 0.0, 0.05], atol=1e-12)
    assert moved.solve().record.status == "optimal"
    with pytest.raises(ValueError, match="q:"):
        s.with_configuration(q[:-1])


def test_plot_writes_a_png(loaded, tmp_path):
    for name in ("allegro_ingot", "talos_hand_on_wall"):
        path = loaded[name].plot(tmp_path / f"{name}.png")
        assert pathlib.Path(path).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_importing_graspforce_does_not_import_pinocchio():
    code = ("import sys, graspforce as gf; assert 'pinocchio' not in sys.modules; "
            "print(gf.robots.list_scenarios()[0]); assert 'pinocchio' in sys.modules")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == SCENARIOS[0]


GOOD = gf.robots.scenario_path("talos_double_support").read_text()


@pytest.mark.parametrize("text, field, rule", [
    (GOOD.replace('model = "talos"', 'model = "talos_mk2"'), "robot.model", "must be one of"),
    (GOOD.replace('frame = "left_sole_link"', 'frame = "left_foot"'), "contact[0].frame",
     "no frame 'left_foot'"),
    (GOOD.replace('kind = "patch"                  #', '#'), "contact[0].kind", "missing"),
    (GOOD.replace("mu = 0.6", "mu = -0.6", 1), "contact[0].mu", "must be >= 0"),
    (GOOD.replace("normal = [0.0, 0.0, 1.0]        #", "normal = [0.0, 0.0, 0.0] #"),
     "contact[0].normal", "nonzero length"),
    (GOOD.replace("[robot]", "[robot"), "TOML syntax", "Expected ']'"),
    (GOOD.replace("size = [0.20, 0.13]", "sise = [0.20, 0.13]", 1), "contact[0].size",
     "missing"),
    (GOOD.replace("leg_left_3_joint", "leg_left_9_joint"), "configuration.joints.leg_left_9_joint",
     "no such joint"),
])
def test_bad_scenario_files_name_the_file_the_field_and_the_rule(tmp_path, text, field, rule):
    assert text != GOOD
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ValueError) as info:
        gf.robots.load_scenario(path)
    message = str(info.value)
    assert message.startswith(f"{path}: ")
    assert field in message and rule in message
    # nothing half-loaded: the shipped scenario still loads and answers as before
    again = gf.robots.load_scenario("talos_double_support")
    assert again.solve().record.status == "optimal"


def test_unknown_fields_and_names_are_refused(tmp_path):
    path = tmp_path / "typo.toml"
    path.write_text(GOOD.replace("[load]", "[load]\ngravitty = 1.0"))
    with pytest.raises(ValueError, match=r"load\.gravitty: unknown field"):
        gf.robots.load_scenario(path)
    with pytest.raises(ValueError, match="neither a shipped scenario"):
        gf.robots.load_scenario("no_such_scenario")
    with pytest.raises(TypeError, match="name_or_path"):
        gf.robots.load_scenario(3)
