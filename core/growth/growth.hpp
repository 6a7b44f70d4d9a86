#pragma once

#include "api.hpp"
#include "shooting/packed.hpp"
#include "shooting/warm.hpp"

// The compiled growth-distance query: one call from Python per pair of poses (section 4.1).
//
// Python's share of a query is then one call and the result record: writing the rotations into
// the program, forming r = p_B - p_A, checking the poses and deciding the verdict all happen
// here, on Delta = R_A(A_0) - R_B(B_0) (eq. 10). The arguments are arrays only, and the query
// fills an array the caller allocated. The solver's constants and warm-start memory (`TAIL`)
// ride at the end of the program's floats, which the kernel reads only at its nodes' offsets.

namespace gf {

namespace growth {

constexpr Int OK = 0;
// not a proper rotation (R^T R = I to ROTATION_TOL, det R > 0) or not finite
constexpr Int BAD_POSE_A = 1;
constexpr Int BAD_POSE_B = 2;
constexpr Int COINCIDENT = 3;   // p_A = p_B: A(0) and B(0) are the same point, g(A, B) = 0

// the verdict of a query whose poses are valid (graspforce.growth names them)
constexpr Int SEPARATED = 0;
constexpr Int TOUCHING = 1;
constexpr Int PENETRATING = 2;
constexpr Int NOT_CERTIFIED = 3;   // max_iter: the bracket did not close

constexpr double ROTATION_TOL = 1e-9;
// warm start: the probes' spread follows the last change of the normal between calls, times
// SPREAD_GAIN (the ray must cross the probes' facet, and the next change is about the last one),
// within [SPREAD_MIN, SPREAD_MAX]. IE then needs about log2(spread^2 / eps) steps: on a pair
// moving by ~0.002 rad a call, 16 iterations instead of 19 with a fixed spread of 0.05 and 28
// cold
constexpr double SPREAD_GAIN = 4.0;
constexpr double SPREAD_MIN = 1e-3;
constexpr double SPREAD_MAX = 0.2;

// the query's frame [R_A (9), p_A, R_B (9), p_B, the shooter's head (HEAD)]: the entries ahead
// of the packed ray-shooting arrays
constexpr Int POSES = 24;
constexpr Int FRAME = POSES + HEAD;

// the last TAIL entries of the program's floats: the program's two rotation offsets, the witness
// size, the method, max_iter, whether to warm-start (integers), eps, touching_tol, then the warm
// start's memory (whether the last call was certified, the spread for the next one, the last
// normal)
constexpr Int MA = 0;
constexpr Int MB = 1;
constexpr Int WS = 2;
constexpr Int METHOD = 3;
constexpr Int MAX_ITER = 4;
constexpr Int WARM_START = 5;
constexpr Int EPS = 6;
constexpr Int TOUCHING_TOL = 7;
constexpr Int WARM = 8;
constexpr Int SPREAD = 9;
constexpr Int NORMAL = 10;
constexpr Int TAIL = NORMAL + 3;
// first warm start: probes at the last normal +- this (a unit vector's tilt)
constexpr double WARM_SPREAD = 0.05;
// a cold ZC-IE query's probes: around r itself, at this spread, instead of ZC from the origin.
// Delta changes with every pose, so no start table can be kept for it; but the normal at
// z_Delta(r) is rarely far from r, and the facet of three support points around r holds the ray
// (protocol, 300 contact pairs, compiled shot, with IE's secant query: spread 0 (ZC) 3.86 us and
// 25.8 IE steps, 0.05 3.00, 0.1 2.94, 0.2 2.76, 0.5 2.70, 0.7 2.69 and 18.3)
constexpr double COLD_SPREAD = 0.7;

}  // namespace growth

namespace growth_detail {

// whether R is a proper rotation (3 x 3, R^T R = I to ROTATION_TOL, det R > 0) and p a finite
// 3-vector
inline bool proper(Mat R, Vec p) {
    if (R.rows != 3 || R.cols != 3 || p.n != 3) return false;
    for (Int a = 0; a < 3; ++a) {
        if (!std::isfinite(p[a])) return false;
        for (Int b = 0; b < 3; ++b) {
            double s = 0.0;
            for (Int c = 0; c < 3; ++c) s += R(c, a) * R(c, b);
            // written so that NaN fails it
            if (!(std::abs(s - (a == b ? 1.0 : 0.0)) <= growth::ROTATION_TOL)) return false;
        }
    }
    const double det = (R(0, 0) * (R(1, 1) * R(2, 2) - R(1, 2) * R(2, 1))
                        - R(0, 1) * (R(1, 0) * R(2, 2) - R(1, 2) * R(2, 0))
                        + R(0, 2) * (R(1, 0) * R(2, 1) - R(1, 1) * R(2, 0)));
    return det > 0.0;
}

}  // namespace growth_detail

// (code, verdict, sigma, sigma_lower, sigma_upper, iterations, support_calls) for
// Delta = R_A(A_0) - R_B(B_0) and r = p_B - p_A (eq. 10): Python's `query`.
//
// code: OK, BAD_POSE_A / BAD_POSE_B (wrong shape, not finite, or not a proper rotation),
// COINCIDENT (sigma = 0). With t r <= z_Delta(r) <= t_upper r the shooter's bracket, g lies in
// [1/t_upper, 1/t] (clamped: an exact face of Delta can put h_Delta(n) / n^T r an ulp below t);
// sigma is the midpoint, and the verdict is TOUCHING when the bracket widened by touching_tol
// holds 1, else SEPARATED (g > 1) or PENETRATING. 0 is interior to Delta, so the ray always hits
// and only max_iter stops it short: NOT_CERTIFIED, sigma = 1/t (inf for t = 0), bracket [0, inf].
// packed (FRAME + capacity(3, ws) entries): the frame [R_A, p_A, R_B, p_B, the shooter's head]
// (a copy, so that the record's contact stays right if the caller reuses its pose arrays), then
// the shot's arrays. floats ends with TAIL; the program's Affine nodes hold M = R_A at
// floats[ma:ma + 9] and M = -R_B at floats[mb:mb + 9] (row-major), overwritten here. With
// WARM_START, a call after a certified one starts ZC-IE from probes around the last normal,
// spread by the last change of the normal; the tail remembers both. Any other ZC-IE call starts
// from probes around r (COLD_SPREAD); either falls back to ZC from the origin when the ray
// misses the probes' facets.
GrowthOut growth_query(IVec ints, Vec floats, Mat R_a, Vec p_a, Mat R_b, Vec p_b, Vec packed) {
    namespace G = growth;
    // one read per cache line of the program, before the kernel's chain of dependent reads
    // (ints[CSTART] -> ints[CHILDREN + ...] -> floats[PSTART + ...]) meets each line's miss one
    // after the other: in a loop over many pairs the solver's arrays are cold, and these reads'
    // misses overlap. Written to the packed head, which the shot overwrites, so that they stay.
    double touched = 0.0;
    for (Int i = 0; i < ints.n; i += 8) touched += static_cast<double>(ints[i]);
    for (Int i = 0; i < floats.n; i += 8) touched += floats[i];
    // the last lines, whatever the arrays' alignment
    packed[G::POSES] = touched + static_cast<double>(ints[ints.n - 1]) + floats[floats.n - 1];
    Int code = G::OK;
    if (!growth_detail::proper(R_a, p_a))
        code = G::BAD_POSE_A;
    else if (!growth_detail::proper(R_b, p_b))
        code = G::BAD_POSE_B;
    if (code != G::OK) return {code, G::NOT_CERTIFIED, 0.0, 0.0, 0.0, 0, 0};
    const Int c = floats.n - G::TAIL;
    const Int ma = static_cast<Int>(floats[c + G::MA]);
    const Int mb = static_cast<Int>(floats[c + G::MB]);
    // r and its direction: one allocation
    Array ray_(2, 3);
    const Mat ray = ray_.mat();
    const Vec r = ray.row(0);
    double rr = 0.0;
    for (Int a = 0; a < 3; ++a) {
        for (Int b = 0; b < 3; ++b) {
            packed[3 * a + b] = R_a(a, b);
            packed[12 + 3 * a + b] = R_b(a, b);
            floats[ma + 3 * a + b] = R_a(a, b);
            floats[mb + 3 * a + b] = -R_b(a, b);
        }
        packed[9 + a] = p_a[a];
        packed[21 + a] = p_b[a];
        r[a] = p_b[a] - p_a[a];
        rr += r[a] * r[a];
    }
    if (rr == 0.0) {
        // A(0) = B(0): no shot, an empty head, no normal to remember
        for (Int a = G::POSES; a < G::FRAME; ++a) packed[a] = 0.0;
        floats[c + G::WARM] = 0.0;
        floats[c + G::SPREAD] = G::WARM_SPREAD;
        return {G::COINCIDENT, G::PENETRATING, 0.0, 0.0, 0.0, 0, 0};
    }
    const Int ws = static_cast<Int>(floats[c + G::WS]);
    const double eps = floats[c + G::EPS];
    const Int max_iter = static_cast<Int>(floats[c + G::MAX_ITER]);
    const bool warm = floats[c + G::WARM] > 0.0;
    const Vec normal = floats.segment(c + G::NORMAL, 3);   // written through below
    const Int method = static_cast<Int>(floats[c + G::METHOD]);
    Head head{};
    if (warm) {
        head = shoot_warm(ints, floats, r, ws, eps, max_iter, normal, floats[c + G::SPREAD],
                          packed, G::FRAME);
    } else if (method == ZC_IE || method == ZC_IE_PAPER) {
        const double rn = 1.0 / std::sqrt(rr);
        for (Int a = 0; a < 3; ++a) ray(1, a) = r[a] * rn;
        head = shoot_warm(ints, floats, r, ws, eps, max_iter, ray.row(1), G::COLD_SPREAD, packed,
                          G::FRAME);
    } else {
        head = pack(shoot(ints, floats, r, ws, method, eps, max_iter), packed, G::FRAME);
    }
    const Int status = head.status;
    const double t = head.t, t_up = head.t_up;
    const Int iterations = head.iters, calls = head.calls;
    packed[G::POSES] = static_cast<double>(status);
    packed[G::POSES + 1] = t;
    packed[G::POSES + 2] = t_up;
    packed[G::POSES + 3] = head.h_n;
    packed[G::POSES + 4] = static_cast<double>(iterations);
    packed[G::POSES + 5] = static_cast<double>(calls);
    packed[G::POSES + 6] = static_cast<double>(head.singular);
    packed[G::POSES + 7] = static_cast<double>(head.k);
    if (floats[c + G::WARM_START] != 0.0) {
        // the first warm call probes at WARM_SPREAD, the next ones at the last change of the
        // normal times SPREAD_GAIN
        if (status == HIT && warm) {
            double dn = 0.0;
            for (Int a = 0; a < 3; ++a) {
                const double x = packed[G::FRAME + a] - normal[a];
                dn += x * x;
            }
            floats[c + G::SPREAD] =
                std::min(std::max(G::SPREAD_GAIN * std::sqrt(dn), G::SPREAD_MIN), G::SPREAD_MAX);
        } else {
            floats[c + G::SPREAD] = G::WARM_SPREAD;
        }
        floats[c + G::WARM] = status == HIT ? 1.0 : 0.0;
        if (status == HIT)
            for (Int a = 0; a < 3; ++a) normal[a] = packed[G::FRAME + a];
    }
    if (status != HIT) {
        const double sigma = t > 0.0 ? 1.0 / t : INF;
        return {code, G::NOT_CERTIFIED, sigma, 0.0, INF, iterations, calls};
    }
    const double upper = 1.0 / t;
    const double lower = std::min(1.0 / t_up, upper);
    const double tol = floats[c + G::TOUCHING_TOL];
    Int verdict;
    if (lower - tol <= 1.0 && 1.0 <= upper + tol)
        verdict = G::TOUCHING;
    else
        verdict = lower > 1.0 ? G::SEPARATED : G::PENETRATING;
    return {code, verdict, 0.5 * (lower + upper), lower, upper, iterations, calls};
}

}  // namespace gf
