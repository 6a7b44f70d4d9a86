"""python -m graspforce warmup | demo

warmup: loads the compiled core and answers one problem with every method, so that a container
image or a new worker fails at build time, not at its first request, if the core is missing or
broken. The core is compiled when the package is installed, so nothing compiles here.
demo: the demo of graspforce.demo.
"""
import argparse
import sys
import time


def warmup():
    """One answer from every procedure and every entry point; returns the seconds it took."""
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


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m graspforce", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("warmup", help="load the compiled core and answer one problem per method")
    sub.add_parser("demo", help="minimal contact forces for a four-finger grasp")
    args = parser.parse_args(argv)
    if args.command == "warmup":
        print(f"graspforce: ready ({warmup():.2f} s)")
    else:
        from . import demo
        demo.main()
    return 0


if __name__ == "__main__":
    sys.exit(main())
