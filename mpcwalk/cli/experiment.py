"""``mpcwalk experiment list|run``: the experiments of the registry
(:mod:`mpcwalk.experiments.command`)."""

import argparse


def add_parser(sub) -> None:
    """Add ``experiment`` to ``sub``."""
    from mpcwalk.experiments.command import add_experiment_parser

    add_experiment_parser(sub)
    sub.choices["experiment"].set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run the ``experiment`` sub-command of ``args``."""
    from mpcwalk.experiments.command import run_experiment_command

    return run_experiment_command(args)
