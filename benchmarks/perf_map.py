"""Profile the compiled code with Linux `perf`: where does a ZC-IE ray shot spend its time?

perf sees Numba's machine code as anonymous "[JIT]" addresses. This script writes the map file
perf reads for such code (/tmp/perf-<pid>.map: start, size, name per function), then runs ZC-IE on
the ingot grasp's W_L1 long enough to sample. The compiled libraries keep their symbol tables only
when they were compiled in this process, so point Numba at an empty cache directory:

    NUMBA_CACHE_DIR=$(mktemp -d) perf record -o /tmp/perf.data python -m benchmarks.perf_map
    perf report -i /tmp/perf.data --no-children --sort symbol

(the first two minutes of samples are compilation; the [JIT] rows are the run). Shares of the
[JIT] samples at 9c1198a: support 28%, zc_from's own loop 14%, NRT reference counting 10%,
_matvec 8%, lu_solve 7%, lstsq 7%, _keep 5%, _pivot 5%, _matvec_t_ones 4%.
"""
import os
import sys

from numba import njit

from benchmarks.grasp_sets import ingot_grasp_sets, random_wrenches
from graspforce import _shooters as S


@njit
def _shoot_all(ints, floats, R, ws, reps):
    total = 0.0
    for _ in range(reps):
        for i in range(R.shape[0]):
            total += S.zc_family(ints, floats, R[i], ws, 1e-9, 1000, S.WITH_IE)[1]
    return total


def write_perf_map(dispatcher, path=None):
    """Write /tmp/perf-<pid>.map for every function linked into `dispatcher`'s compiled code;
    returns the number of functions. Zero when the code came from Numba's cache."""
    entries, seen = [], set()

    def visit(library):
        if id(library) in seen:
            return
        seen.add(id(library))
        module = getattr(library, "_final_module", None)
        if module is not None:
            engine = library._codegen._engine
            for fn in module.functions:
                if not fn.is_declaration:
                    address = engine.get_function_address(fn.name)
                    if address:
                        entries.append((address, fn.name))
        for linked in getattr(library, "_linking_libraries", ()):
            visit(linked)

    for compiled in dispatcher.overloads.values():
        visit(compiled.library)
    if not entries:
        return 0
    entries.sort()
    path = path or f"/tmp/perf-{os.getpid()}.map"
    with open(path, "w") as f:
        ends = [start for start, _ in entries[1:]] + [entries[-1][0] + 4096]
        for (start, name), end in zip(entries, ends):
            f.write(f"{start:x} {end - start:x} {name}\n")
    return len(entries)


def main(reps=300):
    W, _ = ingot_grasp_sets()
    R = -random_wrenches(500)
    ints, floats = W.program
    _shoot_all(ints, floats, R, W.witness_size, 1)
    if not write_perf_map(_shoot_all):
        sys.exit("no symbols: the code came from Numba's cache; set NUMBA_CACHE_DIR to an empty "
                 "directory")
    _shoot_all(ints, floats, R, W.witness_size, reps)


if __name__ == "__main__":
    main()
