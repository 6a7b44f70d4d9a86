"""gf.batch: batch answers equal one-at-a-time answers bit for bit, bad rows are marked and
nothing else refused, a Dask cluster gives the local arrays, an interrupted and resumed CLI run
writes the uninterrupted run's file, and coverage's interval holds a closed-form truth."""
import math
import os
import pathlib
import pickle
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import graspforce as gf
from grasp_cases import random_grasp
from grasps import MU, box_grasp, sphere_grasp, sphere_sigma_l1, two_finger_pinch

FIELDS = ("sigma", "sigma_lower", "status", "iterations", "forces")


def _wrenches(rng, k):
    w = np.hstack([rng.normal(0, 5.0, (k, 3)), rng.normal(0, 0.3, (k, 3))])
    w[3] = 0.0                                  # zero wrench: optimal, sigma 0
    w[5, 2] = np.nan
    w[8, 4] = np.inf
    w[9] = 1e200                                # its squared norm overflows
    return w


def _single(grasp, w, **kw):
    """Grasp.min_force as a batch row: (sigma, lower, status, iterations, forces)."""
    try:
        with np.errstate(over="ignore"):        # the 1e200 row: its squared norm overflows
            r = grasp.min_force(w, **kw)
    except ValueError:
        return None
    return (r.sigma, r.sigma_lower, r.status, r.iterations, np.array(r.forces))


def _same_rows(batch, grasp, wrenches, **kw):
    for i, w in enumerate(wrenches):
        one = _single(grasp, w, **kw)
        if one is None:
            assert batch.status_names[i] == "bad_wrench" and math.isnan(batch.sigma[i])
            continue
        assert (batch.sigma[i], batch.sigma_lower[i], batch.status_names[i],
                batch.iterations[i]) == one[:4], i
        assert np.array_equal(batch.forces[i], one[4]), i


@pytest.mark.parametrize("norm", ["L1", "Linf"])
@pytest.mark.parametrize("m", range(2, 9))
def test_batch_equals_one_at_a_time(m, norm):
    rng = np.random.default_rng(100 + m)
    grasp = random_grasp(rng, m)
    wrenches = _wrenches(rng, 60)
    batch = gf.batch.min_force(grasp, wrenches, norm=norm, forces=True, threads=2)
    assert batch.status[3] == 0 and batch.sigma[3] == 0.0
    assert list(batch.status_names[[5, 8, 9]]) == ["bad_wrench"] * 3
    _same_rows(batch, grasp, wrenches, norm=norm)


@pytest.mark.parametrize("method", ["ie", "zc-ie-newton", "gjk"])
def test_batch_equals_one_at_a_time_other_methods_and_full(method):
    grasp = box_grasp()
    wrenches = _wrenches(np.random.default_rng(7), 40)
    for magnitude in ("normal", "full"):
        batch = gf.batch.min_force(grasp, wrenches, magnitude=magnitude, method=method,
                                   eps=1e-7, forces=True)
        _same_rows(batch, grasp, wrenches, magnitude=magnitude, method=method, eps=1e-7)


def test_infeasible_rows_are_marked():
    grasp = two_finger_pinch()      # no torque about the x axis through both contacts
    w = np.array([[0, 0, -1.0, 0, 0, 0], [0, 0, 0, 1.0, 0, 0], [np.nan] * 6, [0.0] * 6])
    batch = gf.batch.min_force(grasp, w, forces=True)
    assert list(batch.status_names) == ["optimal", "infeasible", "bad_wrench", "optimal"]
    assert batch.sigma[1] == math.inf and batch.sigma_lower[1] == math.inf
    assert not batch.forces[1].any() and not batch.forces[3].any()
    _same_rows(batch, grasp, w)
    assert batch.counts() == {"optimal": 2, "infeasible": 1, "max_iter": 0, "bad_wrench": 1}


def test_max_iter_rows_match():
    grasp = sphere_grasp(1e-3)
    w = _wrenches(np.random.default_rng(3), 30)
    batch = gf.batch.min_force(grasp, w, max_iter=3, forces=True)
    assert "max_iter" in set(batch.status_names)
    _same_rows(batch, grasp, w, max_iter=3)


def test_threads_do_not_change_the_answer():
    grasp = box_grasp()
    w = _wrenches(np.random.default_rng(5), 3000)
    runs = [gf.batch.min_force(grasp, w, norm="Linf", forces=True, threads=t) for t in (1, 2, 3)]
    for r in runs[1:]:
        for f in FIELDS:
            assert np.array_equal(getattr(r, f), getattr(runs[0], f), equal_nan=True), f


def test_arguments_are_checked():
    grasp = box_grasp()
    with pytest.raises(ValueError, match="wrenches: expected shape"):
        gf.batch.min_force(grasp, np.zeros((4, 5)))
    with pytest.raises(TypeError, match="wrenches"):
        gf.batch.min_force(grasp, [["a"] * 6])
    with pytest.raises(TypeError, match="grasp: expected gf.Grasp"):
        gf.batch.min_force("grasp", np.zeros((1, 6)))
    with pytest.raises(ValueError, match="threads"):
        gf.batch.min_force(grasp, np.zeros((1, 6)), threads=0)
    with pytest.raises(ValueError, match="norm"):
        gf.batch.min_force(grasp, np.zeros((1, 6)), norm="L2")
    with pytest.raises(ValueError, match="eps"):
        gf.batch.min_force(grasp, np.zeros((1, 6)), eps=-1.0)
    with pytest.raises(ValueError, match="budget"):
        gf.batch.coverage(grasp, np.zeros((1, 6)), budget=math.nan)
    assert len(gf.batch.min_force(grasp, np.zeros((0, 6)))) == 0


def test_one_wrench_and_a_list():
    grasp = box_grasp()
    w = [0.0, 0.0, -9.81, 0.0, 0.0, 0.0]
    assert gf.batch.min_force(grasp, w).sigma[0] == gf.batch.min_force(grasp, [w]).sigma[0]


def test_many_grasps_equal_new_grasps_first_call():
    rng = np.random.default_rng(9)
    grasps = [random_grasp(rng, m) for m in (2, 3, 4, 5, 6) for _ in range(3)]
    w = np.array([0.0, 0.0, -5.0, 0.01, 0.0, 0.0])
    for g in grasps[:3]:
        g.min_force(w)
        g.min_force(w)                 # earlier calls (a start table) change nothing
    batch = gf.batch.min_force_grasps(grasps, w, forces=True)
    for i, g in enumerate(grasps):
        fresh = gf.Grasp(g.contacts).min_force(w)
        assert (batch.sigma[i], batch.sigma_lower[i], batch.status_names[i],
                batch.iterations[i]) == (fresh.sigma, fresh.sigma_lower, fresh.status,
                                         fresh.iterations)
        assert np.array_equal(batch.forces[i], fresh.forces)
    with pytest.raises(ValueError, match="wrench"):
        gf.batch.min_force_grasps(grasps, [np.nan] * 6)


def test_growth_batch_equals_single_calls():
    from scipy.spatial.transform import Rotation
    A = gf.Ellipsoid(np.zeros(3), np.diag([0.1, 0.05, 0.03]))
    B = gf.Box(np.array([0.05, 0.05, 0.02]))
    n = 200
    rng = np.random.default_rng(0)
    R_a = Rotation.random(n, random_state=1).as_matrix()
    R_b = Rotation.random(n, random_state=2).as_matrix()
    p_a, p_b = rng.normal(size=(n, 3)) * 0.1, rng.normal(size=(n, 3)) * 0.1
    R_a[3] *= 2.0                       # not a rotation
    p_a[4] = p_b[4]                     # coincident reference points
    batch = gf.batch.growth_distance(A, B, (R_a, p_a), (R_b, p_b), threads=2)
    for i in range(n):
        try:
            one = gf.growth_distance(A, (R_a[i], p_a[i]), B, (R_b[i], p_b[i]))
        except ValueError:
            assert batch.status[i] == "bad_pose" and math.isnan(batch.sigma[i])
            continue
        assert (one.sigma, one.sigma_lower, one.sigma_upper, one.status, one.iterations) == (
            batch.sigma[i], batch.sigma_lower[i], batch.sigma_upper[i], batch.status[i],
            batch.iterations[i]), i
    # one pose for all rows, as a 4x4 matrix
    fixed = np.eye(4)
    M = np.tile(np.eye(4), (n, 1, 1))
    M[:, :3, :3], M[:, :3, 3] = R_b, p_b
    again = gf.batch.growth_distance(A, B, fixed, M)
    assert np.array_equal(again.sigma, gf.batch.growth_distance(
        A, B, (np.eye(3), np.zeros(3)), (R_b, p_b)).sigma)


def test_grasp_pickles_and_gives_the_same_batch():
    grasp = box_grasp()
    w = _wrenches(np.random.default_rng(1), 500)
    here = gf.batch.min_force(grasp, w, forces=True)
    there = gf.batch.min_force(pickle.loads(pickle.dumps(grasp)), w, forces=True)
    for f in FIELDS:
        assert np.array_equal(getattr(here, f), getattr(there, f), equal_nan=True), f


def test_local_cluster_gives_the_local_arrays():
    distributed = pytest.importorskip("distributed")
    grasp = box_grasp()
    w = _wrenches(np.random.default_rng(2), 5000)
    local = gf.batch.min_force(grasp, w, norm="Linf", forces=True)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = gf.batch.min_force(grasp, w, norm="Linf", forces=True, client=client,
                                        chunk_size=700)
            grasps = [box_grasp(), two_finger_pinch(), sphere_grasp(0.5)] * 3
            g_remote = gf.batch.min_force_grasps(grasps, w[0], client=client, chunk_size=2)
        # a scheduler address: the call opens and closes its own client
        by_address = gf.batch.min_force(grasp, w[:1000], norm="Linf",
                                        client=cluster.scheduler_address)
    for f in FIELDS:
        assert np.array_equal(getattr(local, f), getattr(remote, f), equal_nan=True), f
    assert np.array_equal(by_address.sigma, local.sigma[:1000], equal_nan=True)
    g_local = gf.batch.min_force_grasps(grasps, w[0])
    assert np.array_equal(g_local.sigma, g_remote.sigma)


# coverage: truths in closed form

def test_coverage_two_opposing_frictionless_contacts():
    """Two frictionless fingers pressing on x = +-0.05 along x: a wrench (s, 0, ..., 0) needs
    |s| of normal force (L1), so wrenches with s uniform in [-1, 1] are resisted within budget
    b with probability b exactly."""
    grasp = gf.Grasp([gf.Contact([0.05, 0, 0], [-1, 0, 0], 0.0),
                      gf.Contact([-0.05, 0, 0], [1, 0, 0], 0.0)])
    budget = 0.37
    held = 0
    for seed in range(40):
        s = np.random.default_rng(seed).uniform(-1.0, 1.0, 400)
        w = np.zeros((400, 6))
        w[:, 0] = s
        c = gf.batch.coverage(grasp, w, budget)
        assert np.allclose(c.result.sigma, np.abs(s), rtol=1e-9, atol=1e-15)
        lo, hi = c.interval
        held += lo <= budget <= hi
    # a 95 % interval: 40 draws hold the truth ~38 times; fewer than 34 has probability < 1 %
    assert held >= 34


def test_coverage_sphere_weight_closed_form():
    """NOTES.md item 1: the sphere's weight G needs sigma_L1 = G / (mu cos a - sin a); with G
    uniform in [0, 20], the fraction held within budget B is B (mu cos a - sin a) / 20."""
    lam = 0.5
    grasp = sphere_grasp(lam)
    per_newton = sphere_sigma_l1(lam) / 10.0
    budget = 60.0
    truth = budget / (per_newton * 20.0)
    rng = np.random.default_rng(11)
    w = np.zeros((20000, 6))
    w[:, 2] = -rng.uniform(0.0, 20.0, 20000)
    c = gf.batch.coverage(grasp, w, budget, confidence=0.99)
    assert 0.0 < truth < 1.0
    assert c.interval[0] <= truth <= c.interval[1]
    assert abs(c.fraction - truth) < 0.02
    assert MU == 0.2


def test_wilson_interval_edges():
    lo, hi = gf.batch.wilson_interval(0, 50)
    assert lo == 0.0 and 0.0 < hi < 0.1
    lo, hi = gf.batch.wilson_interval(50, 50)
    assert hi == 1.0 and 0.9 < lo < 1.0
    assert all(math.isnan(x) for x in gf.batch.wilson_interval(0, 0))


def test_generators_are_seeded():
    from benchmarks.grasp_sets import random_wrenches
    assert np.array_equal(gf.batch.table5(100, seed=4), random_wrenches(100, seed=4))
    for make in (lambda s: gf.batch.ball(300, 2.0, [10, 10, 10, 0.5, 0.5, 0.5], seed=s),
                 lambda s: gf.batch.gaussian(300, 0.0, 3.0, seed=s),
                 lambda s: gf.batch.ellipsoid(300, np.ones(6), np.eye(6)[:, :2], seed=s)):
        assert np.array_equal(make(1), make(1)) and not np.array_equal(make(1), make(2))
    b = gf.batch.ball(2000, 2.0, [10, 10, 10, 0.5, 0.5, 0.5], seed=0)
    r = np.linalg.norm(b / [10, 10, 10, 0.5, 0.5, 0.5], axis=1)
    assert r.max() <= 2.0 and np.quantile(r, 0.5) > 1.6      # uniform: half beyond 2 * 0.5^(1/6)
    with pytest.raises(ValueError, match="scale"):
        gf.batch.ball(10, scale=[1, 2])
    with pytest.raises(TypeError, match="seed"):
        gf.batch.gaussian(10, seed=None)


# the command line

GRASP_JSON = """{"contacts": [
 {"position": [0.05, 0.01, 0.0], "normal": [-1, 0, 0], "mu": 0.5, "mu_spin": 0.01},
 {"position": [0.05, -0.01, 0.01], "normal": [-1, 0, 0], "mu": 0.5, "mu_spin": 0.01},
 {"position": [-0.05, 0.01, 0.0], "normal": [1, 0, 0], "mu": 0.5, "mu_spin": 0.01},
 {"position": [-0.05, -0.01, -0.01], "normal": [1, 0, 0], "mu": 0.5, "mu_spin": 0.01}]}"""


def _cli(*args, **kw):
    root = pathlib.Path(__file__).resolve().parents[1]
    return subprocess.run([sys.executable, "-m", "graspforce", *args], cwd=root,
                          capture_output=True, text=True, **kw)


@pytest.mark.parametrize("suffix", [".parquet", ".csv"])
def test_cli_killed_and_resumed_writes_the_uninterrupted_file(tmp_path, suffix):
    pytest.importorskip("pyarrow")
    grasp = tmp_path / "grasp.json"
    grasp.write_text(GRASP_JSON)
    common = ["batch", str(grasp), "--generate", "table5", "-n", "60000", "--seed", "3",
              "--chunk-size", "2000", "--threads", "1", "--budget", "80"]
    whole = tmp_path / f"whole{suffix}"
    done = _cli(*common, "--out", str(whole), "--quiet")
    assert done.returncode == 0, done.stderr
    out = tmp_path / f"resumed{suffix}"
    parts = tmp_path / f"resumed{suffix}.parts"
    root = pathlib.Path(__file__).resolve().parents[1]
    proc = subprocess.Popen([sys.executable, "-m", "graspforce", *common, "--out",
                             str(out)], cwd=root, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and len(list(parts.glob("chunk-*"))) < 3:
        time.sleep(0.01)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    finished = sorted(parts.glob("chunk-*"))
    assert 3 <= len(finished) < 30 and not out.exists()
    again = _cli(*common, "--out", str(out))                  # without --resume: refused
    assert again.returncode == 2 and "--resume" in again.stderr
    resumed = _cli(*common, "--out", str(out), "--resume")
    assert resumed.returncode == 0, resumed.stderr
    assert "ETA" in resumed.stderr and "coverage at budget 80" in resumed.stdout
    assert out.read_bytes() == whole.read_bytes()
    assert not parts.exists() and not list(tmp_path.glob(".*tmp*"))
    finished_again = _cli(*common, "--out", str(out), "--resume")
    assert finished_again.returncode == 0 and "already complete" in finished_again.stderr
    changed = _cli(*common, "--seed", "4", "--out", str(out), "--resume")
    assert changed.returncode == 2 and "wrenches" in changed.stderr


def test_cli_resume_with_other_inputs_is_refused(tmp_path):
    pytest.importorskip("pyarrow")
    grasp = tmp_path / "grasp.json"
    grasp.write_text(GRASP_JSON)
    out = tmp_path / "r.parquet"
    (tmp_path / "r.parquet.parts").mkdir()
    (tmp_path / "r.parquet.parts" / "manifest.json").write_text('{"rows": 5}')
    res = _cli("batch", str(grasp), "--generate", "ball", "-n", "100", "--out", str(out), "--resume")
    assert res.returncode == 2 and "differ from the interrupted run" in res.stderr


def test_cli_reads_wrench_files_and_plots(tmp_path):
    pytest.importorskip("pyarrow")
    pytest.importorskip("matplotlib")
    grasp = tmp_path / "grasp.json"
    grasp.write_text(GRASP_JSON)
    w = gf.batch.table5(500, seed=1)
    np.save(tmp_path / "w.npy", w)
    np.savetxt(tmp_path / "w.csv", w, delimiter=",", header="fx,fy,fz,tx,ty,tz", comments="")
    expected = gf.batch.min_force(box_grasp(), w).sigma
    import pyarrow.parquet as pq
    for name in ("w.npy", "w.csv"):
        out = tmp_path / f"{name}.parquet"
        res = _cli("batch", str(grasp), "--wrenches", str(tmp_path / name), "--out", str(out),
                   "--forces", "--quiet")
        assert res.returncode == 0, res.stderr
        table = pq.read_table(out)
        assert np.array_equal(table.column("sigma").to_numpy(), expected)
        assert "c3_f4" in table.column_names
    for kind in (["hist", str(out)], ["coverage", str(out)],
                 ["slice", str(grasp), "--grid", "21", "--axes", "fz", "tx"]):
        png = tmp_path / f"{kind[0]}.png"
        res = _cli("plot", "--out", str(png), *kind)
        assert res.returncode == 0, res.stderr
        assert png.read_bytes()[:4] == b"\x89PNG"
    bad = tmp_path / "bad.json"
    bad.write_text('{"contacts": [{"position": [0, 0], "normal": [1, 0, 0], "mu": 0.5}]}')
    res = _cli("batch", str(bad), "--generate", "ball", "-n", "10", "--out", str(tmp_path / "b.csv"))
    assert res.returncode == 2 and "contacts[0]: position" in res.stderr


def test_min_force_batch_refuses_rows_of_another_width():
    grasp = box_grasp()
    for k in (5, 7, 12):
        with pytest.raises(ValueError, match=r"wrenches: expected shape \(k, 6\)"):
            grasp.min_force_batch(np.zeros((3, k)))
