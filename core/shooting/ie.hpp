#pragma once

#include "api.hpp"

// The generalized internal-expanding (IE) procedure of section 3.2, with facet and ridge
// collections, so that it converges when the ray crosses a face of dimension lower than n - 1.
//
// State: b_k = t r on the face CH(S_k) of the inner polytope CH(support points), and the
// collection F_k of facets (n support points each) that contain S_k. A facet is stored by its
// hyperplane y^T x = 1 (so its distance from the origin is 1/||y||, its unit normal y/||y||) and
// the conic coordinates gam of r in its vertices (r = sum gam_l a_l, t = 1 / sum gam). A vertex
// of S_k is one with gam_l > 0.
//
// Each iteration takes the facet i* nearest the origin, evaluates s = s_A(n_i*), and stops when
// h_A(n_i*) - n_i*^T b_k <= eps n_i*^T b_k. Otherwise, with F+ the facets s lies beyond:
// - case 1 (F+ = F_k): the ray leaves through one of the facets that join s to the ridges of F_k
//   not containing S_k; b_{k+1} is the farthest crossing, F_{k+1} every new facet through it;
// - case 2 (F+ a proper sub-collection): each visible facet's ridges that contain S_k and are not
//   shared with another visible facet are joined to s; b_k and S_k stay, the nearest facet moves
//   away from the origin, so case 1 follows after finitely many steps (the paper's argument).

namespace gf::ie_detail {

constexpr double FACE_TOL = 1e-12;    // gam_l <= FACE_TOL * sum(gam): vertex l is not in the face of b_k
constexpr double BEYOND_TOL = 1e-12;  // y^T s > 1 + BEYOND_TOL: s lies beyond the facet

// row g of an (rows, n) int64 matrix stored row-major in `a`
[[gnu::always_inline]] inline IVec irow(IArray& a, Int g, Int n) {
    return {a.data.data() + g * n, n};
}

// sum of x in index order
[[gnu::always_inline]] inline double vsum(Vec x) {
    double s = 0.0;
    for (Int i = 0; i < x.n; ++i) s += x[i];
    return s;
}

// the smallest entry of x; NaN as soon as one entry is NaN (as the compiled array min)
[[gnu::always_inline]] inline double vmin(Vec x) {
    double m = x[0];
    if (std::isnan(m)) return m;
    for (Int i = 1; i < x.n; ++i) {
        const double v = x[i];
        if (std::isnan(v)) return v;
        if (v < m) m = v;
    }
    return m;
}

// LU of the matrix whose columns are the facet's vertices pool[idx]; false if singular.
inline bool factor(Mat pool, IVec idx, Mat M, Mat lu, IVec piv) {
    const Int n = idx.n;
    for (Int j = 0; j < n; ++j)
        for (Int i = 0; i < n; ++i) M(i, j) = pool(idx[j], i);
    return lu_factor(M, n, lu, piv);
}

// Hyperplane y and conic coordinates gam of the facet with vertices pool[idx]; false when it is
// degenerate or does not face the ray (y^T r <= 0).
inline bool facet(Mat pool, IVec idx, Vec r, Mat M, Mat lu, IVec piv, Vec ones, Vec y, Vec gam) {
    const Int n = r.n;
    if (!factor(pool, idx, M, lu, piv)) return false;
    lu_solve_t(lu, piv, n, ones, y);
    lu_solve(lu, piv, n, r, gam);
    return dot(y, r) > 0.0;
}

// The vertex j* that s replaces so that the ray still crosses the facet: with
// s = sum alpha_l a_l, j* minimizes gam_j / alpha_j over alpha_j > 0. -1 on a tie (the ray would
// cross a lower-dimensional face: the general step handles it) or a singular facet.
inline Int ratio_test(Mat pool, IVec fac, Vec gam, Vec s, Mat M, Mat lu, IVec piv, Vec alpha) {
    const Int n = s.n;
    if (!factor(pool, fac, M, lu, piv)) return -1;
    lu_solve(lu, piv, n, s, alpha);
    Int js = -1;
    double best = INF;
    double second = INF;
    for (Int j = 0; j < n; ++j) {
        if (alpha[j] > 0.0) {
            const double ratio = gam[j] / alpha[j];
            if (ratio < best) {
                second = best;
                best = ratio;
                js = j;
            } else if (ratio < second) {
                second = ratio;
            }
        }
    }
    if (js >= 0 && second <= best * (1.0 + 1e-9)) return -1;
    return js;
}

// A facet collection: vertex indices F (cap, n), hyperplanes Y (cap, n), conic coordinates
// GAM (cap, n). Its capacity is fixed.
struct Facets {
    Int cap, n;
    IArray F;
    Array Y, GAM;
    // rows past the count are never read: left uninitialized
    Facets(Int cap_, Int n_)
        : cap(cap_), n(n_), F(IArray::uninitialized(cap_ * n_)),
          Y(Array::uninitialized(cap_, n_)), GAM(Array::uninitialized(cap_, n_)) {}
    IVec f(Int g) { return irow(F, g, n); }
    Vec y(Int g) { return Y.mat().row(g); }
    Vec gam(Int g) { return GAM.mat().row(g); }
};

// Append a facet to a collection; -1 when the collection is full.
inline Int push(Facets& C, Int nf, IVec idx, Vec y, Vec gam) {
    if (nf == C.cap) return -1;
    IVec fr = C.f(nf);
    Vec yr = C.y(nf), gr = C.gam(nf);
    for (Int j = 0; j < C.n; ++j) fr[j] = idx[j];
    for (Int j = 0; j < C.n; ++j) yr[j] = y[j];
    for (Int j = 0; j < C.n; ++j) gr[j] = gam[j];
    return nf + 1;
}

// Whether facet row F[g] holds all m indices of `ridge`.
inline bool contains(Facets& C, Int g, IVec ridge, Int m) {
    const Int n = C.n;
    IVec fg = C.f(g);
    for (Int a = 0; a < m; ++a) {
        bool found = false;
        for (Int j = 0; j < n; ++j) {
            if (fg[j] == ridge[a]) {
                found = true;
                break;
            }
        }
        if (!found) return false;
    }
    return true;
}

// Z_A(r): the vertices of the facet that carry b_k (gam > 0), with weights gam t.
struct Face {
    Array V, W, lam;
    Int k;
};
inline Face face(Mat pool, Mat pwit, IVec fac, Vec gam, double t) {
    const Int n = fac.n;
    const double gsum = vsum(gam);
    Int k = 0;
    for (Int a = 0; a < n; ++a)
        if (gam[a] > FACE_TOL * gsum) k += 1;
    Face out{Array(k, n), Array(k, pwit.cols), Array(k), 0};
    Mat V = out.V.mat(), W = out.W.mat();
    Vec lam = out.lam.vec();
    k = 0;
    for (Int a = 0; a < n; ++a) {
        if (gam[a] > FACE_TOL * gsum) {
            for (Int i = 0; i < n; ++i) V(k, i) = pool(fac[a], i);
            for (Int i = 0; i < W.cols; ++i) W(k, i) = pwit(fac[a], i);
            lam[k] = gam[a];
            k += 1;
        }
    }
    const double ls = vsum(lam);
    for (Int j = 0; j < k; ++j) lam[j] /= ls;
    out.k = k;
    return out;
}

inline Shot ie_result(Int status, double t, Mat pool, Mat pwit, IVec fac, Vec gam, Vec nvec,
                      double h, double ny, Vec r, Int it, Int calls, Int singular) {
    Face fc = face(pool, pwit, fac, gam, t);
    const double t_up = h / dot(nvec, r);
    return make_result(status, t, t_up, h, it, calls, nvec, fc.V.mat(), fc.lam.vec(),
                       fc.W.mat(), fc.k, singular);
}

// ZC-based iterations from b_k on the facet's face: where rounding left IE no candidate.
inline Shot from_facet(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, double t,
                       Mat pool, Mat pwit, IVec fac, Vec gam, Int it, Int calls) {
    Face fc = face(pool, pwit, fac, gam, t);
    return zc_from_simplex(ints, floats, r, ws, eps, max_iter, ZC_ONLY, t, fc.V.mat(), fc.W.mat(),
                           fc.lam.vec(), fc.k, it, calls);
}

}  // namespace gf::ie_detail

namespace gf {

Shot ie(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter) {
    Shot out = first_facet(ints, floats, r, ws, eps, max_iter);
    if (out.status != FACET) return out;
    return ie_from(ints, floats, r, ws, eps, max_iter, out.V.mat(), out.W.mat(), out.iters,
                   out.calls);
}

// IE's steps from the facet V[:n] (support points of A, witnesses Wv) that the ray crosses:
// ZC's first facet (`ie`) or a start table's (start_table.hpp).
Shot ie_from(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Mat V, Mat Wv,
             Int it, Int calls) {
    using namespace ie_detail;
    const Int n = r.n;
    const Int cap_pts = n + 1 + max_iter;
    // rows past npts are never read: left uninitialized (max_iter + n + 1 rows)
    Array pool_a = Array::uninitialized(cap_pts, n), pwit_a = Array::uninitialized(cap_pts, ws);
    Mat pool = pool_a.mat(), pwit = pwit_a.mat();
    for (Int j = 0; j < n; ++j) {
        for (Int i = 0; i < n; ++i) pool(j, i) = V(j, i);
        for (Int i = 0; i < ws; ++i) pwit(j, i) = Wv(j, i);
    }
    Int npts = n;
    // the collections have a fixed capacity: a full one ends the shot with LIMIT
    const Int cap_f = 64 * n;
    Facets C(cap_f, n), C2(cap_f, n);
    // work: M, lu (n, n); ones, y, gam, nvec, point (n); wit (ws)
    Array mats(2 * n, n), vecs(5, n), wit_a(ws);
    Mat M = mats.mat().rows_range(0, n), lu = mats.mat().rows_range(n, 2 * n);
    Vec ones = vecs.mat().row(0), y = vecs.mat().row(1), gam = vecs.mat().row(2),
        nvec = vecs.mat().row(3), point = vecs.mat().row(4), wit = wit_a.vec();
    for (Int i = 0; i < n; ++i) ones[i] = 1.0;
    IArray ints_a(3 * n);
    IVec piv{ints_a.data.data(), n}, idx{ints_a.data.data() + n, n},
        ridge{ints_a.data.data() + 2 * n, n};
    std::vector<char> visible(static_cast<size_t>(cap_f));
    for (Int j = 0; j < n; ++j) C.f(0)[j] = j;
    if (!facet(pool, C.f(0), r, M, lu, piv, ones, C.y(0), C.gam(0)))
        return zc_family(ints, floats, r, ws, eps, max_iter, 0);
    Int nf = 1;
    double t = 1.0 / dot(C.y(0), r);
    Int best = 0;
    double h = 0.0;
    double ny = 1.0;
    Int singular = 0;
    bool queried = false;  // a support call of this loop bounds t from above
    bool closed = false;   // and its stopping rule held
    // the pool of points or the list of facets is full: the shot ends unfinished, as it stands
    auto out_of_room = [&]() {
        return ie_result(LIMIT, t, pool, pwit, C.f(best), C.gam(best), nvec, h, ny, r, it, calls,
                         singular);
    };
    // rounding left no candidate facet crossing the ray: ZC-based iterations finish from the best
    auto from_best = [&]() {
        return from_facet(ints, floats, r, ws, eps, max_iter, t, pool, pwit, C.f(best),
                          C.gam(best), it, calls);
    };
    while (it < max_iter) {
        // the facet of F_k nearest the origin: largest ||y||
        best = 0;
        double by = 0.0;
        for (Int f = 0; f < nf; ++f) {
            const double yy = dot(C.y(f), C.y(f));
            if (yy > by) {
                by = yy;
                best = f;
            }
        }
        ny = std::sqrt(by);
        for (Int i = 0; i < n; ++i) nvec[i] = C.Y.mat()(best, i) / ny;
        h = support(ints, floats, nvec, point, wit);
        calls += 1;
        it += 1;
        queried = true;
        if (h - 1.0 / ny <= eps / ny) {
            closed = true;
            break;
        }
        if (npts == cap_pts) return out_of_room();
        const Int q = npts;
        for (Int i = 0; i < n; ++i) pool(q, i) = point[i];
        for (Int i = 0; i < ws; ++i) pwit(q, i) = wit[i];
        npts += 1;
        bool all_visible = true;
        for (Int f = 0; f < nf; ++f) {
            visible[f] = dot(C.y(f), point) > 1.0 + BEYOND_TOL;
            all_visible = all_visible && visible[f];
        }
        Int nf2 = 0;
        if (nf == 1 && vmin(C.gam(0)) > FACE_TOL * vsum(C.gam(0))) {
            // b_k inside the single facet (the usual case): the ratio test of the simplex
            // method picks the new facet with one solve instead of n factorizations
            const Int js = ratio_test(pool, C.f(0), C.gam(0), point, M, lu, piv, y);
            if (js >= 0) {
                for (Int j = 0; j < n; ++j) idx[j] = C.f(0)[j];
                idx[js] = q;
                if (facet(pool, idx, r, M, lu, piv, ones, y, gam)) {
                    const double yr = dot(y, r);
                    if (vmin(gam) > FACE_TOL * yr) {
                        IVec f0 = C.f(0);
                        Vec y0 = C.y(0), g0 = C.gam(0);
                        for (Int j = 0; j < n; ++j) f0[j] = idx[j];
                        for (Int j = 0; j < n; ++j) y0[j] = y[j];
                        for (Int j = 0; j < n; ++j) g0[j] = gam[j];
                        t = 1.0 / yr;
                        continue;
                    }
                }
            }
        }
        if (all_visible) {
            // case 1: replace each vertex of S_k in each facet by s; keep the farthest crossing
            double t_best = t;
            for (Int f = 0; f < nf; ++f) {
                const double gsum = vsum(C.gam(f));
                for (Int a = 0; a < n; ++a) {
                    if (C.GAM.mat()(f, a) <= FACE_TOL * gsum) continue;
                    for (Int j = 0; j < n; ++j) idx[j] = C.f(f)[j];
                    idx[a] = q;
                    if (!facet(pool, idx, r, M, lu, piv, ones, y, gam)) continue;
                    const double yr = dot(y, r);
                    if (vmin(gam) < -FACE_TOL * yr) continue;
                    const double tc = 1.0 / yr;
                    if (tc < t_best * (1.0 - 1e-12)) continue;
                    if (tc > t_best * (1.0 + 1e-12)) {
                        // strictly farther: the earlier candidates cross elsewhere
                        t_best = tc;
                        nf2 = 0;
                    }
                    nf2 = push(C2, nf2, idx, y, gam);
                    if (nf2 < 0) return out_of_room();
                }
            }
            if (nf2 == 0) return from_best();
            t = t_best;
        } else {
            // case 2: keep the facets s does not see; join s to the ridges that contain S_k
            // and border a facet s does not see
            for (Int f = 0; f < nf; ++f)
                if (!visible[f]) nf2 = push(C2, nf2, C.f(f), C.y(f), C.gam(f));
            for (Int f = 0; f < nf; ++f) {
                if (!visible[f]) continue;
                const double gsum = vsum(C.gam(f));
                for (Int a = 0; a < n; ++a) {
                    // dropping a vertex of S_k: this ridge does not contain S_k
                    if (C.GAM.mat()(f, a) > FACE_TOL * gsum) continue;
                    Int m = 0;
                    for (Int j = 0; j < n; ++j) {
                        if (j != a) {
                            ridge[m] = C.f(f)[j];
                            m += 1;
                        }
                    }
                    bool shared = false;
                    for (Int g = 0; g < nf; ++g) {
                        if (g != f && visible[g] && contains(C, g, ridge, n - 1)) {
                            shared = true;
                            break;
                        }
                    }
                    if (shared) continue;
                    for (Int j = 0; j < n; ++j) idx[j] = C.f(f)[j];
                    idx[a] = q;
                    if (!facet(pool, idx, r, M, lu, piv, ones, y, gam)) continue;
                    nf2 = push(C2, nf2, idx, y, gam);
                    if (nf2 < 0) return out_of_room();
                }
            }
            if (nf2 == 0) return from_best();
        }
        nf = nf2;
        if (nf > 1) singular += 1;  // b_k sits on a face of dimension < n - 1 shared by nf facets
        std::copy(C2.F.data.begin(), C2.F.data.begin() + nf * n, C.F.data.begin());
        std::copy(C2.Y.data.begin(), C2.Y.data.begin() + nf * n, C.Y.data.begin());
        std::copy(C2.GAM.data.begin(), C2.GAM.data.begin() + nf * n, C.GAM.data.begin());
    }
    if (!queried) {
        // no step was left (the facet came on the last allowed iteration, or max_iter is 0):
        // t is certified from below by the facet, and no hyperplane bounds it from above
        Face fc = face(pool, pwit, C.f(0), C.gam(0), t);
        return make_result(LIMIT, t, INF, 0.0, it, calls, nvec, fc.V.mat(), fc.lam.vec(),
                           fc.W.mat(), fc.k, singular);
    }
    return ie_result(closed ? HIT : LIMIT, t, pool, pwit, C.f(best), C.gam(best), nvec, h, ny, r,
                     it, calls, singular);
}

}  // namespace gf
