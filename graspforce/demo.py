"""The main job until the service exists: shoot rays at a 4-contact grasp's wrench set.

    python -m graspforce.demo

W_L1 (eq. 14) of four soft fingers on a box: for a few external wrenches, every procedure of
section 3 finds z_W(-w_ext); sigma_L1 = ||w_ext|| / ||z|| = 1 / t is the minimum total normal
force that resists w_ext (section 5.1).
"""
import numpy as np

import graspforce as gf


def soft_finger_set(position, normal, mu, mu_spin):
    """W_i = G_i(U_i) of eq. (14): a rank-3 ellipsoid in wrench space."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    o = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    o /= np.linalg.norm(o)
    t = np.cross(n, o)
    p = np.asarray(position, float)
    G = np.zeros((6, 4))
    G[:3, :3] = np.column_stack([n, o, t])
    G[3:, :3] = np.column_stack([np.cross(p, n), np.cross(p, o), np.cross(p, t)])
    G[3:, 3] = n
    return gf.Ellipsoid(G[:, 0], G[:, 1:] @ np.diag([mu, mu, mu_spin]))


def main():
    contacts = [([0.05, 0.01, 0.0], [-1, 0, 0]), ([0.05, -0.01, 0.01], [-1, 0, 0]),
                ([-0.05, 0.01, 0.0], [1, 0, 0]), ([-0.05, -0.01, -0.01], [1, 0, 0])]
    W = gf.hull(*(soft_finger_set(p, n, 0.5, 0.01) for p, n in contacts))
    rng = np.random.default_rng(1)
    wrenches = [np.array([0, 0, -9.81, 0, 0, 0])]
    wrenches += [np.concatenate([rng.normal(0, 3, 3), rng.normal(0, 0.05, 3)]) for _ in range(2)]
    print("minimum total normal force sigma_L1 [N] for 4 soft fingers on a box")
    for w in wrenches:
        print(f"\nw_ext = {np.round(w, 3)}")
        for method in gf.METHODS:
            res = gf.ray_shoot(W, -w, method=method)
            sigma = f"{1 / res.t:12.6f} (certified >= {1 / res.t_upper:.6f})" if res.hit else \
                "infeasible"
            print(f"  {method:7s} {res.status:8s} sigma_L1 = {sigma}  iterations {res.iterations}")


if __name__ == "__main__":
    main()
