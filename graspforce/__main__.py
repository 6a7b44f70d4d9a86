"""python -m graspforce: the `graspforce` command (graspforce.cli)."""
import sys

from .cli import main, warmup  # noqa: F401  (warmup: kept importable from here)

if __name__ == "__main__":
    sys.exit(main())
