"""Paper M's experiments for every controller: turning, disturbances, push recovery, speed.

Usage (from the repository root)::

    python experiments/paper_m/run.py --out results/paper_m            # full grid
    python experiments/paper_m/run.py --out out/paper_m --quick --workers 2

Writes ``README.md`` (table, goal checks, definitions), ``results.json`` and the figures into
``--out``. Parameters: ``experiments/paper_m/paper_m.toml``; controllers:
``mpcwalk.experiments.paper_m.CONTROLLERS``.
"""

import argparse
import sys
from pathlib import Path

from mpcwalk.experiments.paper_m import CONTROLLERS, DEFAULT_CONFIG, EXPERIMENTS, load_config
from mpcwalk.experiments.paper_m_report import run_paper_m
from mpcwalk.experiments.paper_m_table import format_goals, format_table


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--out", type=Path, default=Path("results") / "paper_m", help="output directory"
    )
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument(
        "--full", dest="mode", action="store_const", const="full", help="the full grid (default)"
    )
    mode.add_argument(
        "--quick",
        dest="mode",
        action="store_const",
        const="quick",
        help="the reduced grid of the [quick.*] tables",
    )
    parser.set_defaults(mode="full")
    parser.add_argument(
        "--workers",
        type=int,
        default=None,
        help="walks at once, as Ray tasks (default: one per core; a cluster's CPUs)",
    )
    parser.add_argument(
        "--address",
        default=None,
        help="Ray cluster, e.g. ray://HOST:10001 (default: RAY_ADDRESS, else a local Ray)",
    )
    parser.add_argument("--config", type=Path, default=DEFAULT_CONFIG, help="TOML parameters")
    parser.add_argument(
        "--controllers",
        nargs="+",
        default=None,
        choices=list(CONTROLLERS),
        help="run only these controllers",
    )
    parser.add_argument(
        "--experiments", nargs="+", default=list(EXPERIMENTS), choices=list(EXPERIMENTS)
    )
    parser.add_argument("--no-plots", action="store_true", help="table only")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    config = load_config(args.config, mode=args.mode)
    command = "python experiments/paper_m/run.py " + " ".join(
        sys.argv[1:] if argv is None else argv
    )
    results = run_paper_m(
        args.out,
        config,
        names=args.controllers,
        experiments=args.experiments,
        workers=args.workers,
        address=args.address,
        progress=not args.no_progress,
        plots=not args.no_plots,
        command=command.strip(),
    )
    print(format_table(results["rows"]))
    print(format_goals(results["goals"]))
    for name, reason in results["skipped"].items():
        print(f"skipped {name}: {reason}")
    print(f"wrote {args.out / 'README.md'}, {args.out / 'results.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
