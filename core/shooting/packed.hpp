#pragma once

#include "api.hpp"

// A ray-shooting result crosses to Python as scalars (the head) and one array that the caller
// allocated: the entry points called once per query write [extra (caller's data), normal (n),
// weights (k), vertices (k, n), witnesses (k, ws)] into a float array of `capacity` entries
// after the extra ones, and return the head; Python takes views of the array only when a field
// is read. Also ray_shoot.py's compiled entry point, shoot_packed.

namespace gf {

namespace packed_detail {

// read-only views of a shot's arrays
inline Vec vec_of(const Array& a) { return {const_cast<double*>(a.data.data()), a.size()}; }
inline Mat mat_of(const Array& a) {
    return {const_cast<double*>(a.data.data()), a.rows, a.cols, a.cols};
}

}  // namespace packed_detail

// normal, lam[:k], V[:k] and W[:k] written to packed[e:] (at least `capacity(n, ws)` entries),
// in the layout Python's `unpack` reads.
void pack_arrays(Vec normal, Mat V, Vec lam, Mat W, Int k, Vec packed, Int e) {
    const Int n = normal.n;
    const Int ws = W.cols;
    for (Int a = 0; a < n; ++a) packed[e + a] = normal[a];
    Int pos = e + n;
    for (Int j = 0; j < k; ++j) packed[pos + j] = lam[j];
    pos += k;
    for (Int j = 0; j < k; ++j)
        for (Int a = 0; a < n; ++a) packed[pos + n * j + a] = V(j, a);
    pos += n * k;
    for (Int j = 0; j < k; ++j)
        for (Int a = 0; a < ws; ++a) packed[pos + ws * j + a] = W(j, a);
}

// The head (status, t, t_upper, h_n, iterations, support_calls, singular_steps, k) of the
// shooters' result `out`, its arrays written to packed[e:] (`pack_arrays`).
Head pack(const Shot& out, Vec packed, Int e) {
    using namespace packed_detail;
    const Int k = out.k();
    pack_arrays(vec_of(out.normal), mat_of(out.V), vec_of(out.lam), mat_of(out.W), k, packed, e);
    return {out.status, out.t, out.t_up, out.h_n, out.iters, out.calls, out.singular, k};
}

// The head of the shot; its arrays into `packed`. Status BAD_RAY and no shot when r is not
// finite or is zero. table: the set's start table or an empty array.
Head shoot_packed(IVec ints, Vec floats, Vec r, Int ws, Int method, double eps, Int max_iter,
                  Vec packed, Vec table) {
    const double rr = dot(r, r);
    if (!(0.0 < rr && rr < INF)) return {BAD_RAY, 0.0, 0.0, 0.0, 0, 0, 0, 0};
    return pack(shoot_with_table(ints, floats, r, ws, method, eps, max_iter, table), packed, 0);
}

}  // namespace gf
