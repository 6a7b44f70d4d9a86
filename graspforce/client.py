"""graspforce.client.Client: the library's calls answered by a graspforce service (server/).

    client = Client("http://127.0.0.1:8000", timeout=10.0)
    res = client.min_force(grasp, w_ext, norm="L1")      # a gf.MinForce, as grasp.min_force(...)

Each method takes the library's objects (gf.Grasp, convex sets, poses) and returns the library's
record, rebuilt from the service's JSON by the record's from_dict: the same numbers as the local
call (floats cross JSON exactly), without the `shot` certificate object. Every request is a pure
computation, so a request that failed to connect, timed out or met a 502/503/504 is sent again,
up to `retries` times. A 422 or 413 raises ValueError with the service's message (field and
rule), as the library would; a 401 raises PermissionError. Needs httpx (the `service` extra).
"""
import time

import numpy as np

from .records.results import GraspQuality, GrowthDistanceResult, MinForce, MinForceBatch, RayShot
from .serialize import grasp_to_dict, pose_to_dict, set_to_dict

_RETRY_STATUS = (502, 503, 504)


class Client:
    """A graspforce service at base_url; token: the bearer token if the service asks for one
    (GRASPFORCE_TOKEN)."""

    def __init__(self, base_url="http://127.0.0.1:8000", timeout=10.0, retries=2, token=None,
                 backoff=0.1):
        import httpx
        headers = {"Authorization": f"Bearer {token}"} if token else {}
        self._http = httpx.Client(base_url=base_url, timeout=timeout, headers=headers)
        self._errors = (httpx.TransportError,)
        self.retries, self.backoff = int(retries), float(backoff)

    def close(self):
        self._http.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _request(self, method, path, body=None):
        for attempt in range(self.retries + 1):
            last = attempt == self.retries
            try:
                response = self._http.request(method, path, json=body)
            except self._errors:
                if last:
                    raise
            else:
                if response.status_code not in _RETRY_STATUS or last:
                    return _answer(response)
            time.sleep(self.backoff * 2 ** attempt)

    # -- the library's calls ------------------------------------------------------------------
    def min_force(self, grasp, w_ext, norm="L1", magnitude="normal", method="zc-ie", eps=1e-9,
                  max_iter=10000):
        """gf.MinForce, as grasp.min_force(w_ext, ...)."""
        d = self._request("POST", "/v1/force-optimization", {
            **grasp_to_dict(grasp), "w_ext": _list(w_ext), "norm": norm,
            "magnitude": magnitude, "method": method, "eps": eps, "max_iter": max_iter})
        return MinForce.from_dict(d)

    def compare(self, grasp, w_ext, solvers=("clarabel", "osqp"), norm="L1",
                magnitude="normal", method="zc-ie", eps=1e-9):
        """(gf.MinForce, rows): ours and the baselines' answers
        (graspforce.grasping.baselines.compare)."""
        d = self._request("POST", "/v1/force-optimization", {
            **grasp_to_dict(grasp), "w_ext": _list(w_ext), "norm": norm,
            "magnitude": magnitude, "method": method, "eps": eps, "compare": list(solvers)})
        return MinForce.from_dict(d), d["compare"]

    def min_force_batch(self, grasp, wrenches=None, norm="L1", magnitude="normal",
                        method="zc-ie", eps=1e-9, max_iter=10000, forces=False, sample=None):
        """gf.MinForceBatch, as grasp.min_force_batch(wrenches, ...); or, with sample = dict
        {count, seed, force_scale, torque_scale, mean}, for the wrenches the service draws by
        graspforce.batch.wrenches.gaussian (returned in .wrenches)."""
        body = {**grasp_to_dict(grasp), "norm": norm, "magnitude": magnitude, "method": method,
                "eps": eps, "max_iter": max_iter, "forces": bool(forces)}
        if sample is not None:
            body["sample"] = {k: _list(v) if k == "mean" and v is not None else v
                              for k, v in dict(sample).items()}
        else:
            body["wrenches"] = np.asarray(wrenches, dtype=float).tolist()
        return MinForceBatch.from_dict(self._request("POST", "/v1/force-optimization/batch",
                                                     body))

    def is_force_closure(self, grasp, tol=1e-9):
        """bool, as grasp.is_force_closure(tol)."""
        d = self._request("POST", "/v1/force-closure",
                          {**grasp_to_dict(grasp), "quality": False, "tol": tol})
        return bool(d["force_closure"])

    def quality(self, grasp, norm="L1", magnitude="normal", eps=1e-3, tol=1e-9, max_iter=500):
        """gf.GraspQuality, as grasp.quality(...)."""
        d = self._request("POST", "/v1/force-closure", {
            **grasp_to_dict(grasp), "quality": True, "norm": norm, "magnitude": magnitude,
            "eps": eps, "tol": tol, "max_iter": max_iter})
        return GraspQuality.from_dict(d["quality"])

    def ray_shoot(self, A, r, method="zc-ie", eps=1e-9, max_iter=10000):
        """gf.RayShot, as gf.ray_shoot(A, r, ...); its convex_set is A."""
        d = self._request("POST", "/v1/ray-shoot", {
            "set": set_to_dict(A), "r": _list(r), "method": method, "eps": eps,
            "max_iter": max_iter})
        return RayShot.from_dict(d, convex_set=A)

    def growth_distance(self, A, pose_a, B, pose_b, method="zc-ie", eps=1e-9, max_iter=10000,
                        touching_tol=1e-9):
        """gf.GrowthDistanceResult, as gf.growth_distance(A, pose_a, B, pose_b, ...)."""
        d = self._request("POST", "/v1/growth-distance", {
            "a": set_to_dict(A), "pose_a": pose_to_dict(pose_a, "pose_a"), "b": set_to_dict(B),
            "pose_b": pose_to_dict(pose_b, "pose_b"), "method": method, "eps": eps,
            "max_iter": max_iter, "touching_tol": touching_tol})
        return GrowthDistanceResult.from_dict(d)

    def robots(self):
        """The shipped scenarios: [{name, description, robot, floating_base, contacts}], as
        gf.robots.list_scenarios() with each scenario's summary."""
        return self._request("GET", "/v1/robots")

    def robot(self, name):
        """A scenario's Scenario.to_dict(): robot, configuration, load, contacts."""
        return self._request("GET", f"/v1/robots/{name}")

    def robot_forces(self, name, norm="L1", magnitude="normal", method="zc-ie", eps=1e-9,
                     configuration=None, w_ext=None, v=None, a=None):
        """RobotForces.to_dict() of gf.robots.load_scenario(name) (at `configuration` if
        given).solve(...), with its "record" rebuilt as a gf.MinForce."""
        body = {"norm": norm, "magnitude": magnitude, "method": method, "eps": eps}
        if configuration is not None:
            body["configuration"] = _list(configuration)
        if w_ext is not None:
            body["w_ext"] = _list(w_ext)
        if v is not None or a is not None:
            body["motion"] = {"v": None if v is None else _list(v),
                              "a": None if a is None else _list(a)}
        d = self._request("POST", f"/v1/robots/{name}/force-optimization", body)
        d["record"] = MinForce.from_dict(d["record"])
        return d

    def robot_picture(self, name):
        """The PNG bytes of Scenario.plot."""
        for attempt in range(self.retries + 1):
            response = self._http.get(f"/v1/robots/{name}/picture.png")
            if response.status_code not in _RETRY_STATUS or attempt == self.retries:
                break
        if response.status_code != 200:
            _answer(response)
        return response.content

    def healthz(self):
        return self._request("GET", "/healthz")

    def readyz(self):
        return self._request("GET", "/readyz")


def _list(x):
    return np.asarray(x, dtype=float).tolist()


def _answer(response):
    """The JSON of a 2xx response; the library's exception for a refused request."""
    code = response.status_code
    if code < 300:
        return response.json()
    try:
        detail = response.json().get("detail")
    except ValueError:
        detail = response.text
    if code in (413, 422):
        if isinstance(detail, list):
            detail = "; ".join(f"{'.'.join(str(p) for p in e['loc'][1:])}: {e['msg']}"
                               for e in detail)
        raise ValueError(detail)
    if code == 401:
        raise PermissionError(detail)
    response.raise_for_status()
    raise RuntimeError(f"unexpected status {code}: {detail}")
