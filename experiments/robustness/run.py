"""The robustness table: every generator, one closed loop, a world that is not the model.

Usage (from the repository root)::

    python experiments/robustness/run.py --out results/robustness            # full table
    python experiments/robustness/run.py --out out/robustness --quick --workers 2

Writes ``README.md`` (the estimator on nominal walks, walks without a fall per generator,
one table per robot and walk, the walks that fall), ``results.json`` (every walk) and the
estimator figures into ``--out``. Parameters: ``experiments/robustness/robustness.toml``.
"""

import argparse
import sys
from pathlib import Path

from mpcwalk.experiments.robustness import DEFAULT_CONFIG, load_config, run_robustness
from mpcwalk.experiments.robustness_report import falls_table, write_results


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.splitlines()[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    parser.add_argument(
        "--out", type=Path, default=Path("results") / "robustness", help="output directory"
    )
    parser.add_argument(
        "--quick", action="store_true", help="a handful of cases (the [quick] table)"
    )
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
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    config = load_config(args.config, mode="quick" if args.quick else "full")
    command = "python experiments/robustness/run.py " + " ".join(
        sys.argv[1:] if argv is None else argv
    )
    results = run_robustness(
        config,
        workers=args.workers,
        progress=not args.no_progress,
        figures_dir=args.out,
        address=args.address,
    )
    written = write_results(args.out, config, results, command=command.strip())
    print(falls_table(results.rows), end="")
    print(f"{len(results.rows)} walks in {results.wall_time_s / 60.0:.1f} min")
    print("wrote " + ", ".join(str(path) for path in written))
    return 0


if __name__ == "__main__":
    sys.exit(main())
