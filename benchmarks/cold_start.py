"""Cold start: from a fresh clone to the first answer, and from a new process to the first answer.

    python -m benchmarks.cold_start              # 3 runs of each, medians
    python -m benchmarks.cold_start --runs 1 --skip-install

Measured, each in fresh processes, medians of --runs:
- install: a fresh clone of this repository's HEAD (git clone of the working tree's repository)
  into a new folder, a new virtual environment, then the README's first command (its first
  fenced line, run by bash in the clone with the environment active). Wall time and the peak
  resident memory of the whole process tree (pip, the compiler, the main job), sampled from
  /proc every 20 ms. pip's download cache is the user's as it is (a machine that installed
  these packages before reads their wheels from it); nothing else is shared.
- first answer: in the same environment (or the current interpreter with --skip-install), a new
  `python -c` that imports graspforce, builds a four-finger grasp and answers one min_force
  (zc-ie, L1): wall time from the process's start to its exit.

Writes benchmarks/results/cold_start.md.
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FIRST_ANSWER = """
import numpy as np, graspforce as gf
points = [([0.05, 0.01, 0.0], [-1, 0, 0]), ([0.05, -0.01, 0.01], [-1, 0, 0]),
          ([-0.05, 0.01, 0.0], [1, 0, 0]), ([-0.05, -0.01, -0.01], [1, 0, 0])]
grasp = gf.Grasp(gf.Contact(p, n, 0.5, 0.01) for p, n in points)
res = grasp.min_force(np.array([0, 0, -9.81, 0, 0, 0]))
assert res.status == "optimal", res.status
"""


def readme_command():
    """The README's first command: the first line of its first fenced block, comment dropped."""
    text = (ROOT / "README.md").read_text()
    block = re.search(r"```[^\n]*\n(.*?)```", text, re.S).group(1)
    command = block.splitlines()[0].split("#")[0].strip()
    # a command that ends by starting the service would never exit: measure it up to a
    # warmup, which loads the same compiled core and answers
    return re.sub(r"graspforce serve$", "graspforce warmup", command)


def _tree_rss(pid):
    """Resident bytes of pid and all its descendants, from /proc."""
    children = {}
    rss = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()
        children.setdefault(int(fields[1]), []).append(int(entry))
        rss[int(entry)] = int(fields[21]) * os.sysconf("SC_PAGE_SIZE")
    total, stack = 0, [pid]
    while stack:
        p = stack.pop()
        total += rss.get(p, 0)
        stack.extend(children.get(p, []))
    return total


def run_measured(cmd, cwd, env):
    """(wall seconds, peak tree RSS bytes, exit code, output tail) of a bash command."""
    start = time.perf_counter()
    proc = subprocess.Popen(["bash", "-c", cmd], cwd=cwd, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    peak = [0]

    def sample():
        while proc.poll() is None:
            peak[0] = max(peak[0], _tree_rss(proc.pid))
            time.sleep(0.02)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    out, _ = proc.communicate()
    wall = time.perf_counter() - start
    sampler.join()
    return wall, peak[0], proc.returncode, out[-2000:]


def fresh_install(workdir):
    """Clone, new venv, the README's first command; returns (wall, peak, python of the venv)."""
    clone = workdir / "clone"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
    subprocess.run([sys.executable, "-m", "venv", str(workdir / "venv")], check=True)
    env = dict(os.environ)
    env["PATH"] = f"{workdir / 'venv' / 'bin'}:{env['PATH']}"
    env["VIRTUAL_ENV"] = str(workdir / "venv")
    env.pop("PYTHONPATH", None)
    wall, peak, code, out = run_measured(readme_command(), clone, env)
    if code != 0:
        raise SystemExit(f"the README's first command failed ({code}):\n{out}")
    return wall, peak, workdir / "venv" / "bin" / "python"


def first_answer(python):
    """Wall seconds of a new process that imports graspforce and answers one min_force, run from
    a neutral folder so that it imports the installed package."""
    start = time.perf_counter()
    subprocess.run([str(python), "-c", FIRST_ANSWER], check=True, cwd=tempfile.gettempdir())
    return time.perf_counter() - start


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--skip-install", action="store_true",
                        help="only the first answer, with this interpreter")
    parser.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "cold_start.md"))
    args = parser.parse_args(argv)
    installs, answers = [], []
    python = Path(sys.executable)
    for i in range(args.runs):
        if not args.skip_install:
            workdir = Path(tempfile.mkdtemp(prefix="gf-cold-"))
            try:
                wall, peak, python = fresh_install(workdir)
                installs.append((wall, peak))
                print(f"install {i + 1}: {wall:.1f} s, peak {peak / 2**30:.2f} GiB", flush=True)
                answers.append(first_answer(python))
            finally:
                shutil.rmtree(workdir, ignore_errors=True)
        else:
            answers.append(first_answer(python))
        print(f"first answer {i + 1}: {answers[-1]:.2f} s", flush=True)
    lines = ["| measure | median | runs |", "|---|---|---|"]
    if installs:
        walls = [w for w, _ in installs]
        peaks = [p / 2**30 for _, p in installs]
        lines.append(f"| README's first command, fresh clone and venv (s) | "
                     f"{statistics.median(walls):.1f} | {', '.join(f'{w:.1f}' for w in walls)} |")
        lines.append(f"| its peak memory, whole process tree (GiB) | "
                     f"{statistics.median(peaks):.2f} | {', '.join(f'{p:.2f}' for p in peaks)} |")
    lines.append(f"| new process to its first min_force, import included (s) | "
                 f"{statistics.median(answers):.2f} | {', '.join(f'{a:.2f}' for a in answers)} |")
    text = (f"Command: `{readme_command()}` (README); {os.cpu_count()} cores, Python "
            f"{sys.version.split()[0]}.\n\n" + "\n".join(lines) + "\n")
    print(text)
    Path(args.out).write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
