"""Support programs: the layout of a compiled convex set, read by the core's support kernel.

A convex set compiles to a *support program*: a tree of nodes stored in pre-order (a parent before
its children) in flat arrays. `support` (core/geometry/kernel.hpp) evaluates h_A(u) and s_A(u) of
eq. (2) for any program in four passes: directions flow down the tree (an affine node maps u to M^T
u), support values flow up (a hull keeps its best child, a sum adds), the leaves that produced the
point are flagged in the witness vector, and the support point is built up from the flagged nodes
only. Every algorithm is compiled once against this kernel, whatever the shape. Some program shapes
take loops of their own instead of the passes (their `plan`): the contacts' wrench sets, shot at on
every min_force call (hulls of ellipsoids in R^6, bare or lifted, or their affine image in the span
of a rank-deficient grasp, and W_Linf's sum of hulls of the origin and an ellipsoid), and sums of
posed 3-D bodies, growth distance's Delta.

A program is two arrays, `ints` and `floats`, so that a call from Python unboxes two arrays, not
twelve. `ints` = [nn, kind, dim, pstart, cstart, ccount, wstart, dstart, ostart, choice,
active, children, plan] (each block nn long but `children` and the one entry `plan`);
`floats` = [params, scratch]. The blocks:
    kind[i]      node kind (constants below)
    dim[i]       dimension of the node's output space
    pstart[i]    offset of the node's parameters in `params`
    cstart[i], ccount[i]   its children are children[cstart[i] : cstart[i] + ccount[i]]
    wstart[i]    leaves: offset of its witness slot [active, local...] in the witness vector
    dstart[i]    offset of its direction in `scratch`: its parent's, unless the parent is affine
                 (an embedding's child: the last entries of its parent's)
    ostart[i]    offset of its point and value in `scratch`
    choice[i], active[i]   work arrays: a hull's best child (an origin embedding's child, or -1
                 for its origin), whether node i produced the point
    plan         how `support` evaluates the program (GENERAL, ELLIPSOID_HULL, ELLIPSE_HULL,
                 PROJECTED_ELLIPSOID_HULL, PROJECTED_ELLIPSE_HULL, ORIGIN_ELLIPSOID_SUM,
                 ORIGIN_ELLIPSE_SUM or POSED_SUM below, decided by `plan_of` when the set
                 compiles)
"""
from .._core import (AFFINE, BOX, CONE_CAP, ELLIPSE_HULL, ELLIPSOID, ELLIPSOID_HULL, EMBED,
                    GENERAL, HULL, ORIGIN_ELLIPSE_SUM, ORIGIN_ELLIPSOID_SUM, ORIGIN_EMBED,
                    POLYTOPE, POSED_SUM, PROJECTED_ELLIPSE_HULL, PROJECTED_ELLIPSOID_HULL, SUM,
                    TRUNCATED_CONE, support)

__all__ = ["AFFINE", "BOX", "CONE_CAP", "ELLIPSE_HULL", "ELLIPSOID", "ELLIPSOID_HULL", "EMBED",
           "GENERAL", "HULL", "ORIGIN_ELLIPSE_SUM", "ORIGIN_ELLIPSOID_SUM", "ORIGIN_EMBED",
           "POLYTOPE", "POSED_SUM", "PROJECTED_ELLIPSE_HULL",
           "PROJECTED_ELLIPSOID_HULL", "SUM", "TRUNCATED_CONE", "BLOCKS", "children",
           "param_start", "params_size", "plan_of", "support"]

# the blocks of `ints` after nn, in order (core/codes.hpp's `blocks` gives their offsets)
BLOCKS = ("kind", "dim", "pstart", "cstart", "ccount", "wstart", "dstart", "ostart", "choice",
          "active", "children")


def _block(ints, name, node=0):
    return 1 + BLOCKS.index(name) * int(ints[0]) + node


def param_start(ints, node):
    """Offset of a node's parameters in `floats` (Python side, for callers that update them)."""
    return int(ints[_block(ints, "pstart", node)])


def params_size(ints):
    """Entries of `floats` that hold parameters (Python side); the scratch the kernel writes
    follows them."""
    return int(ints[_block(ints, "dstart")])


def plan_of(kind, dim, params, child_lists):
    """The plan of a program (module docstring) from its nodes' kinds, dimensions, parameter
    arrays and children (Python side, when the set compiles)."""
    if kind[0] == SUM and dim[0] == 6:
        return _origin_sum_plan(kind, dim, params, child_lists)
    if kind[0] == SUM and dim[0] == 3:
        for c in child_lists[0]:
            leaf = child_lists[c][0] if kind[c] == AFFINE else c
            if kind[c] != AFFINE or kind[leaf] >= HULL or dim[leaf] != 3:
                return GENERAL
        return POSED_SUM
    if kind[0] == AFFINE:
        # x -> M x + t over such a hull (node 1): a rank-deficient grasp's set in its span
        return {ELLIPSOID_HULL: PROJECTED_ELLIPSOID_HULL,
                ELLIPSE_HULL: PROJECTED_ELLIPSE_HULL}.get(
                    _hull_plan(kind, dim, params, child_lists, child_lists[0][0]), GENERAL)
    return _hull_plan(kind, dim, params, child_lists, 0)


def _origin_sum_plan(kind, dim, params, child_lists):
    """ORIGIN_ELLIPSOID_SUM or ORIGIN_ELLIPSE_SUM when the root sums hulls of the origin (a
    polytope of one vertex at 0, first) and an ellipsoid in R^6 with 3 or 2 axes each (W_Linf);
    else GENERAL."""
    axes = set()
    for c in child_lists[0]:
        if kind[c] != HULL or len(child_lists[c]) != 2:
            return GENERAL
        origin, leaf = child_lists[c]
        if (kind[origin] != POLYTOPE or params[origin][0] != 1 or any(params[origin][2:])
                or kind[leaf] != ELLIPSOID or dim[leaf] != 6):
            return GENERAL
        axes.add(params[leaf][1])          # an ellipsoid's parameters start [n, k]
    return {frozenset({3}): ORIGIN_ELLIPSOID_SUM, frozenset({2}): ORIGIN_ELLIPSE_SUM}.get(
        frozenset(axes), GENERAL)


def _hull_plan(kind, dim, params, child_lists, root):
    """ELLIPSOID_HULL or ELLIPSE_HULL when node `root` is a hull of ellipsoids in R^6 with 3 or
    2 axes each, bare or embedded; else GENERAL."""
    if kind[root] != HULL:
        return GENERAL
    axes = set()
    for c in child_lists[root]:
        leaf = child_lists[c][0] if kind[c] in (EMBED, ORIGIN_EMBED) else c
        if kind[leaf] != ELLIPSOID or dim[leaf] != 6:
            return GENERAL
        axes.add(params[leaf][1])          # an ellipsoid's parameters start [n, k]
    return {frozenset({3}): ELLIPSOID_HULL, frozenset({2}): ELLIPSE_HULL}.get(frozenset(axes),
                                                                             GENERAL)


def children(ints, node):
    """The node indices of a node's children (Python side)."""
    start = _block(ints, "children", ints[_block(ints, "cstart", node)])
    return [int(c) for c in ints[start:start + ints[_block(ints, "ccount", node)]]]
