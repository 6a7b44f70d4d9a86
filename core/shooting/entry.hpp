#pragma once

#include "api.hpp"

// Entry points of the distance algorithms, one call from Python each: the point of A closest to
// b (GJK) and the distance from b to the cone CO(A) (ZC).

namespace gf {

namespace entry_detail {

// the first k rows of a matrix A, as Python's A[:k].copy()
inline Array first_rows(Array&& A, Int k) {
    A.data.resize(static_cast<size_t>(k * A.cols));
    A.rows = k;
    return std::move(A);
}

// the first k entries of a vector x, as Python's x[:k].copy()
inline Array first(Array&& x, Int k) {
    x.data.resize(static_cast<size_t>(k));
    x.rows = k;
    return std::move(x);
}

// the arrays of one GJK or ZC call from the origin of its simplex
struct Work {
    Array P, Wt, lam, nvec, v, point, wit;
    ScratchArrays sc;
    Work(Int n, Int ws)
        : P(n + 2, n), Wt(n + 2, ws), lam(n + 2), nvec(n), v(n), point(n), wit(ws), sc(n) {}
};

}  // namespace entry_detail

ClosestOut closest_point(IVec ints, Vec floats, Vec b, Int ws, double eps, Int max_iter) {
    using entry_detail::first;
    using entry_detail::first_rows;
    entry_detail::Work w(b.n, ws);
    const DistOut o = gjk(ints, floats, b, w.P.mat(), w.Wt.mat(), w.lam.vec(), 0, eps, 0.0, false,
                          max_iter, w.nvec.vec(), w.v.vec(), w.point.vec(), w.wit.vec(), w.sc.sc);
    const double gap = o.status != INSIDE ? o.h - dot(w.nvec.vec(), w.v.vec()) : 0.0;
    return {o.status, o.d, gap, o.it, o.calls, std::move(w.v), first_rows(std::move(w.P), o.k),
            first(std::move(w.lam), o.k), first_rows(std::move(w.Wt), o.k)};
}

ConeOut cone_distance(IVec ints, Vec floats, Vec b, Int ws, double eps, Int max_iter) {
    using entry_detail::first;
    using entry_detail::first_rows;
    const Int n = b.n;
    entry_detail::Work w(n, ws);
    Array shift(n);   // zeros
    const DistOut o = zc(ints, floats, shift.vec(), b, w.P.mat(), w.Wt.mat(), w.lam.vec(), 0, 0.0,
                         eps, max_iter, w.nvec.vec(), w.v.vec(), w.point.vec(), w.wit.vec(),
                         w.sc.sc);
    if (o.status == INSIDE)
        for (Int i = 0; i < n; ++i) w.nvec.data[static_cast<size_t>(i)] = 0.0;
    return {o.status, o.d, o.h, o.it, o.calls, std::move(w.v), std::move(w.nvec),
            first_rows(std::move(w.P), o.k), first(std::move(w.lam), o.k),
            first_rows(std::move(w.Wt), o.k)};
}

}  // namespace gf
