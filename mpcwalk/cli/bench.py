"""``mpcwalk bench ...``: the benchmarks (generator ticks, whole-body IK, walk loop, QP
solvers); their options are the benchmark package's own."""

import argparse


def add_parser(sub) -> None:
    """Add ``bench`` and its sub-commands to ``sub``."""
    from mpcwalk.bench.cli import add_bench_parser

    add_bench_parser(sub)
    bench = sub.choices["bench"]
    bench.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run the benchmark of ``args``."""
    code: int = args.bench_func(args)
    return code
