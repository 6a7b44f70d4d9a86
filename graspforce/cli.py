"""The `graspforce` command (also `python -m graspforce`).

    graspforce serve [--host 127.0.0.1] [--port 8000] [--workers 1]   the service (server/)
    graspforce optimize PROBLEM [--check]         minimal contact forces of a shipped scenario
                                                  (graspforce robots) or a JSON problem file
    graspforce robots                             the shipped robot scenarios
    graspforce warmup                             load the compiled core, one answer per method
    graspforce demo                               the four-finger demo
    graspforce bench [--count N]                  time min_force on the demo grasp

Exit codes: 0 answered; 1 infeasible (optimize --check); 2 bad input (a missing or malformed
problem file, an argument out of range, a missing optional dependency).
"""
import argparse
import json
import sys
import time

OK, INFEASIBLE, BAD_INPUT = 0, 1, 2


def warmup():
    """One answer from every procedure and every entry point; returns the seconds it took.
    Loads the compiled core, so that a container image or a new worker fails at build time,
    not at its first request, if the core is missing or broken."""
    start = time.perf_counter()
    import numpy as np

    import graspforce as gf
    A = gf.Polytope(np.eye(3))
    for method in gf.METHODS:
        if not gf.ray_shoot(A, [1.0, 1.0, 1.0], method=method).hit:
            raise RuntimeError(f"warmup: {method} missed a ray that meets the set")
    gf.closest_point(A, [2.0, 2.0, 2.0])
    gf.cone_distance(A, [1.0, 1.0, 1.0])
    grasp = gf.Grasp([gf.Contact([0.05, 0, 0], [-1, 0, 0], 0.5, 0.01),
                      gf.Contact([-0.05, 0, 0], [1, 0, 0], 0.5, 0.01)])
    for norm in ("L1", "Linf"):
        if grasp.min_force([0, 0, -1.0, 0, 0, 0], norm=norm).status != "optimal":
            raise RuntimeError(f"warmup: min_force {norm} found no optimal forces")
    gf.growth_distance(gf.Ball(np.zeros(3), 1.0), (np.eye(3), np.zeros(3)),
                       gf.Ball(np.zeros(3), 1.0), (np.eye(3), np.array([3.0, 0, 0])))
    return time.perf_counter() - start


def optimize_problem(problem):
    """The gf.MinForce of a problem dict: the body of POST /v1/force-optimization (contacts,
    w_ext, and optionally norm, magnitude, method, eps, max_iter)."""
    from .serialize import grasp_from_dict
    if not isinstance(problem, dict):
        raise ValueError("problem: expected a JSON object with contacts and w_ext")
    known = {"contacts", "w_ext", "norm", "magnitude", "method", "eps", "max_iter"}
    unknown = sorted(set(problem) - known)
    if unknown:
        raise ValueError(f"{unknown[0]}: unknown field (known: {sorted(known)})")
    if "w_ext" not in problem:
        raise ValueError("w_ext: required, the external wrench (6 numbers)")
    grasp = grasp_from_dict(problem)
    options = {k: problem[k] for k in ("norm", "magnitude", "method", "eps", "max_iter")
               if k in problem}
    return grasp.min_force(problem["w_ext"], **options)


def _serve(args):
    try:
        import uvicorn
        import fastapi  # noqa: F401
    except ImportError as missing:
        print(f"graspforce serve: {missing.name} is not installed; "
              'pip install -e ".[service]"', file=sys.stderr)
        return BAD_INPUT
    # the app by its import path (server/ is its own package: the library does not import it)
    uvicorn.run("server.app:create_app", factory=True, host=args.host, port=args.port,
                workers=args.workers, log_level=args.log_level)
    return OK


def _scenarios():
    """The shipped scenario names, or None without the robots' packages."""
    try:
        from . import robots
        import pinocchio  # noqa: F401
    except ImportError:
        return None
    return robots.list_scenarios()


def _robots(args):
    names = _scenarios()
    if names is None:
        print('graspforce robots: the robots extra is not installed; pip install -e ".[robots]"',
              file=sys.stderr)
        return BAD_INPUT
    from . import robots
    for name in names:
        s = robots.load_scenario(name)
        print(f"{name:24s} {len(s.grasp):2d} contacts  {s.description}")
    return OK


def _optimize(args):
    if args.problem in (_scenarios() or ()):
        from . import robots
        res = robots.load_scenario(args.problem).solve()
        print(json.dumps(res.to_dict(), indent=None if args.compact else 2))
        return INFEASIBLE if args.check and not res.record.feasible else OK
    try:
        text = sys.stdin.read() if args.problem == "-" else open(args.problem).read()
    except OSError as error:
        print(f"graspforce optimize: problem: cannot read {args.problem}: {error.strerror}",
              file=sys.stderr)
        return BAD_INPUT
    try:
        problem = json.loads(text)
    except ValueError as error:
        print(f"graspforce optimize: problem: not valid JSON ({error})", file=sys.stderr)
        return BAD_INPUT
    try:
        res = optimize_problem(problem)
    except (ValueError, TypeError) as error:
        print(f"graspforce optimize: {error}", file=sys.stderr)
        return BAD_INPUT
    print(json.dumps(res.to_dict(), indent=None if args.compact else 2))
    return INFEASIBLE if args.check and not res.feasible else OK


def _bench(args):
    import numpy as np

    import graspforce as gf
    from .demo import box_grasp
    from .batch.wrenches import gaussian
    grasp = box_grasp()
    W = gaussian(args.count, [0, 0, -9.81, 0, 0, 0], [3.0] * 3 + [0.05] * 3, seed=1)
    print(f"min_force, 4 soft fingers, {args.count} wrenches; microseconds a call")
    print(f"{'method':14s} {'p50':>8s} {'p99':>8s} {'iterations':>10s}")
    for method in gf.METHODS:
        grasp.min_force(W[0], method=method)
        times, iterations = np.empty(len(W)), 0
        for i, w in enumerate(W):
            start = time.perf_counter()
            res = grasp.min_force(w, method=method)
            times[i] = time.perf_counter() - start
            iterations += res.iterations
        p50, p99 = np.percentile(times, [50, 99]) * 1e6
        print(f"{method:14s} {p50:8.1f} {p99:8.1f} {iterations / len(W):10.1f}")
    start = time.perf_counter()
    grasp.min_force_batch(W)
    print(f"min_force_batch of {len(W)}: {(time.perf_counter() - start) * 1e3:.1f} ms")
    return OK


def parser():
    p = argparse.ArgumentParser(prog="graspforce", description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    s = sub.add_parser("serve", help="run the service (FastAPI on uvicorn)",
                       description="Run the service; see README.md for its environment "
                                   "variables (token, CORS, limits).")
    s.add_argument("--host", default="127.0.0.1", help="address to bind (default 127.0.0.1)")
    s.add_argument("--port", type=_port, default=8000, help="port (default 8000)")
    s.add_argument("--workers", type=_positive, default=1, help="worker processes (default 1)")
    s.add_argument("--log-level", default="warning",
                   choices=["critical", "error", "warning", "info", "debug"])
    o = sub.add_parser("optimize", help="minimal contact forces of a scenario or a problem file",
                       description="Minimal contact forces of a shipped scenario (a name from "
                                   "`graspforce robots`: prints its RobotForces as JSON) or of "
                                   "a JSON file ('-' for stdin) holding the body of POST "
                                   "/v1/force-optimization (prints the MinForce record).")
    o.add_argument("problem", help="scenario name, JSON problem file, or - for stdin")
    o.add_argument("--check", action="store_true", help="exit 1 if the wrench cannot be resisted")
    o.add_argument("--compact", action="store_true", help="one line of JSON")
    sub.add_parser("robots", help="list the shipped robot scenarios")
    sub.add_parser("warmup", help="load the compiled core and answer one problem per method")
    sub.add_parser("demo", help="minimal contact forces for a four-finger grasp")
    b = sub.add_parser("bench", help="time min_force on the demo grasp")
    b.add_argument("--count", type=_positive, default=2000, help="wrenches (default 2000)")
    from .batch.cli import add_batch_parser
    from .batch.plot import add_plot_parser
    add_batch_parser(sub)
    add_plot_parser(sub)
    return p


def _positive(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {value}")
    return value


def _port(text):
    value = _positive(text)
    if value > 65535:
        raise argparse.ArgumentTypeError(f"must be a port number (1-65535), got {value}")
    return value


def main(argv=None):
    try:
        args = parser().parse_args(argv)
    except SystemExit as done:       # argparse: 0 after --help, 2 for a bad argument
        return done.code if isinstance(done.code, int) else BAD_INPUT
    if args.command == "serve":
        return _serve(args)
    if args.command == "optimize":
        return _optimize(args)
    if args.command == "warmup":
        print(f"graspforce: ready ({warmup():.2f} s)")
        return OK
    if args.command == "bench":
        return _bench(args)
    if args.command == "robots":
        return _robots(args)
    if args.command in ("batch", "plot"):
        try:
            return args.run(args)
        except (ValueError, TypeError, ImportError) as e:
            print(f"graspforce {args.command}: error: {e}", file=sys.stderr)
            return BAD_INPUT
    from . import demo
    demo.main()
    return OK


def entry():
    """The console script's entry point."""
    sys.exit(main())
