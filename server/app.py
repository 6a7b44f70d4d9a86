"""The graspforce service: FastAPI routes that validate a request, turn it into library objects,
run the library off the event loop and send its record back as JSON. No mathematics here.

Solves run on a pool of GRASPFORCE_THREADS threads; the compiled core releases the GIL, so one
worker process serves concurrent requests. The compiled support kernel writes scratch into a
set's program arrays, so a grasp (and its wrench sets) must not be shot at by two threads at
once: each pool thread keeps its own cache of grasps (threading.local), and sets for ray
shooting and growth distance are built per request.
"""
import asyncio
import gc
import hmac
import json
import queue
import re
import threading
import time
from collections import OrderedDict
from contextlib import asynccontextmanager

import numpy as np
from fastapi import Depends, FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.openapi.docs import get_swagger_ui_html
from fastapi.responses import JSONResponse, Response
from fastapi.staticfiles import StaticFiles
from pydantic_core import to_json
from starlette.exceptions import HTTPException as StarletteHTTPException

import graspforce as gf
from graspforce.serialize import set_from_dict
from graspforce.batch.wrenches import gaussian

from . import models as M
from . import settings as S

GRASP_CACHE = 64           # grasps kept per pool thread


class InputError(Exception):
    """A request that passed the models but broke a library rule: 422 at `loc`."""

    def __init__(self, loc, message):
        super().__init__(message)
        self.loc, self.message = loc, message


def _loc_of(message, prefix=()):
    """["body", *prefix, *path] from a library message "a.b[2].c: rule"."""
    field, sep, _ = message.partition(": ")
    path = []
    if sep and re.fullmatch(r"[A-Za-z_][\w.\[\] ]*", field):
        for part in re.split(r"\.|\[|\]", field.split(" ")[0]):
            if part:
                path.append(int(part) if part.isdigit() else part)
    return ["body", *prefix, *path]


def _library(call, *args, prefix=(), rename=None):
    """call(*args), a library error becoming an InputError that names its field."""
    try:
        return call(*args)
    except (ValueError, TypeError) as error:
        message = str(error)
        if rename:
            for old, new in rename.items():
                if message.startswith(old + ":"):
                    message = new + message[len(old):]
        raise InputError(_loc_of(message, prefix), message) from None


# -- grasps, one cache per pool thread ----------------------------------------------------------
_local = threading.local()


def _contact_key(c):
    return (*c.position, *c.normal, c.mu, c.mu_spin,
            *(() if c.tangents is None else (*c.tangents[0], *c.tangents[1])))


def grasp_of(contacts, length=None):
    """The gf.Grasp of these contact models (and characteristic length), from this thread's
    cache when seen before, reset so that its answer is the one a new grasp would give
    (Grasp.reset_start_tables)."""
    cache = getattr(_local, "grasps", None)
    if cache is None:
        cache = _local.grasps = OrderedDict()
    key = (length, *(_contact_key(c) for c in contacts))
    grasp = cache.get(key)
    if grasp is not None:
        cache.move_to_end(key)
        grasp.reset_start_tables()
        return grasp
    built = [_library(gf.Contact, c.position, c.normal, c.mu, c.mu_spin, c.tangents,
                      prefix=("contacts", i)) for i, c in enumerate(contacts)]
    grasp = cache[key] = _library(gf.Grasp, built, length)
    if len(cache) > GRASP_CACHE:
        cache.popitem(last=False)
    return grasp


def _json(content, status_code=200):
    # pydantic's encoder: its shortest floats cost a fifth of json.dumps's (an answer's 60
    # numbers: 30 -> 5 us). A NaN or inf that escaped the records is a bug to see, never a
    # response: json.dumps with allow_nan=False then raises as it would have
    body = to_json(content)
    if b"NaN" in body or b"Infinity" in body:
        body = json.dumps(content, allow_nan=False, separators=(",", ":")).encode()
    return Response(body, status_code=status_code, media_type="application/json")


# -- the solves, run on the pool ------------------------------------------------------------------
def solve_force_optimization(body: M.ForceOptimizationIn):
    grasp = grasp_of(body.contacts, body.length)
    w = np.array(body.w_ext)
    start = time.perf_counter()
    res = grasp.min_force(w, norm=body.norm, magnitude=body.magnitude, method=body.method,
                          eps=body.eps, max_iter=body.max_iter)
    out = res.to_dict()
    out["seconds"] = time.perf_counter() - start
    out["compare"] = None
    if body.compare:
        from graspforce.grasping.baselines.compare import compare
        out["compare"] = compare(grasp, w, res, body.compare, body.norm, body.magnitude)
    return _json(out)


def solve_batch(body: M.BatchIn):
    grasp = grasp_of(body.contacts, body.length)
    if body.wrenches is not None:
        W = np.array(body.wrenches)
    else:
        s = body.sample
        W = _library(gaussian, s.count, 0.0 if s.mean is None else s.mean,
                     [s.force_scale] * 3 + [s.torque_scale] * 3, s.seed, prefix=("sample",))
    start = time.perf_counter()
    res = grasp.min_force_batch(W, norm=body.norm, magnitude=body.magnitude,
                                method=body.method, eps=body.eps, max_iter=body.max_iter,
                                forces=body.forces)
    if body.sample is not None:
        res.wrenches = W
    out = res.to_dict()
    out["seconds"] = time.perf_counter() - start
    return _json(out)


def solve_force_closure(body: M.ForceClosureIn):
    grasp = grasp_of(body.contacts, body.length)
    closure = grasp.is_force_closure(tol=body.tol)
    quality = None
    if body.quality:
        quality = grasp.quality(norm=body.norm, magnitude=body.magnitude, eps=body.eps,
                                tol=body.tol, max_iter=body.max_iter).to_dict()
    return _json({"force_closure": bool(closure), "quality": quality})


def solve_ray_shoot(body: M.RayShootIn):
    A = _library(set_from_dict, body.set.model_dump(), "set")
    res = _library(gf.ray_shoot, A, np.array(body.r), body.method, body.eps, body.max_iter)
    return _json(res.to_dict())


def solve_growth_distance(body: M.GrowthDistanceIn):
    A = _library(set_from_dict, body.a.model_dump(), "a")
    B = _library(set_from_dict, body.b.model_dump(), "b")
    # the class rather than gf.growth_distance, whose cache of recent pairs is for sets used
    # again: these are this request's own
    solver = _library(gf.GrowthDistance, A, B, body.method, body.eps, body.max_iter,
                      body.touching_tol, False, rename={"A": "a", "B": "b"})
    pose_a = (np.array(body.pose_a.rotation), np.array(body.pose_a.translation))
    pose_b = (np.array(body.pose_b.rotation), np.array(body.pose_b.translation))
    res = _library(solver, pose_a, pose_b)
    return _json(res.to_dict())


# -- robots: one scenario cache per pool thread (a scenario's grasp and Pinocchio data are written
# by its solves) and one lock for matplotlib, whose pyplot state is global ----------------------
_plot_lock = threading.Lock()
_pictures = {}


def scenario_of(name):
    import graspforce.robots as robots
    cache = getattr(_local, "scenarios", None)
    if cache is None:
        cache = _local.scenarios = {}
    scenario = cache.get(name)
    if scenario is None:
        scenario = cache[name] = robots.load_scenario(name)
    scenario.grasp.reset_start_tables()
    return scenario


def robot_list():
    import graspforce.robots as robots
    out = []
    for name in robots.list_scenarios():
        s = scenario_of(name)
        out.append({"name": name, "description": s.description, "robot": s.spec.robot,
                    "floating_base": bool(s.floating), "contacts": len(s.grasp)})
    return _json(out)


def robot_detail(name):
    return _json(scenario_of(name).to_dict())


def robot_forces(name, body: M.RobotForceIn):
    scenario = scenario_of(name)
    if body.configuration is not None:
        scenario = _library(scenario.with_configuration, np.array(body.configuration),
                            rename={"q": "configuration"})
    v = a = None
    if body.motion is not None:
        v = None if body.motion.v is None else np.array(body.motion.v)
        a = None if body.motion.a is None else np.array(body.motion.a)
        if v is None and a is None:
            raise InputError(["body", "motion"], "motion: give v, a or both")
    w = None if body.w_ext is None else np.array(body.w_ext)
    res = _library(scenario.solve, body.norm, body.magnitude, body.method, body.eps, w, v, a,
                   rename={"centroidal_wrench": "motion", "v": "motion.v", "a": "motion.a"})
    return _json(res.to_dict())


def robot_picture(name):
    import os
    import tempfile
    with _plot_lock:
        png = _pictures.get(name)
        if png is None:
            with tempfile.TemporaryDirectory() as folder:
                path = os.path.join(folder, f"{name}.png")
                scenario_of(name).plot(path)
                with open(path, "rb") as f:
                    png = _pictures[name] = f.read()
    return Response(png, media_type="image/png")


def robots_available():
    """The shipped scenario names, or None without the robots' packages (pin,
    example-robot-data)."""
    try:
        import graspforce.robots as robots
        import pinocchio  # noqa: F401
    except ImportError:
        return None
    return robots.list_scenarios()


# -- the app --------------------------------------------------------------------------------------
class BodyLimit:
    """Refuses a request body over `limit` bytes with 413, from its Content-Length before
    reading it, or as soon as a streamed body passes the limit."""

    def __init__(self, app, limit):
        self.app, self.limit = app, limit

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        for name, value in scope["headers"]:
            if name == b"content-length":
                try:
                    too_big = int(value) > self.limit
                except ValueError:
                    too_big = False
                if too_big:
                    return await self._refuse(send)
        seen = 0
        refused = False

        async def counted():
            nonlocal seen, refused
            message = await receive()
            if message["type"] == "http.request":
                seen += len(message.get("body", b""))
                if seen > self.limit:
                    refused = True
                    raise _TooLarge()
            return message

        try:
            await self.app(scope, counted, send)
        except _TooLarge:
            if refused:
                await self._refuse(send)

    async def _refuse(self, send):
        body = json.dumps({"detail": f"request body exceeds {self.limit} bytes "
                                     "(GRASPFORCE_MAX_BODY_BYTES)"}).encode()
        await send({"type": "http.response.start", "status": 413,
                    "headers": [(b"content-type", b"application/json"),
                                (b"content-length", str(len(body)).encode())]})
        await send({"type": "http.response.body", "body": body})


class _TooLarge(Exception):
    pass


class SolverPool:
    """`threads` threads that run the solves, fed by one queue; a result reaches the awaiting
    request by call_soon_threadsafe. loop.run_in_executor's futures (a concurrent.futures.Future
    with its lock and condition, chained to an asyncio one) cost ~14 us of CPU a request against
    ~2 us here."""

    def __init__(self, threads):
        self._jobs = queue.SimpleQueue()
        self._size = threads
        self._threads = []

    def run(self, fn, arg):
        """An awaitable of fn(arg), run on a pool thread (the threads start at the first)."""
        if not self._threads:
            self._threads = [threading.Thread(target=self._work, name=f"graspforce-{i}",
                                              daemon=True) for i in range(self._size)]
            for thread in self._threads:
                thread.start()
        loop = asyncio.get_running_loop()
        future = loop.create_future()
        self._jobs.put((loop, future, fn, arg))
        return future

    def shutdown(self):
        for _ in self._threads:
            self._jobs.put(None)
        self._threads = []

    def _work(self):
        while (job := self._jobs.get()) is not None:
            loop, future, fn, arg = job
            try:
                result = fn(arg)
            except BaseException as error:            # the request's, raised where it awaits
                loop.call_soon_threadsafe(_settle, future, None, error)
            else:
                loop.call_soon_threadsafe(_settle, future, result, None)


def _settle(future, result, error):
    if future.done():                                 # the request was cancelled meanwhile
        return
    if error is None:
        future.set_result(result)
    else:
        future.set_exception(error)


ERRORS = {422: {"description": "Invalid input: each error names its field (loc) and the rule "
                               "(msg)"},
          413: {"model": M.ErrorOut, "description": "Request body too large"}}


def create_app(settings=None):
    """The FastAPI app with `settings` (default: from the environment, server.settings)."""
    settings = settings or S.Settings.from_env()
    S.current = settings
    pool = SolverPool(settings.threads)
    state = {"ready": False}

    @asynccontextmanager
    async def lifespan(app):
        # one answer from the compiled core on each pool thread before /readyz says ready
        warm = M.ForceOptimizationIn.model_validate(
            M.ForceOptimizationIn.model_config["json_schema_extra"]["examples"][0])
        await asyncio.gather(*(pool.run(solve_force_optimization, warm)
                               for _ in range(settings.threads)))
        # the scenarios are readable (the files; each is loaded on first use)
        import graspforce.robots as robots
        for name in scenarios or ():
            robots.scenario_path(name).read_bytes()
        # the objects made so far (the modules, the warm grasps) live as long as the process:
        # kept out of the collector's scans, which per request walked them all (~15% of a
        # loaded server's CPU in gc_collect_main)
        gc.freeze()
        state["ready"] = True
        yield
        pool.shutdown()

    app = FastAPI(title="graspforce", version=gf_version(), lifespan=lifespan,
                  docs_url=None, redoc_url=None,
                  description="Exact grasp and contact analysis by ray shooting (Zheng & "
                              "Yamane): minimal contact forces on exact friction cones, force "
                              "closure, growth distance. JSON in and out; infinite numbers are "
                              "null.")

    run = pool.run

    # async: FastAPI runs a plain function dependency on its own thread pool, a second hop per
    # request for a header comparison
    async def authorized(request: Request):
        header = request.headers.get("authorization", "")
        if not hmac.compare_digest(header.encode(), f"Bearer {settings.token}".encode()):
            raise _Unauthorized()

    # without a token, no dependency: one that returns at once still costs a request FastAPI's
    # resolving of it
    v1 = [] if settings.token is None else [Depends(authorized)]
    errors = dict(ERRORS)
    if settings.token is not None:
        errors[401] = {"model": M.ErrorOut, "description": "Missing or wrong bearer token"}

    @app.exception_handler(_Unauthorized)
    async def _unauthorized(request, exc):
        return JSONResponse({"detail": "a bearer token is required (GRASPFORCE_TOKEN)"}, 401,
                            headers={"WWW-Authenticate": "Bearer"})

    @app.exception_handler(RequestValidationError)
    async def _invalid(request, exc):
        # the loc, msg and type of each error: the input itself is not echoed (it may be NaN,
        # which JSON cannot carry, or megabytes)
        return _json({"detail": [{"loc": list(e.get("loc", ())), "msg": e.get("msg", ""),
                                  "type": e.get("type", "")} for e in exc.errors()]}, 422)

    @app.exception_handler(StarletteHTTPException)
    async def _http(request, exc):
        # FastAPI answers a body it cannot decode (not UTF-8, not JSON) with 400: bad input,
        # which this service always reports as a 422 naming the body
        if exc.status_code == 400:
            return _json({"detail": [{"loc": ["body"], "msg": f"the body must be UTF-8 JSON: "
                                      f"{exc.detail}", "type": "json_invalid"}]}, 422)
        return JSONResponse({"detail": exc.detail}, exc.status_code,
                            headers=getattr(exc, "headers", None))

    @app.exception_handler(ArithmeticError)
    async def _arithmetic(request, exc):
        # numbers the models allow but whose products overflow: bad input, not a crash
        return _json({"detail": [{"loc": ["body"], "msg": f"numbers out of range for this "
                                  f"problem ({exc}); rescale them", "type": "value_error"}]},
                     422)

    @app.exception_handler(InputError)
    async def _input(request, exc):
        return _json({"detail": [{"loc": exc.loc, "msg": exc.message, "type": "value_error"}]},
                     422)

    @app.get("/healthz", response_model=M.Health, tags=["service"])
    async def healthz():
        """Alive: the process answers."""
        return {"status": "ok"}

    @app.get("/readyz", response_model=M.Ready, tags=["service"],
             responses={503: {"model": M.Ready, "description": "Not ready yet"}})
    async def readyz():
        """Ready: the compiled core is loaded and has answered on every solver thread."""
        if not state["ready"]:
            return JSONResponse({"status": "starting", "core": "loading",
                                 "threads": settings.threads}, 503)
        return {"status": "ready", "core": "loaded", "threads": settings.threads}

    @app.post("/v1/force-optimization", response_model=M.ForceOptimizationOut,
              responses=errors, dependencies=v1, tags=["grasps"])
    async def force_optimization(body: M.ForceOptimizationIn):
        """Minimal contact forces in the exact friction cones that resist w_ext
        (Grasp.min_force), certified: the minimum lies in [sigma_lower, sigma]. `compare`
        adds Clarabel's SOCP and OSQP's linearized pyramid on the same problem."""
        return await run(solve_force_optimization, body)

    @app.post("/v1/force-optimization/batch", response_model=M.BatchOut, responses=errors,
              dependencies=v1, tags=["grasps"])
    async def force_optimization_batch(body: M.BatchIn):
        """min_force for one grasp and many wrenches, given or drawn from a seeded normal
        distribution (Grasp.min_force_batch)."""
        return await run(solve_batch, body)

    @app.post("/v1/force-closure", response_model=M.ForceClosureOut, responses=errors,
              dependencies=v1, tags=["grasps"])
    async def force_closure(body: M.ForceClosureIn):
        """Force closure (Grasp.is_force_closure) and the bracketed Ferrari-Canny quality
        (Grasp.quality)."""
        return await run(solve_force_closure, body)

    @app.post("/v1/ray-shoot", response_model=M.RayShotOut, responses=errors,
              dependencies=v1, tags=["core"])
    async def ray_shoot(body: M.RayShootIn):
        """The farthest point of a convex set on a ray, with its certificate (gf.ray_shoot)."""
        return await run(solve_ray_shoot, body)

    @app.post("/v1/growth-distance", response_model=M.GrowthDistanceOut, responses=errors,
              dependencies=v1, tags=["core"])
    async def growth_distance(body: M.GrowthDistanceIn):
        """The growth distance of two posed 3-D shapes, the contact points and normal
        (gf.growth_distance)."""
        return await run(solve_growth_distance, body)

    scenarios = robots_available()
    if scenarios:
        import enum
        from fastapi import Path
        # a name is one of the shipped scenarios, never a file path: anything else is a 422
        Scenario = enum.Enum("Scenario", {n: n for n in scenarios}, type=str)
        # {name:path} so that a name with slashes reaches the check instead of missing a route
        NameParam = Path(description="a shipped scenario")

        @app.get("/v1/robots", response_model=list[M.RobotSummary], dependencies=v1,
                 responses=errors, tags=["robots"])
        async def robots():
            """The shipped scenarios (graspforce.robots.list_scenarios)."""
            return await run(lambda _: robot_list(), None)

        @app.get("/v1/robots/{name:path}/picture.png", dependencies=v1, tags=["robots"],
                 response_class=Response, responses={
                     **errors, 200: {"content": {"image/png": {}},
                                     "description": "The scenario's plot (Scenario.plot)"}})
        async def robot_png(name: Scenario = NameParam):
            """The scenario's skeleton, contacts, friction cones and optimal forces."""
            return await run(robot_picture, name.value)

        @app.post("/v1/robots/{name:path}/force-optimization", dependencies=v1,
                  response_model=M.RobotForcesOut, responses=errors, tags=["robots"])
        async def robot_force_optimization(body: M.RobotForceIn, name: Scenario = NameParam):
            """Minimal contact forces and joint torques for a scenario (Scenario.solve), at its
            configuration or another, for its load, a given wrench or a motion sample."""
            return await run(lambda b: robot_forces(name.value, b), body)

        @app.get("/v1/robots/{name:path}", response_model=M.RobotOut, dependencies=v1,
                 responses=errors, tags=["robots"])
        async def robot(name: Scenario = NameParam):
            """A scenario: robot, configuration, load and contacts (Scenario.to_dict)."""
            return await run(robot_detail, name.value)

    # Swagger UI from the app's own copy of its files: /docs works without the internet
    import swagger_ui_bundle
    app.mount("/static/swagger-ui", StaticFiles(directory=swagger_ui_bundle.swagger_ui_path),
              name="swagger-ui")

    @app.get("/docs", include_in_schema=False)
    async def docs():
        return get_swagger_ui_html(openapi_url=app.openapi_url, title="graspforce API",
                                   swagger_js_url="/static/swagger-ui/swagger-ui-bundle.js",
                                   swagger_css_url="/static/swagger-ui/swagger-ui.css",
                                   swagger_favicon_url="/static/swagger-ui/favicon-32x32.png")

    if settings.cors_origins:
        from fastapi.middleware.cors import CORSMiddleware
        app.add_middleware(CORSMiddleware, allow_origins=list(settings.cors_origins),
                           allow_methods=["GET", "POST"],
                           allow_headers=["Authorization", "Content-Type"])
    app.add_middleware(BodyLimit, limit=settings.max_body_bytes)
    app.state.settings = settings
    return app


class _Unauthorized(Exception):
    pass


def gf_version():
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("graspforce")
    except PackageNotFoundError:
        return "0"
