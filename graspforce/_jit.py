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
21"). Functions that use exact rounding on purpose (zc_from's `t + 1 / sigma == t`) are compiled
without these flags: `borrowing(fastmath=False)`.
"""
from numba import njit, types
from numba.core.imputils import impl_ret_borrowed
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array


# LLVM's fast-math flags that borrowing functions compile with (module docstring)
FASTMATH = {"reassoc", "contract"}


def borrowing(fn=None, **options):
    """njit(cache=True) without reference counting, with FASTMATH (module docstring) unless
    fastmath=False is given; options such as forceinline=True pass through."""
    options.setdefault("fastmath", FASTMATH)
    decorate = njit(cache=True, _nrt=False, **options)
    return decorate if fn is None else decorate(fn)


@intrinsic
def view(typingctx, buf, start, shape):
    """The C-contiguous array of the given shape (an integer or a tuple of them) whose entries
    are buf[start:start + prod(shape)], buf a C-contiguous 1-D array: a view, made in the
    caller's code. A borrowing function lays its arrays out this way in one array its caller
    owns. Numba's reshape calls a C helper for the strides (~8 ns) and a slice clamps its end
    to the parent's length at run time: both hide the shapes from LLVM, and the loops that
    zc_from's loop, compiled for one n, runs over n-vectors were no longer unrolled (growth
    query, compiled shot: 2.63 us with arrays allocated in the loop's function, 3.03 with
    reshaped views, 2.80 with arrays passed in; BENCHMARKS.md, "Stop 29")."""
    if not (isinstance(buf, types.Array) and buf.ndim == 1 and buf.layout == "C"
            and isinstance(start, types.Integer)):
        return None
    if isinstance(shape, types.Integer):
        dims_types = (shape,)
    elif isinstance(shape, types.BaseTuple) and all(isinstance(d, types.Integer)
                                                    for d in shape):
        dims_types = tuple(shape)
    else:
        return None
    ret = types.Array(buf.dtype, len(dims_types), "C")

    def codegen(context, builder, signature, args):
        intp = types.intp
        data, begin, dims_value = args
        if isinstance(shape, types.Integer):
            dims = [context.cast(builder, dims_value, shape, intp)]
        else:
            dims = [context.cast(builder, builder.extract_value(dims_value, i), d, intp)
                    for i, d in enumerate(dims_types)]
        itemsize = context.get_constant(intp, context.get_abi_sizeof(
            context.get_data_type(buf.dtype)))
        strides = [itemsize]
        for d in reversed(dims[1:]):
            strides.insert(0, builder.mul(strides[0], d))
        parent = make_array(buf)(context, builder, data)
        out = make_array(ret)(context, builder)
        populate_array(out, data=builder.gep(parent.data, [context.cast(builder, begin, start,
                                                                         intp)]),
                       shape=dims, strides=strides, itemsize=itemsize, meminfo=parent.meminfo,
                       parent=parent.parent)
        return impl_ret_borrowed(context, builder, ret, out._getvalue())

    return ret(buf, start, shape), codegen
