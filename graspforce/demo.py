"""The main job until the service exists: minimal contact forces for a four-finger grasp.

    python -m graspforce.demo

Four soft fingers hold a 10 cm box from its sides. For a few external wrenches (the box's weight,
then random pushes), every procedure of section 3 finds the minimal total normal force
sigma_L1 (eq. 13) on the exact elliptic soft-finger cones, with a certified lower bound; then the
four objectives of eq. (13) and (15), the contact forces read off the final simplex, force closure
and the grasp's Ferrari-Canny quality.
"""
import numpy as np

import graspforce as gf


def box_grasp(mu=0.5, mu_spin=0.01):
    """Two fingers on each of the box's x faces, pushing inwards."""
    points = [([0.05, 0.01, 0.0], [-1, 0, 0]), ([0.05, -0.01, 0.01], [-1, 0, 0]),
              ([-0.05, 0.01, 0.0], [1, 0, 0]), ([-0.05, -0.01, -0.01], [1, 0, 0])]
    return gf.Grasp(gf.Contact(p, n, mu, mu_spin) for p, n in points)


def main():
    grasp = box_grasp()
    rng = np.random.default_rng(1)
    wrenches = [np.array([0, 0, -9.81, 0, 0, 0])]
    wrenches += [np.concatenate([rng.normal(0, 3, 3), rng.normal(0, 0.05, 3)]) for _ in range(2)]
    print("4 soft fingers (mu 0.5, mu_spin 0.01 m) on a box; forces in N, torques in N m")
    for w in wrenches:
        print(f"\nw_ext = {np.round(w, 3)}")
        for method in gf.METHODS:
            res = grasp.min_force(w, method=method)
            sigma = (f"{res.sigma:12.6f} (certified >= {res.sigma_lower:.6f})" if res.feasible
                     else "infeasible")
            print(f"  {method:7s} {res.status:10s} sigma_L1 = {sigma}  iterations {res.iterations}")
    w = wrenches[1]
    print(f"\nw_ext = {np.round(w, 3)}: the four objectives (zc-ie)")
    for norm in ("L1", "Linf"):
        for magnitude in ("normal", "full"):
            res = grasp.min_force(w, norm=norm, magnitude=magnitude)
            print(f"  {norm:4s} {magnitude:6s} sigma = {res.sigma:.6f}  status {res.status}")
    res = grasp.min_force(w)
    print("  L1 normal: contact forces (f_n, f_o, f_t, spin) read off the final simplex:")
    for i, f in enumerate(res.forces):
        print(f"    contact {i + 1}: {np.array2string(f, precision=4, suppress_small=True)}")
    print(f"  equilibrium residual |sum G_i f_i + w_ext| = {np.linalg.norm(res.resultant + w):.1e}")
    quality = grasp.quality()
    print(f"\nforce closure: {grasp.is_force_closure()}; Ferrari-Canny quality (L1) in "
          f"[{quality.lower:.6f}, {quality.upper:.6f}]")


if __name__ == "__main__":
    main()
