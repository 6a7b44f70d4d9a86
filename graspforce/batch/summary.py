"""A batch's summary: statuses, feasible fraction, sigma quantiles, coverage at a budget."""
import numpy as np

from .coverage import coverage_of
from .result import STATUSES

QUANTILES = (0.05, 0.25, 0.5, 0.75, 0.95, 0.99)


def summarize(sigma, status_names, budget=None, confidence=0.95, wall_time=None, computed=None):
    """{counts, feasible_fraction, sigma quantiles over the feasible rows, coverage, wall time,
    rate}: plain numbers, JSON-ready. status_names: (N,) strings of STATUSES."""
    status_names = np.asarray(status_names).astype(str)
    codes = np.zeros(len(status_names), np.int8)
    for k, name in enumerate(STATUSES):
        codes[status_names == name] = k
    sigma = np.asarray(sigma, float)
    n = len(sigma)
    finite = sigma[np.isfinite(sigma)]
    out = {"wrenches": n,
           "status": {name: int(np.count_nonzero(codes == k)) for k, name in enumerate(STATUSES)},
           "feasible_fraction": float(len(finite) / n) if n else float("nan"),
           "sigma_quantiles": ({f"q{round(100 * q):02d}": float(np.quantile(finite, q))
                                for q in QUANTILES} | {"max": float(finite.max())}
                               if len(finite) else {})}
    if budget is not None:
        c = coverage_of(sigma, codes, budget, confidence)
        out["coverage"] = {"budget": c.budget, "fraction": c.fraction, "resisted": c.resisted,
                           "total": c.total, "confidence": c.confidence,
                           "interval": list(c.interval), "interval_method": "wilson"}
    if wall_time is not None:
        out["wall_time_s"] = wall_time
        if computed is not None:
            out["computed_this_run"] = computed
            out["rate_per_s"] = computed / wall_time if wall_time > 0 else None
    return out


def text(summary):
    """The summary as a few lines for a terminal."""
    lines = [f"wrenches: {summary['wrenches']:,}  " +
             "  ".join(f"{k}: {v:,}" for k, v in summary["status"].items()),
             f"feasible: {100 * summary['feasible_fraction']:.2f} %"]
    q = summary["sigma_quantiles"]
    if q:
        lines.append("sigma quantiles: " + "  ".join(f"{k} {v:.4g}" for k, v in q.items()))
    c = summary.get("coverage")
    if c:
        lo, hi = c["interval"]
        lines.append(f"coverage at budget {c['budget']:g}: {100 * c['fraction']:.2f} % "
                     f"({100 * c['confidence']:g} % Wilson interval {100 * lo:.2f}-{100 * hi:.2f} %)")
    if "wall_time_s" in summary:
        rate = summary.get("rate_per_s")
        lines.append(f"wall time: {summary['wall_time_s']:.2f} s" +
                     (f" ({summary['computed_this_run']:,} computed, {rate:,.0f}/s)"
                      if rate else ""))
    return "\n".join(lines)
