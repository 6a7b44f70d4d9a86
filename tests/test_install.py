"""An installed graspforce compiles nothing and writes nothing when it runs: the package folder may
be read-only (root-owned site-packages, a container run as another user), and processes started at
once (uvicorn or Dask workers) share nothing that one of them could be writing."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import graspforce
import graspforce._core

JOB = """
import sys
import numpy as np
import graspforce as gf
points = [([0.05, 0.01, 0.0], [-1, 0, 0]), ([0.05, -0.01, 0.01], [-1, 0, 0]),
          ([-0.05, 0.01, 0.0], [1, 0, 0]), ([-0.05, -0.01, -0.01], [1, 0, 0])]
grasp = gf.Grasp(gf.Contact(p, n, 0.5, 0.01) for p, n in points)
w = np.array([1.0, -2.0, -9.81, 0.05, 0.02, -0.01])
answers = [grasp.min_force(w, norm=norm, method=m).sigma
           for norm in ("L1", "Linf") for m in gf.METHODS]
answers.append(gf.growth_distance(gf.Ball(np.zeros(3), 1.0), (np.eye(3), np.zeros(3)),
                                  gf.Box([0.5, 0.5, 0.5]), (np.eye(3), np.array([3.0, 0, 0]))).sigma)
assert "numba" not in sys.modules
print(repr(gf.__file__))
print(" ".join(repr(a) for a in answers))
"""


def _expected():
    scope = {}
    exec(JOB.replace("print(", "_ = ("), scope)
    return scope["answers"]


def _snapshot(root):
    """(path, size, mtime) of every file below root."""
    return sorted((str(p), p.stat().st_size, p.stat().st_mtime_ns)
                  for p in Path(root).rglob("*") if p.is_file())


@pytest.fixture(scope="module")
def package_copy(tmp_path_factory):
    """The installed package (its Python files and the built core) copied to a folder of its own,
    then made read-only; and an environment whose imports see it and the dependencies only (no
    site hooks, so the editable install's finder does not redirect them)."""
    root = tmp_path_factory.mktemp("readonly")
    src = Path(graspforce.__file__).parent
    shutil.copytree(src, root / "graspforce",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    shutil.copy(graspforce._core.__file__, root / "graspforce")
    for p in sorted(root.rglob("*"), reverse=True):
        p.chmod(0o555 if p.is_dir() else 0o444)
    root.chmod(0o555)
    deps = {str(Path(m.__file__).parent.parent) for m in (np, __import__("scipy"))}
    home = tmp_path_factory.mktemp("home")
    env = {"PATH": os.environ.get("PATH", ""), "HOME": str(home),
           "XDG_CACHE_HOME": str(home / "cache"), "PYTHONDONTWRITEBYTECODE": "1",
           "PYTHONPATH": os.pathsep.join([str(root), *sorted(deps)])}
    yield root, home, env
    for p in [root, *root.rglob("*")]:
        p.chmod(0o755 if p.is_dir() else 0o644)


def _run(env, cwd):
    return subprocess.Popen([sys.executable, "-S", "-c", JOB], env=env, cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def test_a_read_only_install_runs_twice_and_writes_nothing(package_copy):
    root, home, env = package_copy
    before = _snapshot(root), _snapshot(home)
    expected = _expected()
    for _ in range(2):
        proc = _run(env, home)
        out, err = proc.communicate(timeout=120)
        assert proc.returncode == 0, err
        path, answers = out.splitlines()
        assert eval(path).startswith(str(root))
        assert [float(a) for a in answers.split()] == expected
        # nothing compiled: nothing said on stderr, no file written in the package or the home
        assert err == ""
        assert (_snapshot(root), _snapshot(home)) == before


def test_processes_started_at_once_answer_alike(package_copy):
    root, home, env = package_copy
    expected = _expected()
    procs = [_run(env, home) for _ in range(4)]
    for proc in procs:
        out, err = proc.communicate(timeout=120)
        assert proc.returncode == 0, err
        assert [float(a) for a in out.splitlines()[1].split()] == expected
