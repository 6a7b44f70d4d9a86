"""How the numerics are compiled: Numba nopython, cached, and, where it is safe, without
Numba's reference counting.

Numba counts references to every array with atomic increments and decrements (NRT_incref,
NRT_decref). Its pruning pass removes the pairs only in simple control flow, so a function with
loops and several exits pays a pair for each array argument and each inlined helper's argument,
on every call: a ZC-IE shot on the ingot's W_L1 made ~500 increments and ~520 decrements (counted
with NUMBA_DEBUG_NRT=1), and a support call on it took 223 ns in a compiled loop, 115 ns compiled
without them (BENCHMARKS.md, "Reference counting").

`borrowing` compiles a function with Numba's `_nrt=False` option, as Numba's own string and sort
helpers are: its array arguments are borrowed from the caller, which owns them, and nothing is
counted. The rule that makes this safe: such a function allocates nothing and returns or stores no
array (a view it made would hold its parent's memory without a reference); it reads and writes
arrays its caller keeps alive, and returns scalars. Everything that allocates, or returns arrays
(the shooters' result records), is compiled with `njit(cache=True)` as usual.

`borrowing` functions also compile with two of LLVM's fast-math flags, `reassoc` and `contract`:
sums may be reordered (which lets LLVM vectorize the short reductions of the support kernel, the IE
step and the factorizations; the speed comes from this flag: `contract` alone gained nothing) and a
product and a sum may fuse into one FMA. That changes results by rounding only: every stopping
rule, residual test and certificate is already written against rounding. The flags that change
meaning are left off: `nnan` and `ninf` (NaN and infinity are tested for: a kink's NaN, a hull's
-inf, `x != x` checks), `nsz` (a signed zero decides a cone cap's test), `arcp` and `afn`
(approximate division and functions). Measured with benchmarks/ab.py: min_force L1 0.946 and 0.942,
ray_shoot 0.956 and 0.962 (two runs); Linf and growth distance unchanged (BENCHMARKS.md, "Stop
21"). Compiled functions that use exact rounding on purpose (zc_from's `t + 1 / sigma == t`) are
not borrowing.
"""
from numba import njit


# LLVM's fast-math flags that borrowing functions compile with (module docstring)
FASTMATH = {"reassoc", "contract"}


def borrowing(fn=None, **options):
    """njit(cache=True) without reference counting, with FASTMATH (module docstring); options
    such as forceinline=True pass through."""
    decorate = njit(cache=True, _nrt=False, fastmath=FASTMATH, **options)
    return decorate if fn is None else decorate(fn)
