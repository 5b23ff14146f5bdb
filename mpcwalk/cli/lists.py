"""The listing commands, one kind for every registry: ``mpcwalk generators``, ``mpcwalk
controllers``, ``mpcwalk stabilizers``, ``mpcwalk solvers`` (name and one line each, then
what is not installed here and how to install it)."""

import argparse
from collections.abc import Callable

from mpcwalk.registry import Registry, format_registry


def _generators() -> Registry:
    from mpcwalk.generators.registry import GENERATORS

    return GENERATORS


def _controllers() -> Registry:
    from mpcwalk.walking.specification import CONTROLLERS

    return CONTROLLERS


def _stabilizers() -> Registry:
    from mpcwalk.control.stabilizers import STABILIZERS

    return STABILIZERS


def _solvers() -> Registry:
    from mpcwalk.qp.solvers.registry import SOLVERS

    return SOLVERS


#: Command -> (help, the registry it lists).
LISTINGS: dict[str, tuple[str, Callable[[], Registry]]] = {
    "generators": ("list the pattern generators", _generators),
    "controllers": (
        "list the named controllers (mpcwalk walk --controller NAME)",
        _controllers,
    ),
    "stabilizers": ("list the stabilizers (mpcwalk walk --stabilizer NAME)", _stabilizers),
    "solvers": ("list the QP back-ends (mpcwalk walk --solver NAME)", _solvers),
}


def add_parsers(sub) -> None:
    """Add the listing commands to ``sub``."""
    for command, (text, registry) in LISTINGS.items():
        p = sub.add_parser(command, help=text, description=text[0].upper() + text[1:] + ".")
        p.set_defaults(run=_lister(registry))


def _lister(registry: Callable[[], Registry]) -> Callable[[argparse.Namespace], int]:
    def run(args: argparse.Namespace) -> int:
        print(format_registry(registry()))
        return 0

    return run
