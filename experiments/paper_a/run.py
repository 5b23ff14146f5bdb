"""Paper A's comparison table: every controller on the straight and turning paths.

Usage (from the repository root)::

    python experiments/paper_a/run.py --out results/paper_a
    python -m experiments.paper_a.run --out DIR --steps 4      # shortened paths

Writes ``table.md``, ``table.json``, the top-view plots (paper A Fig. 5 and 7) and the
per-step placement error plots (Fig. 8) into ``--out``.
"""

import argparse
import sys
from pathlib import Path

from mpcwalk.experiments.paper_a import DEFAULT_SPECS, format_table, run_paper_a


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--out", type=Path, default=Path("results") / "paper_a", help="output directory"
    )
    parser.add_argument(
        "--steps", type=int, default=None, help="steps kept from each path (default: all)"
    )
    parser.add_argument(
        "--slow-steps",
        type=int,
        default=None,
        help="steps kept for controllers with T >= 3 s (default: --steps)",
    )
    parser.add_argument(
        "--experiments", nargs="+", default=["straight", "turning"], choices=["straight", "turning"]
    )
    parser.add_argument(
        "--only",
        nargs="+",
        default=None,
        metavar="GENERATOR",
        help="run only these generators (static, static-qp, mpc)",
    )
    parser.add_argument("--no-plots", action="store_true", help="table only")
    args = parser.parse_args(argv)
    specs = [s for s in DEFAULT_SPECS if args.only is None or s.generator in args.only]
    rows = run_paper_a(
        args.out,
        specs=specs,
        experiments=args.experiments,
        nb_steps=args.steps,
        slow_nb_steps=args.slow_steps,
        plots=not args.no_plots,
    )
    print(format_table(rows))
    print(f"wrote {args.out / 'table.md'}, {args.out / 'table.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
