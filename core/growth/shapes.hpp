// What a pair of shapes made per query computes once: whether an ellipsoid holds its frame's
// origin clearly inside, clearly outside, or too close to its boundary to say in closed form
// (graspforce/growth/growth.py).
#pragma once

#include <cmath>

#include "arrays.hpp"

namespace gf::shapes {

constexpr double THIN = 1e-3;            // graspforce.growth.growth.THIN
constexpr double CLEAR_INSIDE = 0.9;     // graspforce.growth.growth.CLEAR_INSIDE
constexpr double CLEAR_OUTSIDE = 1.1;    // graspforce.growth.growth.CLEAR_OUTSIDE
constexpr Int INSIDE = 1, OUTSIDE = 0, UNDECIDED = -1;

// {c + S x : ||x|| <= 1}, S (3, k) row-major with k >= 3, holds the origin strictly iff
// M = S S^T is nonsingular and q = c^T M^-1 c < 1. INSIDE for q <= CLEAR_INSIDE^2, OUTSIDE for a
// zero S or q >= CLEAR_OUTSIDE^2, UNDECIDED for M near singular (its least eigenvalue below
// ~THIN^2 of its largest) or q between.
inline Int ellipsoid_origin(const double* c, const double* S, Int k) {
    bool any = false;
    for (Int i = 0; i < 3 * k; ++i) any = any || S[i] != 0.0;
    if (!any) return OUTSIDE;
    auto row_dot = [&](Int i, Int j) {
        double s = S[i * k] * S[j * k];
        for (Int l = 1; l < k; ++l) s += S[i * k + l] * S[j * k + l];
        return s;
    };
    const double a = row_dot(0, 0), b = row_dot(0, 1), cc = row_dot(0, 2);
    const double d = row_dot(1, 1), e = row_dot(1, 2), f = row_dot(2, 2);
    // the adjugate's first row and det M
    const double A = d * f - e * e, B = cc * e - b * f, C = b * e - cc * d;
    const double det = a * A + b * B + cc * C;
    const double trace = a + d + f;
    if (!(det >= THIN * THIN * (trace * trace * trace) / 27.0) || !(det > 0.0)) return UNDECIDED;
    const double x = c[0], y = c[1], z = c[2];
    if (x == 0.0 && y == 0.0 && z == 0.0) return INSIDE;
    const double D = a * f - cc * cc, F = b * cc - a * e, I = a * d - b * b;
    const double q =
        (A * x * x + D * y * y + I * z * z + 2.0 * (B * x * y + C * x * z + F * y * z)) / det;
    if (q <= CLEAR_INSIDE * CLEAR_INSIDE) return INSIDE;
    return q >= CLEAR_OUTSIDE * CLEAR_OUTSIDE ? OUTSIDE : UNDECIDED;
}

}  // namespace gf::shapes
