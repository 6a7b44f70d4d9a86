#pragma once

#include "api.hpp"
#include "shooting/pair_exit.hpp"

// One entry point for every ray-shooting procedure: the method code picks GJK-based, IE,
// ZC-based, Bi-GJK, ZC-IE or ZC-IE with the Newton finish; where a shot stalls or stops above eps
// it is finished by another (IE steps from its facet, or GJK-based), so that "hit" always means
// certified to eps.

namespace gf::dispatch_detail {

// The finish's result, with the counts of both shots and the hand-over as a singular step.
inline Shot handed_over(const Shot& out, Shot fin) {
    fin.iters = out.iters + fin.iters;
    fin.calls = out.calls + fin.calls;
    fin.singular = out.singular + fin.singular + 1;
    return fin;
}

// GJK-based, Bi-GJK or ZC-based, finished by IE steps where they stall or stop above eps.
inline Shot distance_based(IVec ints, Vec floats, Vec r, Int ws, Int method, double eps,
                           Int max_iter) {
    Shot out;
    if (method == GJK_BASED)
        out = gjk_based(ints, floats, r, ws, eps, max_iter);
    else if (method == BI_GJK)
        out = bi_gjk(ints, floats, r, ws, eps, max_iter);
    else
        out = zc_family(ints, floats, r, ws, eps, max_iter, ZC_ONLY);
    // a LIMIT short of max_iter is a stall (zc_from), or a hit without its certificate
    out = certify(std::move(out), r, eps);
    const bool stalled = out.status == LIMIT && out.iters < max_iter;
    if (!stalled) return out;
    // GJK's simplex and ZC's cone from b_k lose rank near the boundary (relative singular values
    // ~1e-13) and can stall above eps, seen on a third of the ingot grasp's rays at eps = 1e-9.
    // IE's facets are solved from the origin and stay well-conditioned: finish with IE steps,
    // from the final facet when there is one (ZC-based on the ingot: mean support calls
    // 116 -> 102), else, or if that fails too, from scratch. The hand-over counts as a
    // singular step.
    const Int n = r.n;
    if (out.k() == n) {
        Shot fin = certify(zc_from_simplex(ints, floats, r, ws, eps, max_iter, WITH_IE, out.t,
                                           out.V.mat(), out.W.mat(), out.lam.vec(), n, 0, 0),
                           r, eps);
        if (fin.status == HIT) return handed_over(out, std::move(fin));
    }
    return handed_over(out, certify(ie(ints, floats, r, ws, eps, max_iter), r, eps));
}

// "zc-ie" from the origin: ZC-IE with the smooth path (zc_family.hpp) and, on two soft fingers,
// the exit in closed form from ZC's first facet, whose IE steps go on where it is not certified.
inline Shot zc_ie(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter) {
    const Int n = r.n;
    if (n != 6 || !pair_applies(ints, floats))
        return zc_family(ints, floats, r, ws, eps, max_iter, WITH_SMOOTH_NEWTON);
    Shot first = first_facet(ints, floats, r, ws, eps, max_iter);
    if (first.status != FACET) return first;
    Shot out = pair_exit(ints, floats, r, ws, eps, 1.0 / first.t);
    if (out.status == HIT) {
        out.iters += first.iters;
        out.calls += first.calls;
        return out;
    }
    return zc_from_simplex(ints, floats, r, ws, eps, max_iter, WITH_SMOOTH_NEWTON, first.t,
                          first.V.mat(), first.W.mat(), first.lam.vec(), n, first.iters,
                          first.calls);
}

}  // namespace gf::dispatch_detail

namespace gf {

// Dispatch on the method code.
Shot shoot(IVec ints, Vec floats, Vec r, Int ws, Int method, double eps, Int max_iter) {
    Shot out;
    if (method == IE)
        out = ie(ints, floats, r, ws, eps, max_iter);
    else if (method == ZC_IE)
        out = dispatch_detail::zc_ie(ints, floats, r, ws, eps, max_iter);
    else if (method == ZC_IE_PAPER)
        out = zc_family(ints, floats, r, ws, eps, max_iter, WITH_IE);
    else if (method == ZC_IE_NEWTON)
        out = zc_family(ints, floats, r, ws, eps, max_iter, WITH_NEWTON);
    else
        out = dispatch_detail::distance_based(ints, floats, r, ws, method, eps, max_iter);
    out = certify(std::move(out), r, eps);
    // GJK-based's own stalls are its finish's (ZC's): walking the ray again would repeat them
    if (method == GJK_BASED) return out;
    return unstall(ints, floats, r, ws, eps, max_iter, std::move(out));
}

// `out`, or where it is a stall (a LIMIT short of max_iter: zc_from), GJK-based's answer when
// that one is certified. ZC's cone from b_k loses rank where the ray runs along a flat or thin
// part of A (W_Linf's lift for a doubled point contact and a wrench 1e-9 inside its friction
// cone, a 3-D set in R^7; two point contacts at a corner of W): ZC-based steps then stall with
// the bracket open, and IE and ZC-IE, which hand over to them, with them. GJK's simplex, walking
// down the ray from outside, does not lose rank there (and where GJK-based stops short, IE steps
// from its facet may not: distance_based).
Shot unstall(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Shot out) {
    if (!(out.status == LIMIT && out.iters < max_iter)) return out;
    Shot fin = dispatch_detail::distance_based(ints, floats, r, ws, GJK_BASED, eps,
                                               max_iter - out.iters);
    if (fin.status != LIMIT) return dispatch_detail::handed_over(out, std::move(fin));
    return dispatch_detail::handed_over(fin, std::move(out));
}

}  // namespace gf
