#pragma once

#include "api.hpp"

// Contact forces read off the final simplex Z_W(r): one compiled call per min_force shoots
// z = t r on the wrench set W (r = -w_ext) and reads the contacts' forces off the witnesses of
// Z_W(r)'s vertices.

namespace gf {

namespace forces {

// A Target's force reader (graspforce.grasping.wrench_space): how forces are read off witnesses, as
// one float array read by offsets. Layout: [witness size, linf, full, m, leaves L, length, table
// (4, L) by rows CONTACT, SLOT, SIZE, MAP, G (m, 6, 4), spin_weight (m,), mu (m,), mu_spin (m,),
// maps]. The set and G are in the units (force, torque / length) (docs/grasp-api.md).
constexpr Int READER_HEAD = 6;
constexpr Int LENGTH = 5;

// Entries [sigma, forces (m, 4), wrenches (m, 6), resultant (6,)] ahead of the ray-shooting
// arrays in the packed result of `shoot_and_read_forces`.
inline Int extra_size(Int m) { return 7 + 10 * m; }

}  // namespace forces

namespace forces_detail {

// rows of a wrench space's leaf table (graspforce.grasping.wrench_space.Target._table)
constexpr Int CONTACT = 0;
constexpr Int SLOT = 1;
constexpr Int SIZE = 2;
constexpr Int MAP = 3;
// the forces' certificate: sum_i G_i f_i + w_ext within RESIDUAL |w_ext| (the bound on an
// optimal answer's equilibrium residual), each f_i in F_i to CONE_ROUNDING relative to f_i1
// (every force is a nonnegative combination of unit forces on their cones' boundaries, each to a
// few ulps)
constexpr double RESIDUAL = 1e-9;
constexpr double CONE_ROUNDING = 1e-12;
// a load whose part outside a projected set's span is within SPAN_TOL of its size (in the reader's
// units, as the certificate's) is shot in the span: that part adds at most as much to the
// RESIDUAL the forces' certificate allows
constexpr double SPAN_TOL = 1e-10;

// sigma, with forces (m, 4), wrenches (m, 6) and resultant (6,) written to their entries of
// `packed` (zeroed by the caller), for z = sum_k weights_k v_k = t r, scale = 1/t, and the force
// reader of the shot set (G_i of eq. (11) among its parts).
//
// Every vertex v_k of Z_W(r) holds one wrench G_i u_ki (W_L1, or the lift of W_Linf, whose
// vertices' weights sum to 1/m per contact) or a sum of them (W_Linf itself), u_ki a unit contact
// force recovered from the vertex's witness row as base + map @ local (the reader's table: per
// leaf its contact, witness slot, local size and offset in maps). Then r = sum_i G_i f_i with
// f_i = sum_k (weights_k / t) u_ki: the forces resist w_ext = -r exactly, up to the rounding of
// the simplex. sigma is their objective (eq. 13 or 15), <= 1/t (1/(m t) on the lift) by the
// triangle inequality (equal when each contact appears in one vertex). For the full magnitude
// the reader's spin weights hold (mu_i / mu_si)^2 per contact (0 for point contacts), the weight
// of f_4^2 in ||f_i||.
inline double contact_forces(Mat W, Vec weights, double scale, Vec reader, Vec packed) {
    using forces::READER_HEAD;
    const bool linf = reader[1] != 0.0;
    const bool full = reader[2] != 0.0;
    const Int m = static_cast<Int>(reader[3]);
    const Int leaves = static_cast<Int>(reader[4]);
    const Int g0 = READER_HEAD + 4 * leaves;   // G_i
    const Int s0 = g0 + 24 * m;                // spin weights
    const Int m0 = s0 + 3 * m;                 // maps, after mu and mu_spin
    const Int f0 = 1;                          // forces, wrenches, resultant in packed
    const Int w0 = f0 + 4 * m;
    const Int r0 = w0 + 6 * m;
    for (Int k = 0; k < W.rows; ++k) {
        const double c = weights[k] * scale;
        for (Int j = 0; j < leaves; ++j) {
            const Int i = static_cast<Int>(reader[READER_HEAD + CONTACT * leaves + j]);
            const Int s = static_cast<Int>(reader[READER_HEAD + SLOT * leaves + j]);
            if (i < 0 || W(k, s) < 0.5) continue;
            const Int p = m0 + static_cast<Int>(reader[READER_HEAD + MAP * leaves + j]);
            const Int L = static_cast<Int>(reader[READER_HEAD + SIZE * leaves + j]);
            for (Int a = 0; a < 4; ++a) {
                double f = reader[p + a];
                for (Int b = 0; b < L; ++b) f += reader[p + 4 + a * L + b] * W(k, s + 1 + b);
                packed[f0 + 4 * i + a] += c * f;
            }
        }
    }
    double sigma = 0.0;
    for (Int i = 0; i < m; ++i) {
        const Int f = f0 + 4 * i;
        double value;
        if (full) {
            value = std::sqrt(packed[f] * packed[f] + packed[f + 1] * packed[f + 1] +
                              packed[f + 2] * packed[f + 2] +
                              reader[s0 + i] * (packed[f + 3] * packed[f + 3]));
        } else {
            value = packed[f];
        }
        if (linf)
            sigma = std::max(sigma, value);
        else
            sigma += value;
    }
    for (Int i = 0; i < m; ++i) {
        for (Int a = 0; a < 6; ++a) {
            double s = 0.0;
            for (Int b = 0; b < 4; ++b)
                s += reader[g0 + 24 * i + 4 * a + b] * packed[f0 + 4 * i + b];
            packed[w0 + 6 * i + a] = s;
            packed[r0 + a] += s;
        }
    }
    return sigma;
}

// Whether the forces and resultant that `contact_forces` wrote to `packed` resist the load -r to
// RESIDUAL relative, with each force in its friction cone (eq. 12) to CONE_ROUNDING: a few dot
// products and a square root per contact. r and the resultant are in the reader's units.
inline bool forces_hold(Vec r, Vec reader, Vec packed) {
    using forces::READER_HEAD;
    const Int m = static_cast<Int>(reader[3]);
    const Int leaves = static_cast<Int>(reader[4]);
    const Int mu0 = READER_HEAD + 4 * leaves + 24 * m + m;
    const Int f0 = 1;
    const Int r0 = f0 + 10 * m;
    double res = 0.0;
    for (Int a = 0; a < 6; ++a) {
        const double e = packed[r0 + a] - r[a];
        res += e * e;
    }
    if (!(res <= RESIDUAL * RESIDUAL * dot(r, r))) return false;
    for (Int i = 0; i < m; ++i) {
        const double mu = reader[mu0 + i];
        const double mu_s = reader[mu0 + m + i];
        const double f1 = packed[f0 + 4 * i], f2 = packed[f0 + 4 * i + 1],
                     f3 = packed[f0 + 4 * i + 2], f4 = packed[f0 + 4 * i + 3];
        const double tol = CONE_ROUNDING * f1;
        double excess;
        if (mu == 0.0)
            excess = std::max(std::sqrt(f2 * f2 + f3 * f3), std::abs(f4));
        else if (mu_s == 0.0)
            excess = std::max(std::sqrt(f2 * f2 + f3 * f3) / mu - f1, std::abs(f4));
        else
            excess = std::sqrt((f2 * f2 + f3 * f3) / (mu * mu) + f4 * f4 / (mu_s * mu_s)) - f1;
        if (!(f1 >= 0.0 && excess <= tol)) return false;
    }
    return true;
}

}  // namespace forces_detail

// One compiled call per min_force: z = t r on W by `method` (r = -w_ext), then the forces read
// off Z_W(r). start: the wrench set's start table or an empty array; then a wrench space's
// constant arguments: the shot set's program, its force reader and its span: empty for W (or
// W_Linf's lift) itself, or Q^T (k, 6) by rows for the image of a rank-deficient grasp's set in
// the range of [G_1 ... G_m] in the reader's units (Q an orthonormal basis of it;
// graspforce.grasping.wrench_space), whose ray is Q^T times the load in its last k coordinates.
//
// The set is shot in the reader's units (force, torque / length), along r = -(w_f, w_tau / length):
// t, the forces and sigma do not depend on them, and the wrenches and resultant are returned in
// the grasp's own units.
//
// Returns the head of the shot, whose arrays go to `packed` (extra_size(m) + capacity(n, ws)
// entries, n the shot set's dimension) after the extra entries [sigma, forces (m, 4), wrenches
// (m, 6), resultant (6,)];
// zero forces and sigma = inf when the ray misses W or the shot found no point of W on it.
// A hit is checked against the answer's own certificate (`forces_hold`, and 1 / t_upper <=
// sigma <= (1 + eps) / t_upper, each within eps and rounding): where it fails, the head's
// status is LIMIT, an answer with its bracket but not certified. Or, with no shot, a head
// whose status is ZERO_WRENCH or BAD_WRENCH. In a span, no answer but a certified hit or miss:
// the status FULL_SET (and no shot) for a load farther than SPAN_TOL |load| from it, or after
// a shot that ended short of its certificate, and the caller shoots at the full-dimensional set.
// (At the corners of two point contacts' W, where the load lies on the boundary of the wrenches
// they resist, 4% of the shots in R^5 stalled, all methods alike, where R^6's settle.)
Head shoot_and_read_forces(Vec w_ext, Int method, double eps, Int max_iter, Vec packed,
                           Vec start, IVec ints, Vec floats, Vec reader, Vec span) {
    using namespace forces_detail;
    const double ww = dot(w_ext, w_ext);
    // x.x is NaN or inf iff an entry is (or the squares overflow)
    if (w_ext.n != 6 || !std::isfinite(ww)) return {BAD_WRENCH, 0.0, 0.0, 0.0, 0, 0, 0, 0};
    if (ww == 0.0) return {ZERO_WRENCH, 0.0, 0.0, 0.0, 0, 0, 0, 0};
    // the load -w_ext in the reader's units, and r: the load, or Q^T times it in the span, after
    // the lift's m - 1 zeros for Linf (graspforce.grasping.wrench_space)
    const Int n = ints[blocks(ints[0]).DIM];   // the set's dimension: its root node's
    const Int k = span.n > 0 ? span.n / 6 : 6;
    const double length = reader[forces::LENGTH];
    double load_[6];
    const Vec load{load_, 6};
    for (Int a = 0; a < 3; ++a) load[a] = -w_ext[a];
    for (Int a = 3; a < 6; ++a) load[a] = -w_ext[a] / length;
    Array r_(n);
    const Vec r = r_.vec();
    if (span.n == 0) {
        for (Int a = 0; a < 6; ++a) r[n - 6 + a] = load[a];
    } else {
        double off[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        for (Int j = 0; j < k; ++j) {
            double s = 0.0;
            for (Int a = 0; a < 6; ++a) s += span[6 * j + a] * load[a];
            r[n - k + j] = s;
            for (Int a = 0; a < 6; ++a) off[a] += span[6 * j + a] * s;
        }
        double oo = 0.0;
        for (Int a = 0; a < 6; ++a) oo += (load[a] - off[a]) * (load[a] - off[a]);
        if (!(oo <= SPAN_TOL * SPAN_TOL * dot(load, load)))
            return {FULL_SET, 0.0, 0.0, 0.0, 0, 0, 0, 0};
    }
    Shot out = shoot_with_table(ints, floats, r, static_cast<Int>(reader[0]), method, eps,
                                max_iter, start);
    if (span.n > 0 && out.status == LIMIT) return {FULL_SET, 0.0, 0.0, 0.0, 0, 0, 0, 0};
    const double t = out.t;
    const Int m = static_cast<Int>(reader[3]);
    const Int e = forces::extra_size(m);
    for (Int a = 0; a < e; ++a) packed[a] = 0.0;
    // no point of W on the ray beyond the origin: no finite forces
    if (out.status == MISS || !(t > 0.0)) {
        packed[0] = INF;
        return pack(out, packed, e);
    }
    const double sigma = contact_forces(out.W.mat(), out.lam.vec(), 1.0 / t, reader, packed);
    packed[0] = sigma;
    Head head = pack(out, packed, e);
    if (out.status == HIT) {
        // t on W_Linf is m t' on its lift in R^(m - 1 + k); 1 on W itself (n = k)
        const double lower = 1.0 / (static_cast<double>(n - k + 1) * out.t_up);
        if (!(forces_hold(load, reader, packed) && lower <= sigma * (1.0 + eps) &&
              sigma <= lower * (1.0 + eps + 1e-15)))
            head.status = span.n > 0 ? FULL_SET : LIMIT;
    }
    // the torques back in the grasp's units
    const Int w0 = 1 + 4 * m;
    for (Int i = 0; i <= m; ++i)
        for (Int a = 3; a < 6; ++a) packed[w0 + 6 * i + a] *= length;
    return head;
}

}  // namespace gf
