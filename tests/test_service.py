"""The service (server/) against a real uvicorn process on a loopback port (conftest `served`):
every endpoint through graspforce.client.Client agrees with the library to 1e-12; malformed
requests are refused with 422 or 413 naming the field and the rule; 64 concurrent clients each
get their own answer; the CLI's exit codes; /docs renders in headless Chromium."""
import json
import math
import os
import shutil
import subprocess
import sys
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import graspforce as gf
from graspforce.batch.wrenches import gaussian
from graspforce.demo import box_grasp

httpx = pytest.importorskip("httpx")
pytest.importorskip("fastapi")

from graspforce.client import Client  # noqa: E402

TOL = 1e-12
RESULTS = os.path.join(os.path.dirname(__file__), "..", "benchmarks", "results")


def assert_close(a, b, path="record"):
    """Equal structure; floats within TOL relative to max(1, |b|); None (an infinite number)
    only where the other is None."""
    if isinstance(b, dict):
        assert isinstance(a, dict) and set(a) == set(b), f"{path}: keys {set(a) ^ set(b)}"
        for k in b:
            assert_close(a[k], b[k], f"{path}.{k}")
    elif isinstance(b, (list, tuple)):
        assert isinstance(a, (list, tuple)) and len(a) == len(b), f"{path}: lengths differ"
        for i, (x, y) in enumerate(zip(a, b)):
            assert_close(x, y, f"{path}[{i}]")
    elif isinstance(b, float) and not isinstance(b, bool):
        assert isinstance(a, (int, float)), f"{path}: {a!r} vs {b!r}"
        assert abs(a - b) <= TOL * max(1.0, abs(b)), f"{path}: {a!r} vs {b!r}"
    else:
        assert a == b, f"{path}: {a!r} vs {b!r}"


@pytest.fixture(scope="module")
def client(served):
    with Client(served, timeout=30.0) as c:
        yield c


def three_fingers():
    return gf.Grasp([gf.Contact([0.04, 0.0, 0.0], [-1, 0, 0], 0.6),
                     gf.Contact([-0.02, 0.035, 0.0], [0.5, -0.866, 0.1], 0.6),
                     gf.Contact([-0.02, -0.035, 0.0], [0.5, 0.866, -0.1], 0.6, 0.005)])


WRENCHES = [np.array([0, 0, -9.81, 0, 0, 0]), np.array([1.0, -2.0, 3.0, 0.05, -0.02, 0.01]),
            np.array([0, 0, 0, 0, 0, 0.0])]


# -- every endpoint agrees with the library --------------------------------------------------------
@pytest.mark.parametrize("norm,magnitude,method", [
    ("L1", "normal", "zc-ie"), ("Linf", "normal", "ie"), ("L1", "full", "gjk"),
    ("Linf", "full", "zc-ie-newton"), ("L1", "normal", "bi-gjk"), ("L1", "normal", "zc")])
def test_min_force_agrees(client, norm, magnitude, method):
    for grasp in (box_grasp(), three_fingers()):
        for w in WRENCHES:
            # the service answers as a grasp's first call (Grasp.reset_start_tables)
            grasp.reset_start_tables()
            local = grasp.min_force(w, norm=norm, magnitude=magnitude, method=method, eps=1e-10)
            remote = client.min_force(grasp, w, norm=norm, magnitude=magnitude, method=method,
                                      eps=1e-10)
            assert isinstance(remote, gf.MinForce)
            assert_close(remote.to_dict(), local.to_dict())


def test_a_given_length_travels_with_the_grasp(client):
    """A grasp's characteristic length (gf.Grasp(contacts, length=...)) is part of its JSON
    form: the service answers in the same units, hence with the same record, for a length the
    grasp would not derive itself as for its own."""
    contacts = three_fingers().contacts
    for length in (1.0, 0.01, None):
        grasp = gf.Grasp(contacts, length=length)
        for w in WRENCHES[:2]:
            for norm in ("L1", "Linf"):
                local = grasp.min_force(w, norm=norm, eps=1e-10)
                remote = client.min_force(grasp, w, norm=norm, eps=1e-10)
                assert_close(remote.to_dict(), local.to_dict())
                grasp.reset_start_tables()


def test_infeasible_is_a_200_with_null_sigma(client, served):
    grasp = gf.Grasp([gf.Contact([0.05, 0, 0], [-1, 0, 0], 0.5)])     # can only push along -x
    w = np.array([-1.0, 0, 0, 0, 0, 0])                                # needs a pull
    local = grasp.min_force(w)
    remote = client.min_force(grasp, w)
    assert local.status == remote.status == "infeasible" and math.isinf(remote.sigma)
    r = httpx.post(served + "/v1/force-optimization", json={
        "contacts": [{"position": [0.05, 0, 0], "normal": [-1, 0, 0], "mu": 0.5}],
        "w_ext": [-1, 0, 0, 0, 0, 0]})
    assert r.status_code == 200 and r.json()["sigma"] is None


def test_max_iter_is_a_200_with_its_bracket(client):
    grasp = box_grasp()
    local = grasp.min_force(WRENCHES[1], method="ie", eps=1e-15, max_iter=2)
    remote = client.min_force(grasp, WRENCHES[1], method="ie", eps=1e-15, max_iter=2)
    assert remote.status == local.status == "max_iter"
    assert_close(remote.to_dict(), local.to_dict())


def test_compare_returns_the_baselines(client):
    pytest.importorskip("clarabel")
    pytest.importorskip("osqp")
    grasp = box_grasp()
    ours, rows = client.compare(grasp, WRENCHES[0])
    assert_close(ours.to_dict(), grasp.min_force(WRENCHES[0]).to_dict())
    by = {r["solver"]: r for r in rows}
    assert by["clarabel"]["status"] == "optimal" and abs(by["clarabel"]["error"]) < 1e-6
    # the inscribed pyramid needs more force than the exact cone
    assert by["osqp"]["method"] == "osqp-pyramid" and by["osqp"]["sigma"] >= ours.sigma * (1 - 1e-4)


def test_batch_agrees(client):
    grasp = three_fingers()
    W = gaussian(40, std=[2.0] * 3 + [0.05] * 3, seed=3)
    local = grasp.min_force_batch(W, forces=True)
    grasp.reset_start_tables()
    remote = client.min_force_batch(grasp, W, forces=True)
    assert isinstance(remote, gf.records.results.MinForceBatch)
    assert_close(remote.to_dict(), local.to_dict())
    # each entry is min_force's answer
    for i in (0, 17, 39):
        assert remote.sigma[i] == three_fingers().min_force_batch(W[:i + 1]).sigma[i]
    # drawn by the service from a seed: the same wrenches as drawn here
    sample = {"count": 25, "seed": 9, "force_scale": 3.0, "torque_scale": 0.05,
              "mean": [0, 0, -9.81, 0, 0, 0]}
    drawn = client.min_force_batch(grasp, sample=sample, norm="Linf")
    W = gaussian(25, sample["mean"], [3.0] * 3 + [0.05] * 3, seed=9)
    np.testing.assert_array_equal(drawn.wrenches, W)
    grasp.reset_start_tables()
    assert_close(drawn.to_dict(), {**grasp.min_force_batch(W, norm="Linf").to_dict(),
                                   "wrenches": W.tolist()})


def test_force_closure_and_quality_agree(client):
    for grasp in (box_grasp(), three_fingers(),
                  gf.Grasp([gf.Contact([0.05, 0, 0], [-1, 0, 0], 0.5)])):
        assert client.is_force_closure(grasp) == grasp.is_force_closure()
        remote = client.quality(grasp, eps=1e-2)
        assert isinstance(remote, gf.GraspQuality)
        assert_close(remote.to_dict(), grasp.quality(eps=1e-2).to_dict())


def _sets():
    rng = np.random.default_rng(5)
    R = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    R *= np.sign(np.linalg.det(R))
    ell = gf.Ellipsoid(np.zeros(3), np.diag([1.0, 2.0, 0.5]))
    poly = gf.Polytope(rng.normal(size=(12, 3)))
    return {
        "polytope": poly,
        "ellipsoid": ell,
        "ball": gf.Ball(np.array([0.1, 0.0, -0.1]), 1.5),
        "box": gf.Box([1.0, 0.5, 0.25], center=[0.1, 0, 0], rotation=R),
        "truncated_cone": gf.TruncatedCone(0.3, 0.1, 0.6),
        "capsule": gf.Capsule(0.2, 1.0),
        "hull": gf.hull(ell, poly),
        "sum": gf.minkowski_sum(ell, gf.Box([0.2, 0.2, 0.2])),
        "affine": gf.affine(rng.normal(size=(4, 3)), ell, [0.1, 0, 0, 0]),
        "negation": -gf.hull(ell, gf.Polytope(np.eye(3))),
        "dim6": gf.hull(gf.Ellipsoid(np.zeros(6), np.diag(np.arange(1.0, 7.0))),
                        gf.Polytope(rng.normal(size=(8, 6)))),
    }


@pytest.mark.parametrize("name", list(_sets()))
def test_ray_shoot_agrees(client, name):
    rng = np.random.default_rng(len(name))
    for method in ("zc-ie", "gjk", "ie", "zc", "bi-gjk", "zc-ie-newton"):
        # a new set each time: the service builds the set of each request, so its shot is a
        # set's first (a second shot at one set starts from its start table)
        A = _sets()[name]
        r = rng.normal(size=A.dim)
        local = gf.ray_shoot(A, r, method=method)
        remote = client.ray_shoot(A, r, method=method)
        assert isinstance(remote, gf.RayShot) and remote.convex_set is A
        assert_close(remote.to_dict(), local.to_dict())


def test_growth_distance_agrees(client):
    A = gf.Ellipsoid(np.zeros(3), np.diag([0.1, 0.2, 0.3]))
    B = gf.TruncatedCone(0.1, 0.05, 0.2)
    C = gf.Capsule(0.05, 0.3)
    rng = np.random.default_rng(2)
    for X, Y in ((A, B), (B, C), (A, C)):
        for distance in (1.0, 0.25, 0.05):
            R = np.linalg.qr(rng.normal(size=(3, 3)))[0]
            R *= np.sign(np.linalg.det(R))
            pose_a = (np.eye(3), np.zeros(3))
            pose_b = (R, rng.normal(size=3) * distance)
            local = gf.growth_distance(X, pose_a, Y, pose_b)
            remote = client.growth_distance(X, pose_a, Y, pose_b)
            assert isinstance(remote, gf.GrowthDistanceResult)
            assert_close(remote.to_dict(), local.to_dict())


def test_health_and_readiness(client):
    assert client.healthz() == {"status": "ok"}
    assert client.readyz()["status"] == "ready"


# -- robots --------------------------------------------------------------------------------------------
def _robots():
    try:
        import graspforce.robots as robots
        import pinocchio  # noqa: F401
    except ImportError:
        pytest.skip("the robots' packages (pin, example-robot-data) are not installed")
    return robots


def test_robots_agree(client):
    robots = _robots()
    listed = client.robots()
    assert [r["name"] for r in listed] == robots.list_scenarios()
    for name in robots.list_scenarios():
        local = robots.load_scenario(name)
        assert_close(client.robot(name), local.to_dict())
        remote = client.robot_forces(name)
        expected = local.solve().to_dict()
        assert isinstance(remote["record"], gf.MinForce)
        assert_close({**remote, "record": remote["record"].to_dict()}, expected)


def test_robot_configuration_wrench_and_motion_agree(client):
    robots = _robots()
    s = robots.load_scenario("talos_double_support")
    q = s.q.copy()
    q[2] -= 0.01                                   # the base 1 cm lower
    w = s.external_wrench + np.array([5.0, 0, 0, 0, 0.5, 0])
    for kwargs, local in (
            ({"configuration": q}, lambda: s.with_configuration(q).solve()),
            ({"w_ext": w, "norm": "Linf"}, lambda: s.solve(norm="Linf", w_ext=w)),
            ({"a": np.full(s.model.nv, 0.05)}, lambda: s.solve(a=np.full(s.model.nv, 0.05)))):
        s.grasp.reset_start_tables()
        expected = local().to_dict()
        remote = client.robot_forces("talos_double_support", **kwargs)
        assert_close({**remote, "record": remote["record"].to_dict()}, expected)


def test_robot_picture(client):
    _robots()
    png = client.robot_picture("panda_pinch_box")
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10000


# -- malformed requests ------------------------------------------------------------------------------
EX = [{"position": [0.05, 0.01, 0.0], "normal": [-1, 0, 0], "mu": 0.5, "mu_spin": 0.01},
      {"position": [-0.05, 0.01, 0.0], "normal": [1, 0, 0], "mu": 0.5, "mu_spin": 0.01}]
FO = {"contacts": EX, "w_ext": [0, 0, -9.81, 0, 0, 0]}
BALL = {"type": "ball", "center": [0, 0, 0], "radius": 1.0}
EYE = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
RS = {"set": BALL, "r": [1, 0, 0]}
GD = {"a": BALL, "pose_a": {"rotation": EYE, "translation": [0, 0, 0]},
      "b": BALL, "pose_b": {"rotation": EYE, "translation": [3, 0, 0]}}


def contact(i=0, **change):
    contacts = [dict(c) for c in EX]
    contacts[i].update(change)
    return contacts


def nested(depth):
    s = BALL
    for _ in range(depth):
        s = {"type": "hull", "sets": [s]}
    return s


FORCE, BATCH, CLOSURE, RAY, GROWTH = ("/v1/force-optimization", "/v1/force-optimization/batch",
                                      "/v1/force-closure", "/v1/ray-shoot", "/v1/growth-distance")
# (name, path, body (a dict, or raw bytes), status, loc after "body" (or None), words in msg)
MALFORMED = [
    ("short wrench", FORCE, {**FO, "w_ext": [0] * 5}, 422, ("w_ext",), "at least 6"),
    ("long wrench", FORCE, {**FO, "w_ext": [0] * 7}, 422, ("w_ext",), "at most 6"),
    ("NaN wrench", FORCE, b'{"contacts": %s, "w_ext": [NaN, 0, 0, 0, 0, 0]}'
     % json.dumps(EX).encode(), 422, ("w_ext", 0), "finite number"),
    ("inf wrench", FORCE, b'{"contacts": %s, "w_ext": [0, Infinity, 0, 0, 0, 0]}'
     % json.dumps(EX).encode(), 422, ("w_ext", 1), "finite number"),
    ("overflowing number", FORCE, b'{"contacts": %s, "w_ext": [0, 0, 1e400, 0, 0, 0]}'
     % json.dumps(EX).encode(), 422, ("w_ext", 2), "finite number"),
    ("huge wrench entry", FORCE, {**FO, "w_ext": [0, 0, 1e12, 0, 0, 0]}, 422, ("w_ext", 2),
     "less than or equal to 1000000000"),
    ("string in wrench", FORCE, {**FO, "w_ext": [0, 0, "9.81", 0, 0, 0]}, 422, ("w_ext", 2),
     "valid number"),
    ("wrench not a list", FORCE, {**FO, "w_ext": "down"}, 422, ("w_ext",), "valid"),
    ("empty contacts", FORCE, {**FO, "contacts": []}, 422, ("contacts",), "at least 1"),
    ("zero length", FORCE, {**FO, "length": 0.0}, 422, ("length",), "greater than 0"),
    ("negative length", BATCH, {"contacts": EX, "wrenches": [FO["w_ext"]], "length": -1.0}, 422,
     ("length",), "greater than 0"),
    ("subnormal length", BATCH, {"contacts": EX, "wrenches": [FO["w_ext"]], "length": 5e-324},
     422, ("length",), "within a factor"),
    ("length as a string", CLOSURE, {"contacts": EX, "length": "1 m"}, 422, ("length",),
     "valid number"),
    ("missing contacts", FORCE, {"w_ext": FO["w_ext"]}, 422, ("contacts",), "Field required"),
    ("negative friction", FORCE, {**FO, "contacts": contact(mu=-0.1)}, 422,
     ("contacts", 0, "mu"), "greater than or equal to 0"),
    ("negative spin friction", FORCE, {**FO, "contacts": contact(1, mu_spin=-1.0)}, 422,
     ("contacts", 1, "mu_spin"), "greater than or equal to 0"),
    ("vanishing spin friction", FORCE, {**FO, "contacts": contact(mu_spin=1e-300)}, 422,
     ("contacts", 0, "mu_spin"), "must be 0 or at least 1e-9"),
    ("zero normal", FORCE, {**FO, "contacts": contact(normal=[0, 0, 0])}, 422,
     ("contacts", 0, "normal"), "nonzero"),
    ("short position", FORCE, {**FO, "contacts": contact(position=[0, 0])}, 422,
     ("contacts", 0, "position"), "at least 3"),
    ("spin without friction", FORCE, {**FO, "contacts": contact(mu=0.0, mu_spin=0.01)}, 422,
     ("contacts", 0, "mu_spin"), "must be 0 when mu is 0"),
    ("bad tangents", FORCE, {**FO, "contacts": contact(tangents=[[1, 0, 0], [0, 1, 0]])}, 422,
     ("contacts", 0, "tangents"), "o x t = normal"),
    ("too many contacts", FORCE, {**FO, "contacts": EX * 33}, 422, ("contacts",),
     "at most 64 contacts"),
    ("unknown method", FORCE, {**FO, "method": "simplex"}, 422, ("method",), "'zc-ie'"),
    ("unknown norm", FORCE, {**FO, "norm": "L2"}, 422, ("norm",), "'Linf'"),
    ("unknown magnitude", FORCE, {**FO, "magnitude": "tangential"}, 422, ("magnitude",),
     "'full'"),
    ("zero eps", FORCE, {**FO, "eps": 0}, 422, ("eps",), "greater than or equal to 0.000000000000001"),
    ("eps too large", FORCE, {**FO, "eps": 0.5}, 422, ("eps",), "less than or equal to 0.1"),
    ("zero max_iter", FORCE, {**FO, "max_iter": 0}, 422, ("max_iter",), "greater than or equal"),
    ("misspelt option", FORCE, {**FO, "epsilon": 1e-6}, 422, ("epsilon",), "Extra inputs"),
    ("unknown baseline", FORCE, {**FO, "compare": ["gurobi"]}, 422, ("compare", 0),
     "'clarabel'"),
    ("not JSON", FORCE, b"{contacts: ...", 422, None, "JSON"),
    ("JSON array body", FORCE, b"[1, 2, 3]", 422, None, "valid dictionary"),
    ("too large a body", FORCE, b'{"contacts": [], "w_ext": [' + b"0," * 2_500_000 + b"0]}",
     413, None, "GRASPFORCE_MAX_BODY_BYTES"),
    ("both wrenches and sample", BATCH, {**FO, "w_ext": None, "wrenches": [[0] * 6],
                                         "sample": {"count": 3}}, 422, None, "w_ext"),
    ("neither wrenches nor sample", BATCH, {"contacts": EX}, 422, (),
     "give exactly one of them"),
    ("too many wrenches", BATCH, {"contacts": EX, "wrenches": [[0] * 6] * 20001}, 422,
     ("wrenches",), "at most 20000 wrenches"),
    ("huge sample", BATCH, {"contacts": EX, "sample": {"count": 10**9}}, 422, (),
     "sample.count: at most 20000"),
    ("negative seed", BATCH, {"contacts": EX, "sample": {"count": 3, "seed": -1}}, 422,
     ("sample", "seed"), "greater than or equal to 0"),
    ("short wrench row", BATCH, {"contacts": EX, "wrenches": [[0] * 6, [0] * 5]}, 422,
     ("wrenches", 1), "at least 6"),
    ("closure eps out of range", CLOSURE, {"contacts": EX, "eps": 0.0}, 422, ("eps",),
     "greater than or equal to 0.0001"),
    ("unknown set type", RAY, {**RS, "set": {"type": "sphere", "radius": 1}}, 422, ("set",),
     "does not match any of the expected tags"),
    ("ray of the wrong dimension", RAY, {**RS, "r": [1, 0]}, 422, ("r",), "must have 3 entries"),
    ("zero ray", RAY, {**RS, "r": [0, 0, 0]}, 422, ("r",), "must be nonzero"),
    ("ragged vertices", RAY, {**RS, "set": {"type": "polytope", "vertices": [[0, 0, 0], [1, 0]]}},
     422, ("set", "polytope", "vertices"), "same length"),
    ("hull of two dimensions", RAY, {**RS, "set": {"type": "hull", "sets": [
        BALL, {"type": "ball", "center": [0, 0], "radius": 1}]}}, 422, ("set", "sets"),
     "same dimension"),
    ("improper rotation", RAY, {**RS, "set": {"type": "box", "half_extents": [1, 1, 1],
                                              "rotation": [[1, 0, 0], [0, 1, 0], [0, 0, -1]]}},
     422, ("set", "rotation"), "proper rotation"),
    ("nested too deep", RAY, {**RS, "set": nested(20)}, 422, (), "nested at most 16"),
    ("negative radius", RAY, {**RS, "set": {**BALL, "radius": -1}}, 422,
     ("set", "ball", "radius"), "greater than or equal to 0"),
    ("flat shape for growth", GROWTH, {**GD, "a": {"type": "polytope",
                                                   "vertices": [[0, 0, 0], [1, 0, 0]]}},
     422, ("a",), "interior point"),
    ("2-D shape for growth", GROWTH, {**GD, "b": {"type": "ball", "center": [0, 0],
                                                  "radius": 1}}, 422, ("b",), "3-D set"),
    ("unknown scenario", "/v1/robots/atlas_backflip", None, 422, ("path", "name"),
     "'talos_double_support'"),
    ("a path as a scenario name", "/v1/robots/..%2F..%2Fetc%2Fpasswd/force-optimization", {},
     422, ("path", "name"), "Input should be"),
    ("a file as a scenario name", "/v1/robots/%2Ftmp%2Fx.toml", None, 422, ("path", "name"),
     "Input should be"),
    ("robot configuration of the wrong length", "/v1/robots/panda_pinch_box/force-optimization",
     {"configuration": [0.0] * 3}, 422, ("configuration",), "must be 9 finite numbers"),
    ("motion of a fixed base", "/v1/robots/panda_pinch_box/force-optimization",
     {"motion": {"a": [0.1] * 9}}, 422, ("motion",), "floating-base"),
    ("wrench and motion together", "/v1/robots/go1_uneven_terrain/force-optimization",
     {"w_ext": [0] * 6, "motion": {"a": [0.0] * 18}}, 422, ("w_ext",), "not both"),
    ("improper pose", GROWTH, {**GD, "pose_b": {"rotation": [[2, 0, 0], [0, 1, 0], [0, 0, 1]],
                                               "translation": [3, 0, 0]}}, 422, ("pose_b",),
     "rotation must be proper"),
    ("short translation", GROWTH, {**GD, "pose_a": {"rotation": EYE, "translation": [0, 0]}},
     422, ("pose_a", "translation"), "at least 3"),
]


@pytest.mark.parametrize("name,path,body,status,loc,words", MALFORMED,
                         ids=[m[0] for m in MALFORMED])
def test_malformed_request(served, name, path, body, status, loc, words):
    if path.startswith("/v1/robots"):
        _robots()
    if body is None:
        r = httpx.get(served + path)
    elif isinstance(body, bytes):
        r = httpx.post(served + path, content=body, headers={"content-type": "application/json"})
    else:
        r = httpx.post(served + path, json=body)
    assert r.status_code == status, r.text
    detail = r.json()["detail"]
    text = json.dumps(detail)
    assert words in text, text
    if loc is not None:
        where = list(loc) if loc[:1] == ("path",) else ["body", *loc]
        assert any(list(e["loc"]) == where for e in detail), text
        for e in detail:
            assert e["msg"] and e["loc"][0] in ("body", "path")


def test_malformed_table_is_large_enough():
    assert len(MALFORMED) >= 30


# -- concurrency ---------------------------------------------------------------------------------------
def test_64_concurrent_clients(served):
    """64 clients at once, every one on the same grasp (and the same set) with its own wrench,
    method and objective: a server that shot two threads' problems at one shared set object
    would mix their scratch and answer someone else's problem."""
    grasp = box_grasp()
    contacts = [{"position": c.position.tolist(), "normal": c.normal.tolist(), "mu": c.mu,
                 "mu_spin": c.mu_spin} for c in grasp.contacts]
    local_grasp = gf.Grasp(gf.Contact(**c) for c in contacts)
    A = _sets()["hull"]
    from graspforce.serialize import set_from_dict, set_to_dict
    set_json = set_to_dict(A)
    rng = np.random.default_rng(64)
    methods = ("zc-ie", "ie", "gjk", "zc-ie-newton")
    problems = []
    for i in range(64 * 4):
        if i % 4 == 3:
            r = rng.normal(size=3)
            problems.append(("ray", r, methods[i % 3]))
        else:
            w = np.concatenate([rng.normal(0, 3, 3), rng.normal(0, 0.05, 3)])
            problems.append(("force", w, methods[i % 4], ("L1", "Linf")[i % 2]))
    barrier = threading.Barrier(64)

    def one_client(k):
        answers = []
        with httpx.Client(base_url=served, timeout=60) as http:
            barrier.wait()
            for p in problems[k::64]:
                if p[0] == "force":
                    r = http.post("/v1/force-optimization", json={
                        "contacts": contacts, "w_ext": p[1].tolist(), "method": p[2],
                        "norm": p[3]})
                else:
                    r = http.post("/v1/ray-shoot", json={"set": set_json, "r": p[1].tolist(),
                                                         "method": p[2]})
                answers.append((p, r.status_code, r.json()))
        return answers

    with ThreadPoolExecutor(64) as pool:
        results = [a for answers in pool.map(one_client, range(64)) for a in answers]
    assert len(results) == len(problems)
    for p, status, body in results:
        assert status == 200, body
        if p[0] == "force":
            local_grasp.reset_start_tables()
            local = local_grasp.min_force(p[1], method=p[2], norm=p[3]).to_dict()
            body = {k: v for k, v in body.items() if k in local}
        else:
            # a set of its own, as the service builds for each request
            local = gf.ray_shoot(set_from_dict(set_json), p[1], method=p[2]).to_dict()
        assert_close(body, local)


# -- the command line --------------------------------------------------------------------------------
def test_cli_exit_codes(tmp_path, capsys):
    from graspforce.cli import main
    good = tmp_path / "good.json"
    good.write_text(json.dumps(FO))
    assert main(["optimize", str(good), "--check"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "optimal"
    pull = tmp_path / "pull.json"
    pull.write_text(json.dumps({"contacts": [{"position": [0.05, 0, 0], "normal": [-1, 0, 0],
                                              "mu": 0.5}], "w_ext": [-1, 0, 0, 0, 0, 0]}))
    assert main(["optimize", str(pull)]) == 0
    assert main(["optimize", str(pull), "--check"]) == 1
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({**FO, "contacts": contact(normal=[0, 0, 0])}))
    assert main(["optimize", str(bad)]) == 2
    assert "contacts[0].normal: must be a nonzero vector" in capsys.readouterr().err
    (tmp_path / "broken.json").write_text("{")
    assert main(["optimize", str(tmp_path / "broken.json")]) == 2
    assert main(["optimize", str(tmp_path / "missing.json")]) == 2
    assert main(["serve", "--port", "70000"]) == 2
    assert main(["frobnicate"]) == 2
    for command in ([], ["serve"], ["optimize"], ["robots"], ["warmup"], ["demo"], ["bench"]):
        assert main([*command, "--help"]) == 0
    capsys.readouterr()


def test_cli_agrees_with_library(tmp_path, capsys):
    from graspforce.cli import main
    problem = {**FO, "norm": "Linf", "magnitude": "full", "method": "ie"}
    path = tmp_path / "p.json"
    path.write_text(json.dumps(problem))
    assert main(["optimize", str(path), "--compact"]) == 0
    grasp = gf.Grasp(gf.Contact(**c) for c in EX)
    assert_close(json.loads(capsys.readouterr().out),
                 grasp.min_force(FO["w_ext"], norm="Linf", magnitude="full",
                                 method="ie").to_dict())


def test_cli_robots(capsys):
    robots = _robots()
    from graspforce.cli import main
    assert main(["robots"]) == 0
    listed = capsys.readouterr().out
    assert all(name in listed for name in robots.list_scenarios())
    assert main(["optimize", "talos_double_support", "--check", "--compact"]) == 0
    out = json.loads(capsys.readouterr().out)
    expected = robots.load_scenario("talos_double_support").solve().to_dict()
    assert_close(out, expected)
    assert main(["optimize", "atlas_backflip"]) == 2
    assert main(["robots", "--help"]) == 0
    capsys.readouterr()


def test_console_script_and_module():
    script = shutil.which("graspforce", path=os.path.dirname(sys.executable))
    if script is None:
        pytest.skip("the graspforce console script is not installed next to this Python")
    for command in ([script, "warmup"], [sys.executable, "-m", "graspforce", "warmup"]):
        done = subprocess.run(command, capture_output=True, text=True, timeout=60)
        assert done.returncode == 0 and "ready" in done.stdout
    done = subprocess.run([script, "optimize", "/nonexistent.json"], capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 2 and "problem" in done.stderr


# -- /docs offline ------------------------------------------------------------------------------------
def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def test_docs_render_offline(served):
    page = httpx.get(served + "/docs").text
    # every script and style comes from the app itself
    assert "http://" not in page.replace(served, "") and "https://" not in page
    for asset in ("/static/swagger-ui/swagger-ui-bundle.js", "/static/swagger-ui/swagger-ui.css"):
        assert httpx.get(served + asset).status_code == 200
    chromium = _chromium()
    if chromium is None:
        pytest.skip("no chromium to render /docs (apt-get install chromium)")
    # every host but the loopback resolves to nothing: the page must render from the app alone
    flags = [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
             "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1",
             "--virtual-time-budget=15000", "--window-size=1280,1400"]
    dom = subprocess.run([*flags, "--dump-dom", served + "/docs"], capture_output=True,
                         text=True, timeout=120).stdout
    for text in ("graspforce", "/v1/force-optimization", "/v1/ray-shoot", "/v1/growth-distance",
                 "opblock"):
        assert text in dom, f"/docs did not render {text!r}"
    os.makedirs(RESULTS, exist_ok=True)
    shot = os.path.join(RESULTS, "service_docs.png")
    subprocess.run([*flags, f"--screenshot={shot}", served + "/docs"], capture_output=True,
                   timeout=120)
    assert os.path.getsize(shot) > 10000
