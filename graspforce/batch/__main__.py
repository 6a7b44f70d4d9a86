"""python -m graspforce.batch batch ... | plot ...: the batch commands on their own."""
import argparse
import sys

from .cli import add_batch_parser
from .plot import add_plot_parser


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m graspforce.batch",
                                     description="graspforce batch runs and their figures")
    sub = parser.add_subparsers(dest="command", required=True)
    add_batch_parser(sub)
    add_plot_parser(sub)
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except (ValueError, TypeError, ImportError) as e:
        print(f"{parser.prog}: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
