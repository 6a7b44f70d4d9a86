"""The package layout: every public name resolves from `gf`, every import the repository writes
(code and the docs' snippets) resolves, the layers import downwards only with no circles, and each
module imports in a fresh interpreter."""
import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

import graspforce as gf

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "graspforce"

# the public names that `import graspforce as gf` gives; they stay as the folders change
PUBLIC = [
    "METHODS", "Ball", "Box", "Capsule", "ClosestPoint", "ConeCap", "ConeDistance", "Contact",
    "ConvexSet", "Ellipsoid", "Grasp", "GraspQuality", "GrowthDistance", "GrowthDistanceResult",
    "MinForce", "Polytope", "RayShot", "TruncatedCone", "affine", "closest_point",
    "cone_distance", "growth_distance", "hull", "minkowski_sum", "pose", "ray_shoot",
]
# imported on first use (gf.robots needs Pinocchio)
LAZY = ["robots", "batch"]

# the layers, bottom up: a module imports, at its top, only modules of its own layer or below.
# Modules of graspforce/ itself (the entry points) sit above every layer; _core (compiled) and
# _validate (argument checks) below all of them
LAYERS = ["records", "geometry", "shooting", "grasping", "growth", "robots", "batch"]
BASE = {"graspforce._core", "graspforce._validate"}
# imports inside a function that go upwards: Grasp.min_force hands a batch of wrenches to
# graspforce.batch (which builds on Grasp)
DEFERRED_UP = {("graspforce.grasping.grasp", "graspforce.batch.forces")}


def _modules():
    """{dotted name: path} of every module of the package."""
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(ROOT).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _imports(name, path):
    """[(imported module, names taken from it, at module level)] of one module, graspforce's own
    only, relative imports resolved."""
    tree = ast.parse(path.read_text())
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    top = {id(node) for node in tree.body}
    for node in tree.body:      # a module's top: its statements and their bodies (try, if)
        for child in ast.walk(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                break
            top.add(id(child))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module
            names = [a.name for a in node.names]
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] == "graspforce":
                    found.append((a.name, [], id(node) in top))
            continue
        else:
            continue
        if module.split(".")[0] == "graspforce":
            found.append((module, names, id(node) in top))
    return found


def _rank(module):
    """A module's layer: -1 below every layer, len(LAYERS) above them all."""
    if module in BASE or module.startswith("graspforce._core."):
        return -1
    parts = module.split(".")
    if len(parts) > 1 and parts[1] in LAYERS:
        return LAYERS.index(parts[1])
    return len(LAYERS)


def _edges(level_only=True):
    """{(importer, imported module)} of the package; imported names that are modules count as
    imports of those modules."""
    modules = _modules()
    edges = set()
    for name, path in modules.items():
        for module, names, at_top in _imports(name, path):
            if level_only and not at_top:
                continue
            targets = [f"{module}.{n}" for n in names
                       if f"{module}.{n}" in modules or f"{module}.{n}" == "graspforce._core"]
            for target in targets or [module]:
                if target != name:
                    edges.add((name, target))
    return edges


@pytest.mark.parametrize("name", PUBLIC)
def test_public_names_resolve(name):
    assert name in gf.__all__
    assert getattr(gf, name) is not None


def test_all_lists_exactly_the_public_names():
    assert sorted(gf.__all__) == sorted(PUBLIC)


@pytest.mark.parametrize("name", LAZY)
def test_lazy_subpackages_resolve(name):
    pytest.importorskip("pinocchio")
    assert getattr(gf, name).__name__ == f"graspforce.{name}"


def test_records_import_only_the_compiled_core():
    for source, target in _edges(level_only=False):
        if source.startswith("graspforce.records"):
            assert target.startswith(("graspforce.records", "graspforce._core")), (source, target)


def test_layers_import_downwards_only():
    up = []
    for source, target in _edges(level_only=False):
        if _rank(target) > _rank(source) and (source, target) not in DEFERRED_UP:
            up.append((source, target))
    assert not up
    # and the exceptions still exist, as imports inside a function
    assert DEFERRED_UP <= _edges(level_only=False) - _edges()


def test_no_import_circles():
    """The graph of module-level imports has no cycle (a depth-first search finds no back edge)."""
    graph = {}
    for source, target in _edges():
        graph.setdefault(source, set()).add(target)
    state = {}

    def visit(node, path):
        state[node] = "open"
        for nxt in graph.get(node, ()):
            assert state.get(nxt) != "open", " -> ".join(path + [node, nxt])
            if nxt not in state:
                visit(nxt, path + [node])
        state[node] = "done"

    for node in list(graph):
        if node not in state:
            visit(node, [])


def _written_imports():
    """[(file, line, module, names)] of every `import graspforce...` and `from graspforce...
    import ...` written in the repository's code and in the docs' snippets."""
    out = []
    files = [p for d in ("graspforce", "server", "tests", "benchmarks", "tools", "docs")
             for p in (ROOT / d).rglob("*") if p.suffix in (".py", ".md")]
    files += [ROOT / "README.md", ROOT / "BENCHMARKS.md"]
    pattern = re.compile(r"^\s*(?:from\s+(graspforce[\w.]*)\s+import\s+\(?([\w\s,]+)|"
                         r"import\s+(graspforce[\w.]*))")
    for path in files:
        for number, line in enumerate(path.read_text().splitlines(), 1):
            m = pattern.match(line)
            if m:
                names = [n.split(" as ")[0].strip() for n in (m.group(2) or "").split(",")]
                out.append((path.relative_to(ROOT), number, m.group(1) or m.group(3),
                            [n for n in names if n]))
    modules = _modules()
    for name, path in modules.items():     # the package's own relative imports
        for module, names, _ in _imports(name, path):
            out.append((path.relative_to(ROOT), 0, module, names))
    return out


def test_every_written_import_resolves():
    import importlib
    missing = []
    for path, line, module, names in _written_imports():
        try:
            mod = importlib.import_module(module)
        except ModuleNotFoundError as e:
            if e.name.split(".")[0] == "graspforce":
                missing.append(f"{path}:{line}: {module}")
            continue
        for n in names:
            if not hasattr(mod, n):
                try:
                    importlib.import_module(f"{module}.{n}")
                except ModuleNotFoundError:
                    missing.append(f"{path}:{line}: {module}.{n}")
    assert not missing


def test_every_module_imports_in_a_fresh_interpreter():
    """Each module, the service's too, imported alone in an interpreter forked from one that has
    imported nothing of graspforce. Modules that need an optional extra that is not installed
    are skipped."""
    optional = ("pinocchio", "fastapi", "httpx", "distributed", "dask", "pyarrow", "matplotlib",
                "clarabel", "qpsolvers", "osqp", "uvicorn")
    names = [n for n in _modules() if not n.endswith("__main__")]
    names += ["server", "server.app", "server.models", "server.settings"]
    # the extras' own packages are loaded once, before the forks: each child imports graspforce
    job = ("import importlib, sys\n"
           f"for extra in {optional!r}:\n"
           "    try:\n"
           "        importlib.import_module(extra)\n"
           "    except ImportError:\n"
           "        pass\n"
           "import numpy, scipy.sparse, scipy.spatial\n"
           "for name in sys.argv[1:]:\n"
           "    pid = __import__('os').fork()\n"
           "    if pid == 0:\n"
           "        try:\n"
           "            importlib.import_module(name)\n"
           "        except ModuleNotFoundError as e:\n"
           f"            __import__('os')._exit(0 if e.name.split('.')[0] in {optional!r} else 1)\n"
           "        except BaseException:\n"
           "            __import__('traceback').print_exc()\n"
           "            __import__('os')._exit(1)\n"
           "        __import__('os')._exit(0)\n"
           "    if __import__('os').waitpid(pid, 0)[1]:\n"
           "        print('FAILED', name)\n")
    run = subprocess.run([sys.executable, "-c", job, *names], capture_output=True, text=True,
                         cwd=ROOT, timeout=300)
    assert run.returncode == 0 and "FAILED" not in run.stdout, run.stdout + run.stderr

