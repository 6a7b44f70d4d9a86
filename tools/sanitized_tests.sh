#!/usr/bin/env bash
# The test suite against a core built with AddressSanitizer and UBSan: an out-of-bounds read or
# write, a use of freed memory or undefined behaviour in core/ stops the run with a report. The
# editable install is rebuilt with the sanitizers, the tests run, and it is rebuilt as usual.
#   tools/sanitized_tests.sh [pytest arguments]     (default: the core's test files)
set -euo pipefail
cd "$(dirname "$0")/.."
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
rebuild_normal() { python -m pip install -q -e . --no-deps; }
trap rebuild_normal EXIT
python -m pip install -q -e . --no-deps -Ccmake.define.CMAKE_CXX_FLAGS="$flags" \
    -Cbuild-dir=build/sanitized
tests=("$@")
if [ ${#tests[@]} -eq 0 ]; then
    tests=(tests/test_linalg.py tests/test_shooter_steps.py tests/test_newton.py
           tests/test_closest_point.py tests/test_cone_distance.py tests/test_ray_shoot.py
           tests/test_degenerate.py tests/test_start_table.py tests/test_linf_lift.py
           tests/test_grasp_forces.py tests/test_growth.py tests/test_certificates.py
           tests/test_determinism.py tests/test_threads.py tests/test_batch.py
           tests/test_span.py tests/test_scale.py tests/test_fresh.py tests/test_contact.py
           tests/test_sets.py tests/test_min_force_call.py tests/test_pair_exit.py)
fi
# Python itself is not built with the sanitizers: its allocations are not tracked for leaks
LD_PRELOAD="$(gcc -print-file-name=libasan.so):$(gcc -print-file-name=libubsan.so)" \
ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    python -m pytest -q -p no:randomly "${tests[@]}"
