"""Batch throughput: gf.batch.min_force (L1, eps 1e-9) on 4 soft fingers (the ingot, and a
sphere grasp), all cores and one, against Clarabel's SOCP updated in a loop, timed in slices
alternating with our one-thread figure's; the Dask path on a 2-worker LocalCluster; 10^6
wrenches through `graspforce batch` to Parquet.

    python -m benchmarks.batch [--n 1000000] [--quick]

Writes benchmarks/results/batch.md. Wrenches: the paper's Table 5 protocol (gf.batch.table5).
"""
import argparse
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np

import graspforce as gf
from benchmarks.grasp_sets import ingot_grasp

RESULTS = pathlib.Path(__file__).parent / "results" / "batch.md"
SLICES = 10         # the one-thread figure's and Clarabel's alternating slices
CLARABEL_COUNT = 2000


def sphere_grasp(lam=0.5, mu=0.2, mu_spin=0.02):
    """NOTES.md item 1's four contacts on a unit sphere, as soft fingers."""
    alpha = (1.0 - lam) * np.arctan(mu)
    contacts = []
    for az in np.deg2rad([0.0, 90.0, 180.0, 270.0]):
        p = np.array([np.cos(alpha) * np.cos(az), np.cos(alpha) * np.sin(az), np.sin(alpha)])
        contacts.append(gf.Contact(p, -p, mu, mu_spin))
    return gf.Grasp(contacts)


def rate(grasp, wrenches, threads, repeats=3):
    """Best of `repeats` wrenches per second of one batch call."""
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        gf.batch.min_force(grasp, wrenches, eps=1e-9, threads=threads)
        best = min(best, time.perf_counter() - t)
    return len(wrenches) / best


def per_core(grasp, wrenches, clarabel_count, slices=SLICES):
    """Wrenches per second on one thread, ours and Clarabel's updated in a Python loop, timed in
    alternating slices (ours len(wrenches) / slices each, Clarabel's clarabel_count / slices),
    each side's best slice: a change of the machine's speed during the run reaches both."""
    from graspforce.grasping.baselines import clarabel_socp
    prepared = clarabel_socp.Prepared(grasp)
    prepared.solve_raw(wrenches[0])
    ours = clarabel = 0.0
    size, clarabel_size = len(wrenches) // slices, clarabel_count // slices
    for i in range(slices):
        part = wrenches[i * size:(i + 1) * size]
        t = time.perf_counter()
        gf.batch.min_force(grasp, part, eps=1e-9, threads=1)
        ours = max(ours, len(part) / (time.perf_counter() - t))
        part = wrenches[i * clarabel_size:(i + 1) * clarabel_size]
        t = time.perf_counter()
        for w in part:
            prepared.solve_raw(w)
        clarabel = max(clarabel, len(part) / (time.perf_counter() - t))
    return ours, clarabel


def dask_numbers(grasp, n, log):
    from distributed import Client, LocalCluster
    w = gf.batch.table5(n, seed=5)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        gf.batch.min_force(grasp, w[:1000], client=client, chunk_size=500)     # workers warm
        # overhead per chunk: many tiny chunks, minus their compute time
        tiny = w[:2000]
        t = time.perf_counter()
        gf.batch.min_force(grasp, tiny, client=client, chunk_size=10)
        tiny_wall = time.perf_counter() - t
        compute = len(tiny) / rate(grasp, tiny, 1, 1)
        per_chunk = (tiny_wall - compute / 2) / (len(tiny) / 10)
        t = time.perf_counter()
        remote = gf.batch.min_force(grasp, w, client=client)
        wall = time.perf_counter() - t
    local = gf.batch.min_force(grasp, w)
    same = all(np.array_equal(getattr(local, f), getattr(remote, f), equal_nan=True)
               for f in ("sigma", "sigma_lower", "status", "iterations"))
    log(f"dask: {per_chunk * 1e3:.2f} ms a chunk, {n / wall:,.0f} wrenches/s at {n:,} "
        f"({wall:.2f} s), equal to local: {same}")
    return per_chunk, n / wall, wall, same


def cli_numbers(n, log):
    root = pathlib.Path(__file__).resolve().parents[1]
    with tempfile.TemporaryDirectory() as d:
        grasp_json = pathlib.Path(d) / "ingot.json"
        contacts = ingot_grasp().contacts
        import json
        grasp_json.write_text(json.dumps({"contacts": [
            {"position": c.position.tolist(), "normal": c.normal.tolist(), "mu": c.mu,
             "mu_spin": c.mu_spin, "tangents": [t.tolist() for t in c.tangents]}
            for c in contacts]}))
        out = pathlib.Path(d) / "r.parquet"
        t = time.perf_counter()
        res = subprocess.run([sys.executable, "-m", "graspforce", "batch", str(grasp_json),
                              "--generate", "table5", "-n", str(n), "--out", str(out),
                              "--budget", "100"], cwd=root, capture_output=True, text=True)
        wall = time.perf_counter() - t
        if res.returncode != 0:
            raise RuntimeError(res.stderr)
        size = out.stat().st_size
    last_bar = res.stderr.strip().splitlines()[-1]
    log(f"cli: {n:,} wrenches in {wall:.2f} s ({size / 1e6:.1f} MB)\n{res.stdout}\n{last_bar}")
    return wall, res.stdout, last_bar, size


def main(argv=None):
    parser = argparse.ArgumentParser()
    parser.add_argument("--n", type=int, default=1_000_000)
    parser.add_argument("--quick", action="store_true", help="small sizes, no results file")
    args = parser.parse_args(argv)
    n_rate = 20_000 if args.quick else 200_000
    n_big = 20_000 if args.quick else args.n
    lines = []

    def log(s):
        print(s, flush=True)
        lines.append(s)

    cores = os.cpu_count()
    rows = []
    for name, grasp in (("ingot (4 soft)", ingot_grasp()), ("sphere (4 soft)", sphere_grasp())):
        w = gf.batch.table5(n_rate, seed=1)
        gf.batch.min_force(grasp, w[:1000])                       # the start table
        all_cores = rate(grasp, w, None)
        two = rate(grasp, w, 2)
        one, clar = per_core(grasp, w, CLARABEL_COUNT if not args.quick else 300)
        rows.append((name, all_cores, one, two, clar))
        log(f"{name}: all cores {all_cores:,.0f}/s, 1 thread {one:,.0f}/s, 2 threads "
            f"{two:,.0f}/s, Clarabel updated {clar:,.0f}/s: per core {one / clar:.1f}x")
    load = os.getloadavg()
    dask = dask_numbers(ingot_grasp(), n_big, log)
    cli = cli_numbers(n_big, log)
    if args.quick:
        return 0
    md = ["# Batch throughput (`python -m benchmarks.batch`)", "",
          f"{cores} cores; load average at the start of the run {load[0]:.2f} (the machine is "
          "shared: other processes' load lowers every figure). Wrenches: Table 5 protocol "
          f"(gf.batch.table5), {n_rate:,} per throughput figure; all cores and 2 threads: "
          "best of 3 calls; L1, magnitude normal, ZC-IE, eps 1e-9. Clarabel: "
          "graspforce.grasping.baselines.clarabel_socp.Prepared.solve_raw, the wrench updated per "
          "call and solved (no record built), in a Python loop. 1 thread and Clarabel: "
          f"{SLICES} alternating slices ({n_rate // SLICES:,} wrenches of ours, "
          f"{CLARABEL_COUNT // SLICES} of Clarabel's), each side's best slice.", "",
          "| grasp | all cores /s | 1 thread /s | 2 threads /s | 2 / 1 | Clarabel /s | per core "
          "vs Clarabel |", "|---|---|---|---|---|---|---|"]
    for name, a, one, two, clar in rows:
        md.append(f"| {name} | {a:,.0f} | {one:,.0f} | {two:,.0f} | {two / one:.2f} | "
                  f"{clar:,.0f} | {one / clar:.1f}x |")
    per_chunk, dask_rate, dask_wall, same = dask
    wall, summary, bar, size = cli
    md += ["", "Goals: >= 300,000 wrenches/s on all cores; >= 20x Clarabel per core.", "",
           "## Dask, 2-worker LocalCluster (1 thread each, processes)", "",
           f"- overhead per chunk: {per_chunk * 1e3:.2f} ms (2,000 wrenches in chunks of 10, "
           "less their compute time)",
           f"- {n_big:,} ingot wrenches in chunks of 50,000: {dask_wall:.2f} s, "
           f"{dask_rate:,.0f} wrenches/s; arrays equal to the local run: {same}", "",
           f"## `graspforce batch`, {n_big:,} wrenches to Parquet", "",
           f"Wall time {wall:.2f} s for the whole command (start-up, generation, 20 chunk files, "
           f"assembly, summary), {size / 1e6:.1f} MB. Its output:", "", "```", summary.strip(),
           bar, "```", ""]
    RESULTS.write_text("\n".join(md))
    print(f"wrote {RESULTS}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
