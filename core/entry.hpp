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

}  // namespace entry_detail

ClosestOut closest_point(IVec ints, Vec floats, Vec b, Int ws, double eps, Int max_iter) {
    using entry_detail::first;
    using entry_detail::first_rows;
    const Int n = b.n;
    Array P(n + 2, n);
    Array Wt(n + 2, ws);
    Array lam(n + 2);
    Array nvec(n);
    Array v(n);
    Array point(n);
    Array wit(ws);
    ScratchArrays sc(n);
    const DistOut o = gjk(ints, floats, b, P.mat(), Wt.mat(), lam.vec(), 0, eps, 0.0, false,
                          max_iter, nvec.vec(), v.vec(), point.vec(), wit.vec(), sc.sc);
    const double gap = o.status != INSIDE ? o.h - dot(nvec.vec(), v.vec()) : 0.0;
    return {o.status, o.d, gap, o.it, o.calls, std::move(v), first_rows(std::move(P), o.k),
            first(std::move(lam), o.k), first_rows(std::move(Wt), o.k)};
}

ConeOut cone_distance(IVec ints, Vec floats, Vec b, Int ws, double eps, Int max_iter) {
    using entry_detail::first;
    using entry_detail::first_rows;
    const Int n = b.n;
    Array P(n + 2, n);
    Array Wt(n + 2, ws);
    Array lam(n + 2);
    Array nvec(n);
    Array v(n);
    Array point(n);
    Array wit(ws);
    Array shift(n);   // zeros
    ScratchArrays sc(n);
    const DistOut o = zc(ints, floats, shift.vec(), b, P.mat(), Wt.mat(), lam.vec(), 0, 0.0, eps,
                         max_iter, nvec.vec(), v.vec(), point.vec(), wit.vec(), sc.sc);
    if (o.status == INSIDE)
        for (Int i = 0; i < n; ++i) nvec.data[static_cast<size_t>(i)] = 0.0;
    return {o.status, o.d, o.h, o.it, o.calls, std::move(v), std::move(nvec),
            first_rows(std::move(P), o.k), first(std::move(lam), o.k),
            first_rows(std::move(Wt), o.k)};
}

}  // namespace gf
