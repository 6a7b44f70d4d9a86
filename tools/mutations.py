"""Mutation run: plausible one-line bugs in the Python layer, each applied to a scratch copy of
the repository (never to the working tree), and the tests that should catch it run there.

    python tools/mutations.py [--only NAME] [--full]

Each mutation replaces one exact line fragment (it must occur exactly once); the copy imports
its own graspforce (the installed compiled core is copied in beside it, and the editable
install's finder is removed by a sitecustomize on PYTHONPATH). A mutation is caught when the
run fails. --full runs the whole suite for each mutation instead of the listed files.
"""
import argparse
import glob
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# (name, file, original fragment, mutated fragment, test files that should catch it)
MUTATIONS = [
    ("quality tolerance not scaled by W's width", "graspforce/grasping/quality.py",
     "return tol * max(math.sqrt(float(np.dot(widths * u, widths * u))), floor)",
     "return tol",
     ["tests/test_scale.py", "tests/test_grasp_closure.py", "tests/test_growth.py"]),
    ("sigma_lower collapsed onto sigma", "graspforce/grasping/grasp.py",
     "1.0 / (t_scale * head[2]), norm, magnitude, method, ray,",
     "sigma, norm, magnitude, method, ray,",
     ["tests/test_grasp_forces.py", "tests/test_scale.py"]),
    ("Linf lift's t_scale dropped from sigma_lower", "graspforce/grasping/grasp.py",
     "1.0 / (t_scale * head[2]), norm, magnitude, method, ray,",
     "1.0 / head[2], norm, magnitude, method, ray,",
     ["tests/test_grasp_forces.py", "tests/test_linf_lift.py"]),
    ("sign of the second tangent (left-handed contact frame)", "graspforce/grasping/contact.py",
     "return (ox, oy, oz), (ny * oz - nz * oy, nz * ox - nx * oz, nx * oy - ny * ox)",
     "return (ox, oy, oz), (nz * oy - ny * oz, nz * ox - nx * oz, nx * oy - ny * ox)",
     ["tests/test_contact.py", "tests/test_grasp_forces.py"]),
    ("frictionless contact with spin friction accepted", "graspforce/grasping/contact.py",
     "if mu == 0.0 and mu_spin > 0.0:",
     "if False:",
     ["tests/test_contact.py", "tests/test_grasp_forces.py"]),
    ("batch wrenches' width not checked", "graspforce/grasping/grasp.py",
     "if W.shape[1] != 6:",
     "if W.shape[1] < 0:",
     ["tests/test_batch.py", "tests/test_grasp_forces.py"]),
    ("force reader's layout off by one (leaf count)", "graspforce/records/_forces.py",
     "[witness_size, linf, full, G.shape[0], table.shape[1]],",
     "[witness_size, linf, full, G.shape[0], table.shape[1] - 1],",
     ["tests/test_grasp_forces.py"]),
    ("force views off by one", "graspforce/records/_forces.py",
     "packed[1 + 4 * m:1 + 10 * m].reshape(m, 6),",
     "packed[4 * m:10 * m].reshape(m, 6),",
     ["tests/test_grasp_forces.py", "tests/test_batch.py"]),
    ("growth's closed-form origin test too generous", "graspforce/growth/growth.py",
     "return None if verdict == UNDECIDED else verdict == INSIDE",
     "return verdict == INSIDE or verdict == UNDECIDED",
     ["tests/test_growth.py", "tests/test_scale.py"]),
]

SITECUSTOMIZE = """import sys
sys.meta_path[:] = [f for f in sys.meta_path if 'ScikitBuild' not in type(f).__name__]
sys.path[:] = [p for p in sys.path if p != {root!r}]
"""


def scratch_copy(where):
    files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True,
                           check=True).stdout.split()
    for f in files:
        if os.path.isfile(os.path.join(ROOT, f)):
            os.makedirs(os.path.join(where, os.path.dirname(f)), exist_ok=True)
            shutil.copy2(os.path.join(ROOT, f), os.path.join(where, f))
    import graspforce._core as core          # the installed compiled core, beside the copy
    shutil.copy2(core.__file__, os.path.join(where, "graspforce"))
    site = os.path.join(where, ".site")
    os.makedirs(site)
    with open(os.path.join(site, "sitecustomize.py"), "w") as f:
        f.write(SITECUSTOMIZE.format(root=ROOT))
    return site


def run(where, site, tests):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join((site, where)))
    cmd = [sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:randomly", "-p", "no:cacheprovider",
           *tests]
    proc = subprocess.run(cmd, cwd=where, env=env, capture_output=True, text=True)
    return proc.returncode, proc.stdout.strip().splitlines()[-1:] if proc.stdout else []


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--only")
    ap.add_argument("--full", action="store_true")
    args = ap.parse_args()
    caught_all = True
    with tempfile.TemporaryDirectory() as tmp:
        where = os.path.join(tmp, "repo")
        site = scratch_copy(where)
        # the copy itself must pass the tests, or a failure proves nothing
        rc, tail = run(where, site, ["tests/test_contact.py"])
        assert rc == 0, ("unmutated copy fails", tail)
        import graspforce
        assert os.path.dirname(graspforce.__file__) != os.path.join(where, "graspforce")
        for name, path, old, new, tests in MUTATIONS:
            if args.only and args.only not in name:
                continue
            target = os.path.join(where, path)
            text = open(target).read()
            assert text.count(old) == 1, (name, "fragment not found exactly once")
            with open(target, "w") as f:
                f.write(text.replace(old, new))
            try:
                rc, tail = run(where, site, ["tests"] if args.full else tests)
            finally:
                with open(target, "w") as f:
                    f.write(text)
            caught = rc != 0
            caught_all &= caught
            print(f"{'caught' if caught else 'MISSED'}  {name}  ({path})  {' '.join(tail)}",
                  flush=True)
    sys.exit(0 if caught_all else 1)


if __name__ == "__main__":
    main()
