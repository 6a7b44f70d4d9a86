"""A/B: two checkouts of graspforce timed call by call in one process.

This machine's speed drifts by up to 2x over seconds (other tenants), which swamps a 5-10% change
measured by two benchmark runs one after the other. Here both versions are loaded side by side
(as packages gf_a and gf_b) and every case is timed A then B, seven times, keeping each one's
minimum.

    python -m benchmarks.ab <checkout A> <checkout B>

Each checkout's compiled core (graspforce._core) is taken from its build folder, where
`pip install -e .` or `pip wheel --no-deps -w /tmp/wheels <checkout>` leaves it
(build/<wheel tag>/), or from its package folder: a checkout made with `git worktree add` must
be built first. A checkout from before the C++ core compiles with Numba instead: give it an empty
NUMBA_CACHE_DIR, so that no other version's compiled code is reused. Cases: growth distance on
the protocol's contact pairs, ray_shoot ZC-IE on the ingot's W_L1, min_force L1 and Linf on the
ingot grasp (benchmarks/README.md).
"""
import glob
import importlib.machinery
import importlib.util
import os
import sys
import time

import numpy as np

from benchmarks.grasp_sets import MU, MU_S, ingot_contacts, ingot_ellipsoids, random_wrenches
from benchmarks.growth_sets import protocol_pairs

REPEATS = 7


def load(checkout, name):
    """The package `graspforce` of a checkout, imported as `name`, with its own compiled core."""
    root = f"{checkout}/graspforce"
    spec = importlib.util.spec_from_file_location(name, f"{root}/__init__.py",
                                                  submodule_search_locations=[root])
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    core = _built_core(checkout)
    if core is not None:
        # registered ahead of the package, whose `from ._core import ...` then finds it
        core_spec = importlib.util.spec_from_file_location(f"{name}._core", core)
        core_module = importlib.util.module_from_spec(core_spec)
        sys.modules[core_spec.name] = core_module
        core_spec.loader.exec_module(core_module)
        module._core = core_module
    spec.loader.exec_module(module)
    return module


def _built_core(checkout):
    """The path of a checkout's compiled core outside its package folder (the newest of its
    build folders), or None: a package folder's own is found by the import itself, and a
    checkout from before the C++ core has none."""
    if any(os.path.exists(f"{checkout}/graspforce/_core{suffix}")
           for suffix in importlib.machinery.EXTENSION_SUFFIXES):
        return None
    built = [path for suffix in importlib.machinery.EXTENSION_SUFFIXES
             for path in glob.glob(f"{checkout}/build/*/_core{suffix}")]
    if not built:
        if os.path.exists(f"{checkout}/CMakeLists.txt"):
            raise SystemExit(f"{checkout}: no compiled core; build it first, e.g. "
                             f"pip wheel --no-deps -w /tmp/wheels {checkout}")
        return None
    return max(built, key=os.path.getmtime)


def cases(gf, pairs, wrenches):
    """{case: [zero-argument calls]} for one version."""
    growth = []
    for p in pairs:
        solver = gf.GrowthDistance(gf.Ellipsoid(np.zeros(3), np.diag(p["axes"])),
                                   gf.TruncatedCone(p["rb"], p["rt"], p["h"]), warm_start=False)
        pose_a, pose_b = (p["R_e"], p["p_e"]), (p["R_c"], p["p_c"])
        growth.append(lambda s=solver, a=pose_a, b=pose_b: s(a, b))
    W = gf.hull(*[gf.Ellipsoid(c, S) for c, S in ingot_ellipsoids()])
    grasp = gf.Grasp(gf.Contact(p, n, MU, MU_S, tangents=(o, t))
                     for p, n, o, t in ingot_contacts())
    return {
        "growth": growth,
        "ray_shoot zc-ie": [lambda r=-w: gf.ray_shoot(W, r) for w in wrenches],
        "min_force L1": [lambda w=w: grasp.min_force(w) for w in wrenches],
        "min_force Linf": [lambda w=w: grasp.min_force(w, norm="Linf") for w in wrenches],
    }


def compare(calls_a, calls_b):
    """Per-call minima over REPEATS rounds, each round timing A then B on the same input. Each
    call is timed on its second run: the first brings its version's code back into the caches,
    which switching versions call by call evicts (the benchmarks run one version warm)."""
    best_a = np.full(len(calls_a), np.inf)
    best_b = np.full(len(calls_b), np.inf)
    for _ in range(REPEATS):
        for i, (fa, fb) in enumerate(zip(calls_a, calls_b)):
            best_a[i] = min(best_a[i], _second_run(fa))
            best_b[i] = min(best_b[i], _second_run(fb))
    return best_a * 1e6, best_b * 1e6


def _second_run(f):
    f()
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


def main(checkout_a, checkout_b, n_pairs=200, n_wrenches=300):
    pairs, wrenches = protocol_pairs(n_pairs), random_wrenches(n_wrenches)
    a = cases(load(checkout_a, "gf_a"), pairs, wrenches)
    b = cases(load(checkout_b, "gf_b"), pairs, wrenches)
    print("| case | A median (us) | B median (us) | B / A |")
    print("|---|---|---|---|")
    for name in a:
        ta, tb = compare(a[name], b[name])
        print(f"| {name} | {np.median(ta):.1f} | {np.median(tb):.1f} | "
              f"{np.median(tb) / np.median(ta):.3f} |")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
