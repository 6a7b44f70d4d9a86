"""Draws docs/architecture.png: how a request flows through graspforce.

    python docs/architecture.py
"""
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyArrowPatch, FancyBboxPatch  # noqa: E402

# (x, y, width, height, title, detail, colour): the layers, top (callers) to bottom (kernel)
BOXES = {
    "callers": (0.5, 9.0, 9.0, 0.9, "Python API  ·  REST service  ·  client  ·  CLI  ·  batch",
                "import graspforce as gf; server/ and the CLI add no math", "#e8eef7"),
    "robot": (0.5, 7.4, 4.2, 1.1, "Robot scenario (robots/*.toml)",
              "Pinocchio: frames, Jacobians, CoM -> contacts, load", "#eef7e8"),
    "wrench": (5.3, 7.4, 4.2, 1.1, "Contacts and load",
               "gf.Contact(p, n, mu, mu_spin), w_ext", "#eef7e8"),
    "grasp": (0.5, 5.8, 9.0, 1.1, "Grasp -> wrench set W (eq. 14)",
              "G_i of eq. 11; W_L1 = CH(W_i), W_Linf's lift; compiled to a support program "
              "(ints, floats)", "#fdf3e3"),
    "shooter": (0.5, 4.1, 9.0, 1.2, "Ray shooter (graspforce._core, C++): z_W(r) on R(-w_ext)",
                "ZC-IE (default), IE, ZC-based, GJK-based, Bi-GJK; start table; "
                "stopping rule t_upper/t - 1 <= eps", "#f7e8ee"),
    "distance": (0.5, 2.6, 4.2, 1.0, "GJK / ZC", "point to set, point to cone (section 2)",
                 "#f7e8ee"),
    "kernel": (5.3, 2.6, 4.2, 1.0, "Support kernel", "h_W(u), s_W(u) and witnesses (eq. 2)",
               "#f7e8ee"),
    "record": (0.5, 0.6, 9.0, 1.3, "Certified record",
               "MinForce: sigma, sigma_lower (the bracket), forces read off the witnesses of "
               "Z_W(r), status", "#e8f7f5"),
}
ARROWS = [("callers", "robot"), ("callers", "wrench"), ("robot", "grasp"), ("wrench", "grasp"),
          ("grasp", "shooter"), ("shooter", "distance"), ("shooter", "kernel"),
          ("distance", "kernel"), ("shooter", "record")]


def centre(box, side):
    x, y, w, h = BOXES[box][:4]
    return {"top": (x + w / 2, y + h), "bottom": (x + w / 2, y), "left": (x, y + h / 2),
            "right": (x + w, y + h / 2)}[side]


def main(path=Path(__file__).with_name("architecture.png")):
    fig, ax = plt.subplots(figsize=(10, 10.5))
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 10.2)
    ax.axis("off")
    for x, y, w, h, title, detail, colour in BOXES.values():
        ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0.02,rounding_size=0.12",
                                    facecolor=colour, edgecolor="#445"))
        ax.text(x + w / 2, y + h * 0.64, title, ha="center", va="center", fontsize=11,
                weight="bold")
        ax.text(x + w / 2, y + h * 0.28, detail, ha="center", va="center", fontsize=8.5,
                wrap=True)
    for a, b in ARROWS:
        if a == "distance" and b == "kernel":
            start, end = centre(a, "right"), centre(b, "left")
        elif a == "shooter" and b == "record":
            start, end = (1.0, BOXES[a][1]), (1.0, BOXES[b][1] + BOXES[b][3])
        else:
            start, end = centre(a, "bottom"), centre(b, "top")
        ax.add_patch(FancyArrowPatch(start, end, arrowstyle="-|>", mutation_scale=14,
                                     color="#445", lw=1.2))
    ax.text(5.0, 0.15, "Z_W(r) and its witnesses flow back up: forces f_i = sum_k (lambda_k / t) "
            "u_ki, exact on the elliptic cones", ha="center", fontsize=8.5, style="italic")
    fig.savefig(path, dpi=110, bbox_inches="tight")


if __name__ == "__main__":
    main()
