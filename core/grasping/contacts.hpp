// What a grasp made per query computes once: a contact's frame and G_i (eq. 11), and a wrench
// space's program and force reader gathered from a template (graspforce/grasping/wrench_space.py).
#pragma once

#include <cmath>

#include "arrays.hpp"

namespace gf::contacts {

// entries of a contact's array: G_i (6 x 4, row-major), then mu, mu_s, mu_s / mu and
// (mu / mu_s)^2 (0 for the last two without spin)
constexpr Int G = 24;
constexpr Int ENTRIES = G + 4;

// G_i and the friction entries of a contact at p with normal n (not normalized) into out
// (ENTRIES), the normalized normal into unit; false for a normal of length <= 1e-12. The
// arithmetic is graspforce/grasping/contact.py's, operation for operation; `dot3` is the dot
// product that contact.py's norms take (NumPy's, whose BLAS may fuse multiply-adds), passed in so
// that the norms round as NumPy's do.
template <class Dot3>
bool contact_entries(const double* p, const double* n_in, double mu, double mu_s, Dot3 dot3,
                     double* unit, double* out) {
    const double length = std::sqrt(dot3(n_in));
    if (!(length > 1e-12)) return false;
    const double nx = n_in[0] / length, ny = n_in[1] / length, nz = n_in[2] / length;
    unit[0] = nx;
    unit[1] = ny;
    unit[2] = nz;
    // the world axis least aligned with n, first on ties (np.argmin's); o = e_k - n_k n
    const double ax = std::fabs(nx), ay = std::fabs(ny), az = std::fabs(nz);
    const int k = ax <= ay && ax <= az ? 0 : (ay <= az ? 1 : 2);
    const double c = unit[k];
    double o[3] = {0.0 - c * nx, 0.0 - c * ny, 0.0 - c * nz};
    o[k] = 1.0 - c * unit[k];
    const double olength = std::sqrt(dot3(o));
    const double ox = o[0] / olength, oy = o[1] / olength, oz = o[2] / olength;
    const double tx = ny * oz - nz * oy, ty = nz * ox - nx * oz, tz = nx * oy - ny * ox;
    const double px = p[0], py = p[1], pz = p[2];
    const double g[G] = {nx, ox, tx, 0.0,
                         ny, oy, ty, 0.0,
                         nz, oz, tz, 0.0,
                         py * nz - pz * ny, py * oz - pz * oy, py * tz - pz * ty, nx,
                         pz * nx - px * nz, pz * ox - px * oz, pz * tx - px * tz, ny,
                         px * ny - py * nx, px * oy - py * ox, px * ty - py * tx, nz};
    for (Int i = 0; i < G; ++i) out[i] = g[i];
    out[G] = mu;
    out[G + 1] = mu_s;
    out[G + 2] = out[G + 3] = 0.0;
    if (mu_s > 0.0) {
        const double ratio = mu / mu_s;
        out[G + 2] = mu_s / mu;
        out[G + 3] = ratio * ratio;
    }
    return true;
}

// A template's gathers: floats[dst] = values[src] * values[scale] + add, reader[read_dst] =
// values[read_src] (graspforce.grasping.wrench_space._Template).
inline void fill_template(Vec values, Vec floats, IVec dst, IVec src, IVec scale, Vec add,
                          Vec reader, IVec read_dst, IVec read_src) {
    for (Int i = 0; i < dst.n; ++i) floats[dst[i]] = values[src[i]] * values[scale[i]] + add[i];
    for (Int i = 0; i < read_dst.n; ++i) reader[read_dst[i]] = values[read_src[i]];
}

}  // namespace gf::contacts
