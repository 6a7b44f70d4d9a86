// Codes shared across the compiled core and with Python (the bindings export every one of them,
// so that Python reads the same values: graspforce._core.<NAME>).
#pragma once

#include "arrays.hpp"

namespace gf {

// support programs (kernel.hpp): node kinds
constexpr Int POLYTOPE = 0;        // params: m, n, vertices (m*n)            witness: [active, vertex index]
constexpr Int ELLIPSOID = 1;       // params: n, k, center (n), shape (n*k)   witness: [active, x (k)]
constexpr Int BOX = 2;             // params: n, half extents (n)             witness: [active, corner (n)]
constexpr Int TRUNCATED_CONE = 3;  // params: bottom radius, top radius, height  witness: [active, point (3)]
constexpr Int CONE_CAP = 4;        // params: n, mu                           witness: [active, g (n)]
constexpr Int HULL = 10;
constexpr Int SUM = 11;
constexpr Int AFFINE = 12;         // params: m, n, M (m*n), t (m)
constexpr Int EMBED = 13;          // params: m, n, span, t (m): x -> (0, x) + t
constexpr Int ORIGIN_EMBED = 14;   // params as EMBED: the embedding of CH({0} U child)
// plans (the last entry of a program's ints)
constexpr Int GENERAL = 0;
constexpr Int ELLIPSOID_HULL = 1;   // a hull of ellipsoids (6, 3) in R^6, bare or embedded
constexpr Int POSED_SUM = 2;
constexpr Int ELLIPSE_HULL = 3;     // the same of ellipses (6, 2): point contacts
// an affine image x -> M x + t of ELLIPSOID_HULL's or ELLIPSE_HULL's set (a rank-deficient
// grasp's wrench set in its span)
constexpr Int PROJECTED_ELLIPSOID_HULL = 4;
constexpr Int PROJECTED_ELLIPSE_HULL = 5;
// W_Linf itself: a sum in R^6 of hulls CH({0} U E_i), E_i an ellipsoid with 3 axes (soft
// fingers) or 2 (point contacts)
constexpr Int ORIGIN_ELLIPSOID_SUM = 6;
constexpr Int ORIGIN_ELLIPSE_SUM = 7;

// the offsets in `ints` of a program's blocks, for a program of nn nodes
struct Blocks {
    Int KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE, CHILDREN;
};
// always inlined: a call returns the struct through memory (~30 instructions), where the
// callers read one or two of its offsets (the IE loop's piece test, every step)
[[gnu::always_inline]] inline Blocks blocks(Int nn) {
    return {1, 1 + nn, 1 + 2 * nn, 1 + 3 * nn, 1 + 4 * nn, 1 + 5 * nn, 1 + 6 * nn, 1 + 7 * nn,
            1 + 8 * nn, 1 + 9 * nn, 1 + 10 * nn};
}

// GJK and ZC (distance.hpp)
constexpr Int CONVERGED = 0;   // GJK: h_A(n) - n^T v within tolerance; ZC: h_{A - shift}(n) within it
constexpr Int INSIDE = 1;      // the target is in CH(V) (GJK) or in CO(V - shift) (ZC)
constexpr Int STALLED = 2;     // the new support point brought no decrease: exact to rounding
constexpr Int MAX_ITER = 3;

// ray shots: statuses
constexpr Int HIT = 0;
constexpr Int MISS = 1;
constexpr Int LIMIT = 2;
constexpr Int FACET = 3;       // internal: ZC-based iterations reached a facet the ray crosses

// zc_from's modes
constexpr Int ZC_ONLY = 0;
constexpr Int WITH_IE = 1;
constexpr Int UNTIL_FACET = 2;
constexpr Int WITH_NEWTON = 3;
constexpr Int WITH_SMOOTH_NEWTON = 4;   // WITH_NEWTON's smooth path alone (newton.hpp)

// methods
constexpr Int GJK_BASED = 0;
constexpr Int IE = 1;
constexpr Int ZC_BASED = 2;
constexpr Int BI_GJK = 3;
constexpr Int ZC_IE = 4;
constexpr Int ZC_IE_NEWTON = 5;
constexpr Int ZC_IE_PAPER = 6;   // ZC_IE without the Newton finish's smooth path: section 3.4.2

// a packed shot's head: (status, t, t_upper, h_n, iterations, support_calls, singular_steps, k)
constexpr Int HEAD = 8;

}  // namespace gf
