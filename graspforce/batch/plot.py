"""The `plot` command: PNG figures of a batch. `slice`: sigma over a 2-D slice of wrench space,
with the feasible region's boundary and contour lines; `hist`: the histogram of sigma in a
result file; `coverage`: the fraction resisted against the budget, with its Wilson band."""
import pathlib

import numpy as np

from .coverage import coverage_curve, wilson_interval
from .inputs import WRENCH_COLUMNS, load_grasp


def add_plot_parser(subparsers):
    p = subparsers.add_parser("plot", help="figures of a batch, as PNG",
                              description=__doc__.split("\n")[0])
    kinds = p.add_subparsers(dest="kind", required=True)
    s = kinds.add_parser("slice", help="sigma over a 2-D slice of wrench space")
    s.add_argument("grasp", help="a shipped scenario's name or a grasp JSON file")
    s.add_argument("--axes", nargs=2, default=["fx", "fz"], choices=WRENCH_COLUMNS)
    s.add_argument("--range", nargs=2, type=float, default=[-20.0, 20.0], metavar=("LOW", "HIGH"))
    s.add_argument("--base", nargs=6, type=float, default=[0.0] * 6,
                   help="the wrench the slice goes through (fx fy fz tx ty tz)")
    s.add_argument("--grid", type=int, default=201, help="points per axis")
    s.add_argument("--norm", default="L1")
    s.add_argument("--magnitude", default="normal")
    for kind in ("hist", "coverage"):
        k = kinds.add_parser(kind, help={"hist": "histogram of sigma of a result file",
                                         "coverage": "coverage against budget of a result "
                                                     "file"}[kind])
        k.add_argument("result", help="a `graspforce batch` output, .parquet or .csv")
        k.add_argument("--bins", type=int, default=80)
    p.add_argument("--out", required=True, help="the PNG to write")
    p.set_defaults(run=run_plot)
    return p


def read_result(path):
    """(sigma, status names) of a `graspforce batch` output file."""
    import pyarrow.csv
    import pyarrow.parquet
    path = pathlib.Path(path)
    table = (pyarrow.parquet.read_table(path, columns=["sigma", "status"])
             if path.suffix.lower() == ".parquet" else
             pyarrow.csv.read_csv(path).select(["sigma", "status"]))
    return table.column("sigma").to_numpy(), table.column("status").to_numpy().astype(str)


def slice_grid(grasp, axes, low, high, base, grid, norm="L1", magnitude="normal"):
    """(x, y, sigma (grid, grid)) of min_force over the slice base + x e_a + y e_b."""
    from .forces import min_force
    a, b = (WRENCH_COLUMNS.index(ax) for ax in axes)
    x = np.linspace(low, high, grid)
    X, Y = np.meshgrid(x, x)
    w = np.tile(np.asarray(base, float), (grid * grid, 1))
    w[:, a] += X.ravel()
    w[:, b] += Y.ravel()
    return x, x, min_force(grasp, w, norm=norm, magnitude=magnitude).sigma.reshape(grid, grid)


def run_plot(args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.8), dpi=120)
    if args.kind == "slice":
        grasp = load_grasp(args.grasp)
        x, y, sigma = slice_grid(grasp, args.axes, *args.range, args.base, args.grid, args.norm,
                                 args.magnitude)
        finite = np.isfinite(sigma)
        shown = np.where(finite, sigma, np.nan)
        mesh = ax.pcolormesh(x, y, shown, shading="auto", cmap="viridis")
        fig.colorbar(mesh, ax=ax, label=f"sigma ({args.norm}, {args.magnitude})")
        if finite.any() and not finite.all():
            ax.contour(x, y, finite.astype(float), levels=[0.5], colors="red", linewidths=1.5)
        if np.count_nonzero(finite) > 3:
            levels = np.quantile(sigma[finite], [0.1, 0.3, 0.5, 0.7, 0.9])
            cs = ax.contour(x, y, shown, levels=np.unique(levels), colors="white",
                            linewidths=0.7)
            ax.clabel(cs, fmt="%.3g", fontsize=7)
        ax.set_xlabel(args.axes[0])
        ax.set_ylabel(args.axes[1])
        ax.set_title("minimal contact force over a wrench slice (red: feasible boundary)")
    else:
        sigma, status = read_result(args.result)
        finite = sigma[np.isfinite(sigma)]
        if args.kind == "hist":
            if finite.size:
                ax.hist(finite, bins=args.bins, color="tab:blue")
            ax.set_xlabel("sigma")
            ax.set_ylabel("wrenches")
            ax.set_title(f"{finite.size:,} feasible of {sigma.size:,} wrenches")
        else:
            ok = status != "bad_wrench"
            top = np.quantile(finite, 0.999) if finite.size else 1.0
            budgets = np.linspace(0.0, top, 400)
            frac = coverage_curve(sigma[ok], np.zeros(np.count_nonzero(ok), np.int8), budgets)
            n = int(np.count_nonzero(ok))
            band = np.array([wilson_interval(round(f * n), n) for f in frac])
            ax.fill_between(budgets, 100 * band[:, 0], 100 * band[:, 1], alpha=0.3,
                            label="95 % Wilson interval")
            ax.plot(budgets, 100 * frac, label="resisted")
            ax.set_xlabel("force budget")
            ax.set_ylabel("% of wrenches resisted")
            ax.legend()
    fig.tight_layout()
    fig.savefig(args.out)
    plt.close(fig)
    print(f"wrote {args.out}")
    return 0
