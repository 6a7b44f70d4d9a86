"""Profile the compiled core with Linux `perf`: where does a ZC-IE ray shot spend its time?

Runs ZC-IE (without a start table) on the ingot grasp's W_L1 in a compiled loop
(graspforce._core.timing.shoot_loop), long enough to sample, with Python out of the way. perf
reads the names of the core's functions from the extension's symbol table, which a Release build
strips (nanobind strips Release and MinSizeRel builds): build with symbols first, profile, then
build as usual again:

    pip install -e . --no-deps -Ccmake.build-type=RelWithDebInfo
    OPENBLAS_NUM_THREADS=1 perf record -o /tmp/perf.data python -m benchmarks.perf_map
    perf report -i /tmp/perf.data --no-children --sort symbol
    pip install -e . --no-deps

(RelWithDebInfo compiles at -O2 with symbols, Release at -O3: close enough to find where the time
goes, not to time it; with one BLAS thread, no idle BLAS thread spins through the samples.) `--reps` sets the
passes over the 500 rays (about 5 ms a pass).
"""
import argparse
import sys

import numpy as np

from benchmarks.grasp_sets import ingot_grasp_sets, random_wrenches
from graspforce._core import ZC_IE, timing


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--reps", type=int, default=1000, help="passes over the rays (default 1000)")
    args = ap.parse_args(argv)
    W, _ = ingot_grasp_sets()
    R = np.ascontiguousarray(-random_wrenches(500))
    ints, floats = W.program
    ns, total = timing.shoot_loop(ints, floats, R, W.witness_size, ZC_IE, 1e-9, 1000, args.reps)
    print(f"{args.reps} passes over {len(R)} rays: median shot {np.median(ns) / 1e3:.2f} us, "
          f"least pass {ns.sum(axis=1).min() / 1e6:.1f} ms (sum of t {total:.6g})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
