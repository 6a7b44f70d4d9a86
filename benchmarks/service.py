"""The service under load: latency and throughput of POST /v1/force-optimization, a 10,000-wrench
batch end to end, and the time from `graspforce serve` to the first 200 on /readyz.

    python -m benchmarks.service                 # 5 s per load run
    python -m benchmarks.service --duration 3 --out /tmp/service.md

Run from the repository root with the `service` extra installed and wrk on the PATH (Debian:
apt-get install wrk). Everything binds 127.0.0.1. Measured, one server process at a time, each
started as `python -m graspforce serve` with one worker (the command the Dockerfile runs):
- serve to ready: from starting the process to the first 200 on /readyz, median of --starts;
- our POST /v1/force-optimization (4 soft fingers, the demo grasp, L1, zc-ie, eps 1e-9, the
  same body every request) by wrk from a second process: p50 and p99 at 1 connection (1
  thread), requests/s at 32 connections (2 threads) and the server's CPU time a request there,
  errors (socket errors and non-2xx);
- beside it, in the same run, the bare framework: a FastAPI app that validates the same
  pydantic body (server.models.ForceOptimizationIn) and returns {"ok": true} without solving,
  on the same uvicorn settings;
- a batch of 10,000 wrenches (drawn by graspforce.batch.wrenches.gaussian, seed 1: forces
  N(0, 3 N), torques N(0, 0.05 N m) about the weight) sent as JSON by httpx and answered in full: median of 5 round trips,
  and the same with the service drawing them from a seed.
Writes benchmarks/results/service.md.
"""
import argparse
import json
import os
import re
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx

ROOT = Path(__file__).resolve().parent.parent
CONTACTS = [
    {"position": [0.05, 0.01, 0.0], "normal": [-1, 0, 0], "mu": 0.5, "mu_spin": 0.01},
    {"position": [0.05, -0.01, 0.01], "normal": [-1, 0, 0], "mu": 0.5, "mu_spin": 0.01},
    {"position": [-0.05, 0.01, 0.0], "normal": [1, 0, 0], "mu": 0.5, "mu_spin": 0.01},
    {"position": [-0.05, -0.01, -0.01], "normal": [1, 0, 0], "mu": 0.5, "mu_spin": 0.01}]
BODY = {"contacts": CONTACTS, "w_ext": [0.3, -0.2, -9.81, 0.01, 0.02, -0.005], "norm": "L1",
        "magnitude": "normal", "method": "zc-ie", "eps": 1e-9}


def bare_app():
    """FastAPI validating the same body as ours and answering without solving."""
    from fastapi import FastAPI

    from server.models import ForceOptimizationIn
    app = FastAPI()

    @app.post("/v1/force-optimization")
    async def force_optimization(body: ForceOptimizationIn):
        return {"ok": True}

    @app.get("/readyz")
    async def readyz():
        return {"status": "ready"}

    return app


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start(command, port):
    """(process, seconds from start to the first 200 on /readyz)."""
    begin = time.perf_counter()
    proc = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    url = f"http://127.0.0.1:{port}/readyz"
    while True:
        try:
            if httpx.get(url, timeout=1).status_code == 200:
                return proc, time.perf_counter() - begin
        except httpx.TransportError:
            pass
        if proc.poll() is not None or time.perf_counter() - begin > 60:
            proc.kill()
            raise RuntimeError(f"{command} did not become ready")
        time.sleep(0.005)


def cpu_seconds(pid):
    """User + system CPU seconds of a process so far (/proc): a server's CPU a request depends
    far less on other work sharing the machine than its rate does."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def stop(proc):
    proc.terminate()
    try:
        proc.wait(10)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


def ours(port):
    return [sys.executable, "-m", "graspforce", "serve", "--port", str(port)]


def bare(port):
    return [sys.executable, "-m", "uvicorn", "--factory", "benchmarks.service:bare_app",
            "--host", "127.0.0.1", "--port", str(port), "--log-level", "warning"]


def wrk(url, connections, threads, duration, script):
    """{p50_ms, p99_ms, rps, errors} of one wrk run."""
    out = subprocess.run(["wrk", f"-t{threads}", f"-c{connections}", f"-d{duration}s",
                          "--latency", "-s", script, url], capture_output=True, text=True,
                         check=True).stdout

    def ms(label):
        m = re.search(rf"^\s*{label}%\s+([\d.]+)(us|ms|s)\s*$", out, re.M)
        value, unit = float(m.group(1)), m.group(2)
        return value * {"us": 1e-3, "ms": 1.0, "s": 1e3}[unit]

    rps = float(re.search(r"Requests/sec:\s+([\d.]+)", out).group(1))
    errors = 0
    m = re.search(r"Non-2xx or 3xx responses:\s+(\d+)", out)
    if m:
        errors += int(m.group(1))
    m = re.search(r"Socket errors: connect (\d+), read (\d+), write (\d+), timeout (\d+)", out)
    if m:
        errors += sum(int(g) for g in m.groups())
    requests = int(re.search(r"(\d+) requests in", out).group(1))
    return {"p50_ms": ms(50), "p99_ms": ms(99), "rps": rps, "errors": errors,
            "requests": requests}


def batch_times(port, repeats=5):
    import numpy as np

    from graspforce.batch.wrenches import gaussian
    W = gaussian(10000, [0, 0, -9.81, 0, 0, 0], [3.0] * 3 + [0.05] * 3, seed=1)
    given = {"contacts": CONTACTS, "wrenches": W.tolist()}
    drawn = {"contacts": CONTACTS, "sample": {"count": 10000, "seed": 1, "force_scale": 3.0,
                                              "torque_scale": 0.05,
                                              "mean": [0, 0, -9.81, 0, 0, 0]}}
    out = {}
    with httpx.Client(base_url=f"http://127.0.0.1:{port}", timeout=60) as http:
        for name, body in (("given", given), ("drawn", drawn)):
            payload = json.dumps(body).encode()
            times = []
            for _ in range(repeats + 1):
                begin = time.perf_counter()
                r = http.post("/v1/force-optimization/batch", content=payload,
                              headers={"content-type": "application/json"})
                answer = r.json()
                times.append(time.perf_counter() - begin)
                assert r.status_code == 200 and answer["summary"]["count"] == 10000
            out[name] = (statistics.median(times[1:]) * 1e3, answer["seconds"] * 1e3,
                         len(payload))
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--duration", type=int, default=5, help="seconds per wrk run")
    p.add_argument("--starts", type=int, default=3, help="starts timed to /readyz")
    p.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "service.md"))
    args = p.parse_args(argv)

    script = tempfile.NamedTemporaryFile("w", suffix=".lua", delete=False)
    script.write('wrk.method = "POST"\nwrk.headers["Content-Type"] = "application/json"\n'
                 f"wrk.body = {json.dumps(json.dumps(BODY))}\n")
    script.close()

    starts = []
    for _ in range(args.starts):
        port = free_port()
        proc, seconds = start(ours(port), port)
        starts.append(seconds)
        stop(proc)

    rows = {}
    for name, command in (("bare FastAPI, validation only", bare), ("graspforce", ours)):
        port = free_port()
        proc, _ = start(command(port), port)
        try:
            url = f"http://127.0.0.1:{port}/v1/force-optimization"
            subprocess.run(["wrk", "-t1", "-c1", "-d1s", "-s", script.name, url],
                           capture_output=True, check=True)              # warm-up
            one = wrk(url, 1, 1, args.duration, script.name)
            before = cpu_seconds(proc.pid)
            many = wrk(url, 32, 2, args.duration, script.name)
            many["cpu_us"] = (cpu_seconds(proc.pid) - before) / many["requests"] * 1e6
            rows[name] = (one, many)
            if name == "graspforce":
                batches = batch_times(port)
                check = httpx.post(url, json=BODY).json()
        finally:
            stop(proc)
    os.unlink(script.name)

    lines = ["# The service under load", "",
             f"`python -m benchmarks.service --duration {args.duration}`: wrk from a second "
             "process on 127.0.0.1, one uvicorn worker, this machine (2 cores, shared). "
             "POST /v1/force-optimization, 4 soft fingers, L1, zc-ie, eps 1e-9 "
             f"(sigma {check['sigma']:.6f}, status {check['status']}, {check['iterations']} "
             "iterations); the bare framework validates the same body and answers without "
             "solving.", "",
             "| server | p50 ms (1 conn) | p99 ms (1 conn) | requests/s (32 conn) | "
             "p99 ms (32 conn) | server CPU us a request (32 conn) | errors |",
             "|---|---|---|---|---|---|---|"]
    for name, (one, many) in rows.items():
        lines.append(f"| {name} | {one['p50_ms']:.2f} | {one['p99_ms']:.2f} | "
                     f"{many['rps']:.0f} | {many['p99_ms']:.1f} | {many['cpu_us']:.0f} | "
                     f"{one['errors'] + many['errors']} of {one['requests'] + many['requests']}"
                     " |")
    lines += ["", "| batch of 10,000 wrenches | round trip ms (median of 5) | solve ms | "
                  "request bytes |", "|---|---|---|---|"]
    for name, (total, solve, size) in batches.items():
        label = "wrenches sent" if name == "given" else "drawn by the service from a seed"
        lines.append(f"| {label} | {total:.0f} | {solve:.0f} | {size:,} |")
    lines += ["", f"From `python -m graspforce serve` to the first 200 on /readyz: "
                  f"{statistics.median(starts):.2f} s (median of {len(starts)}; "
                  f"{', '.join(f'{s:.2f}' for s in starts)})."]
    text = "\n".join(lines) + "\n"
    print(text)
    Path(args.out).write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
