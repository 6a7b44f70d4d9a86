"""Shared helpers for the graspforce core test suite.

`build(desc)` turns a truth.py description into the graspforce set; the `check_*` fixtures hold
the assertions of the API contract (docs/core-api.md) shared by several test files. The truth
itself always comes from tests/truth.py (LP, NNLS, Clarabel, closed forms), never from graspforce.
"""
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))

import graspforce as gf  # noqa: E402
import truth as T  # noqa: E402

METHODS = ("gjk", "ie", "zc", "bi-gjk", "zc-ie", "zc-ie-newton")

# Relative accuracy demanded of t at the default eps (1e-9): (t_upper - t)/t <= eps by contract.
T_RTOL = 1e-9
# Clarabel truth (hulls, sums): with its tolerances at 1e-12 it reaches ~1e-11 relative on t
# (measured: worst 6e-12 against the closed form on random ellipsoids); truth.ray_shoot_socp also
# returns a certified upper bound t_upper_truth from its dual. The comparison is therefore
# |t - t_socp| <= (1e-9 + (t_upper_truth - t_socp)/t_socp) t_socp: the required 1e-9 plus the
# truth's own certified uncertainty, and t <= t_upper_truth exactly. In addition, the exact
# certificate in _check_hit (independent support function + independent witness evaluation)
# proves the 1e-9 accuracy of every answer without relying on the conic solver.


def build(d):
    """graspforce set from a truth.py description."""
    k = d[0]
    if k == "poly":
        return gf.Polytope(d[1])
    if k == "ell":
        return gf.Ellipsoid(d[1], d[2])
    if k == "box":
        half, center, R = d[1], d[2], d[3]
        if not center.any() and np.array_equal(R, np.eye(half.size)):
            return gf.Box(half)
        return gf.Box(half, center=center, rotation=R)
    if k == "tcone":
        return gf.TruncatedCone(d[1], d[2], d[3])
    if k == "capsule":
        return gf.Capsule(d[1], d[2])
    if k == "hull":
        return gf.hull(*[build(c) for c in d[1]])
    if k == "sum":
        return gf.minkowski_sum(*[build(c) for c in d[1]])
    if k == "affine":
        return gf.affine(d[1], build(d[3]), d[2])
    raise ValueError(k)


def rel(a, b):
    return abs(a - b) / max(abs(b), 1e-300)


def has_capsule(d):
    if d[0] == "capsule":
        return True
    if d[0] in ("hull", "sum"):
        return any(has_capsule(c) for c in d[1])
    if d[0] == "affine":
        return has_capsule(d[3])
    return False


def check_witness(A, d, vertex, witness, what="vertex"):
    """vertex == A.witness_point(witness) (contract) and == the independent evaluation of the
    witness on the description (which also checks the leaf-local pre-images are feasible)."""
    vertex = np.asarray(vertex, dtype=float)
    tol = 1e-12 * max(1.0, np.linalg.norm(vertex))
    pairs = tuple(witness)
    assert len(pairs) >= 1, f"{what}: empty witness"
    for pair in pairs:
        assert len(pair) == 2, f"{what}: witness entries are (leaf_index, local) pairs: {pair!r}"
    lib = np.asarray(A.witness_point(witness), dtype=float)
    assert np.linalg.norm(lib - vertex) <= tol, \
        f"{what}: A.witness_point(w) = {lib} != {vertex} (diff {np.linalg.norm(lib - vertex):.3e})"
    if has_capsule(d):
        return
    mine = T.witness_point(d, witness)
    assert np.linalg.norm(mine - vertex) <= tol, \
        f"{what}: independent witness evaluation {mine} != {vertex} " \
        f"(diff {np.linalg.norm(mine - vertex):.3e})"


def _check_hit(A, d, r, res, t_true, method, eps=1e-9, t_rtol=T_RTOL, exact=True,
               t_true_upper=None, label=""):
    """All contract assertions for a hit (requirement 4 of the issue).

    exact: t_true is exact to ~1e-14 (LP polished, closed form), so the bracket
    t <= t_true <= t_upper is asserted. Otherwise (conic truth) t_true_upper is a certified upper
    bound of the true t (weak duality with the exact support function) and t <= t_true_upper."""
    r = np.asarray(r, dtype=float)
    n = r.size
    ctx = f"[{method}{' ' + label if label else ''}] r={r.tolist()} t_true={float(t_true)!r}"
    assert res.status == "hit", f"{ctx}: status {res.status!r}, expected 'hit'"
    assert res.hit is True or res.hit == True, ctx  # noqa: E712
    assert res.method == method, ctx
    t = float(res.t)
    t_up = float(res.t_upper)
    point = np.asarray(res.point, dtype=float)
    assert point.shape == (n,), ctx
    assert np.all(np.isfinite(point)) and np.isfinite(t) and np.isfinite(t_up), ctx
    # point == t r
    assert np.linalg.norm(point - t * r) <= 1e-12 * max(1.0, np.linalg.norm(point)), \
        f"{ctx}: point {point} != t r {t * r}"
    # accuracy against the independent truth
    assert rel(t, t_true) <= t_rtol, \
        f"{ctx}: t = {t!r} vs truth {t_true!r}: relative error {rel(t, t_true):.3e} > {t_rtol:g}"
    if exact:
        # the bracket: t <= t_true <= t_upper (t r is a point of A; the hyperplane is supporting)
        assert t <= t_true * (1 + 1e-12), f"{ctx}: t = {t!r} > t_true = {t_true!r}"
        assert t_true <= t_up * (1 + 1e-12), f"{ctx}: t_true = {t_true!r} > t_upper = {t_up!r}"
    if t_true_upper is not None:
        assert t <= t_true_upper * (1 + 1e-12), \
            f"{ctx}: t = {t!r} > certified upper bound of the truth {t_true_upper!r}"
    assert t <= t_up * (1 + 1e-15) + 1e-300, f"{ctx}: t = {t!r} > t_upper = {t_up!r}"
    assert (t_up - t) / t <= eps * (1 + 1e-6), \
        f"{ctx}: (t_upper - t)/t = {(t_up - t) / t:.3e} > eps = {eps:g}"
    assert abs(res.error_bound - (t_up - t) * np.linalg.norm(r)) <= \
        1e-12 * max(1.0, t_up * np.linalg.norm(r)), ctx
    # vertices, weights, witnesses
    V = np.asarray(res.vertices, dtype=float)
    w = np.asarray(res.weights, dtype=float)
    assert V.ndim == 2 and V.shape[1] == n and 1 <= V.shape[0] <= n + 1, \
        f"{ctx}: vertices {V.shape}"
    assert w.shape == (V.shape[0],), ctx
    assert np.all(w >= -1e-14), f"{ctx}: weights {w}"
    assert abs(w.sum() - 1.0) <= 1e-12, f"{ctx}: sum of weights {w.sum()!r}"
    assert np.linalg.norm(w @ V - point) <= 1e-10 * max(1.0, np.linalg.norm(point)), \
        f"{ctx}: weights @ vertices = {w @ V} != point {point}"
    assert np.linalg.matrix_rank(np.hstack([V, np.ones((V.shape[0], 1))])) == V.shape[0], \
        f"{ctx}: vertices not affinely independent:\n{V}"
    assert len(res.witnesses) == V.shape[0], ctx
    for i, (v, wit) in enumerate(zip(V, res.witnesses)):
        check_witness(A, d, v, wit, what=f"{ctx} vertex {i}")
    # the supporting hyperplane
    nrm = np.asarray(res.normal, dtype=float)
    assert nrm.shape == (n,), ctx
    assert abs(np.linalg.norm(nrm) - 1.0) <= 1e-12, f"{ctx}: |normal| = {np.linalg.norm(nrm)!r}"
    nr = float(nrm @ r)
    assert nr > 0, f"{ctx}: normal . r = {nr!r} <= 0"
    h_lib = float(A.support(nrm)[0])
    h_mine = T.support(d, nrm)
    hs = max(1.0, abs(h_mine))
    assert abs(h_lib - h_mine) <= 1e-12 * hs, f"{ctx}: A.support(n) = {h_lib!r} vs {h_mine!r}"
    assert abs(float(res.support_value) - h_mine) <= 1e-12 * hs, \
        f"{ctx}: support_value = {res.support_value!r} vs h_A(n) = {h_mine!r}"
    assert h_lib - nrm @ point <= (t_up - t) * nr + 1e-12 * hs, \
        f"{ctx}: h_A(n) - n.point = {h_lib - nrm @ point:.3e} > " \
        f"(t_upper - t) n.r = {(t_up - t) * nr:.3e}"
    # independent certificate of the relative error: with the independent support function,
    # t_true <= h(n)/(n.r) and t r in A, so (t_true - t)/t <= (h(n) - n.z)/(n.z) <= eps.
    nz = float(nrm @ point)
    assert nz > 0, ctx
    assert (h_mine - nz) / nz <= eps * (1 + 1e-6) + 1e-13, \
        f"{ctx}: certified relative gap (h(n) - n.z)/(n.z) = {(h_mine - nz) / nz:.3e} > eps"


def _check_miss(A, d, r, res, method, label=""):
    r = np.asarray(r, dtype=float)
    n = r.size
    ctx = f"[{method}{' ' + label if label else ''}] r={r.tolist()} (truth: miss)"
    assert res.status == "miss", f"{ctx}: status {res.status!r} (t={res.t!r}), expected 'miss'"
    assert not res.hit, ctx
    assert res.method == method, ctx
    assert res.t == 0, ctx
    point = np.asarray(res.point, dtype=float)
    assert point.shape == (n,) and not point.any(), f"{ctx}: point {point}"
    assert np.asarray(res.vertices).size == 0, ctx
    assert np.asarray(res.weights).size == 0, ctx
    assert len(res.witnesses) == 0, ctx
    nrm = np.asarray(res.normal, dtype=float)
    assert nrm.shape == (n,) and np.all(np.isfinite(nrm)), ctx
    assert nrm @ r > 0, f"{ctx}: normal . r = {nrm @ r!r} <= 0"
    h = T.support(d, nrm)
    assert h <= 1e-12 * np.linalg.norm(nrm) * max(1.0, T.scale_of(d)), \
        f"{ctx}: h_A(normal) = {h!r} > 0: not a separating direction"


@pytest.fixture
def check_hit():
    return _check_hit


@pytest.fixture
def check_miss():
    return _check_miss


def _check_shot(A, d, r, res, truth_hit, t_true, method, exact=True, t_rtol=T_RTOL,
                t_true_upper=None, label=""):
    if truth_hit:
        _check_hit(A, d, r, res, t_true, method, exact=exact, t_rtol=t_rtol,
                   t_true_upper=t_true_upper, label=label)
    else:
        _check_miss(A, d, r, res, method, label=label)


@pytest.fixture
def check_shot():
    return _check_shot


# -- random data --------------------------------------------------------------------------------
def random_rotation(rng, n):
    Q, R = np.linalg.qr(rng.standard_normal((n, n)))
    Q = Q * np.sign(np.diag(R))
    if np.linalg.det(Q) < 0:
        Q[:, 0] = -Q[:, 0]
    return Q


def random_polytope(rng, n, m=None, shift=None):
    m = 2 * n + 6 if m is None else m
    V = rng.standard_normal((m, n))
    V -= V.mean(axis=0)
    if shift is not None:
        V += shift
    return V


def random_ellipsoid(rng, n, k=None, c_scale=0.3):
    k = n if k is None else k
    # well-conditioned shape: singular values in [0.5, 2]
    U = random_rotation(rng, n)[:, :k]
    W = random_rotation(rng, k)
    s = rng.uniform(0.5, 2.0, size=k)
    S = U @ np.diag(s) @ W.T
    c = c_scale * rng.standard_normal(n)
    return c, S


# -- the service: one real server for the session's service tests -------------------------------
@pytest.fixture(scope="session")
def served():
    """The base URL of a service started as `python -m graspforce serve` on a loopback port (the
    command the Dockerfile runs), stopped after the session. Skipped without the service's
    packages (the `service` or `test` extra)."""
    pytest.importorskip("fastapi")
    pytest.importorskip("uvicorn")
    httpx = pytest.importorskip("httpx")
    import subprocess
    import time

    from benchmarks.service import free_port, stop
    port = free_port()
    env = {**os.environ, "GRASPFORCE_THREADS": "2"}
    for name in ("GRASPFORCE_TOKEN", "GRASPFORCE_CORS_ORIGINS", "GRASPFORCE_MAX_BODY_BYTES",
                 "GRASPFORCE_MAX_CONTACTS", "GRASPFORCE_MAX_BATCH", "GRASPFORCE_MAX_SET_LEAVES"):
        env.pop(name, None)
    proc = subprocess.Popen([sys.executable, "-m", "graspforce", "serve", "--port", str(port)],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    url = f"http://127.0.0.1:{port}"
    deadline = time.monotonic() + 60
    try:
        while True:
            if proc.poll() is not None:
                raise RuntimeError("the server exited: " + proc.stdout.read().decode())
            try:
                if httpx.get(url + "/readyz", timeout=1).status_code == 200:
                    break
            except httpx.TransportError:
                pass
            if time.monotonic() > deadline:
                raise RuntimeError("the server was not ready within 60 s")
            time.sleep(0.05)
        yield url
    finally:
        stop(proc)
