"""``mpcwalk sweep ...``: the sweeps of the experiments, run on the sweep engine."""

import argparse


def add_parser(sub) -> None:
    """Add ``sweep`` to ``sub``."""
    from mpcwalk.experiments.sweep_cli import add_sweep_parser

    add_sweep_parser(sub)
    sub.choices["sweep"].set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run the sweep of ``args``."""
    from mpcwalk.experiments.sweep_cli import run_sweep_command

    code: int = run_sweep_command(args)
    return code
