"""The ``mpcwalk`` command: one parser, one sub-command per module of this package, errors
as exit codes (:data:`~mpcwalk.cli.exits.EXIT_CODES`)."""

import argparse
import os
import sys
import traceback
from pathlib import Path

from mpcwalk.cli import bench, experiment, lists, plan, replay, robots, walk
from mpcwalk.cli.console import joined_negative_numbers, use_formatter
from mpcwalk.exceptions import MpcwalkError

_DESCRIPTION = (
    "Optimization-based walking of humanoid robots: plan a walk on the LIPM (plan), list the "
    "pattern generators (generators), the named controllers (controllers), the stabilizers "
    "(stabilizers), the QP back-ends (solvers) and the robots (robots), simulate a robot "
    "walking in MuJoCo (walk), replay a walk (replay), run the benchmarks (bench) and the "
    "experiments (experiment). Exit status: 0 success, 1 the simulated robot fell, 2 bad "
    "input (nothing ran), 3 the controller stopped the walk (faults beyond its bound), 4 "
    "internal error (traceback saved under --out; --debug prints it), 130 interrupted "
    "(partial results written)."
)


def build_parser() -> argparse.ArgumentParser:
    """The ``mpcwalk`` argument parser."""
    from mpcwalk import __version__

    parser = argparse.ArgumentParser(prog="mpcwalk", description=_DESCRIPTION)
    parser.add_argument("--version", action="version", version=f"mpcwalk {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    plan.add_parser(sub)
    lists.add_parsers(sub)
    bench.add_parser(sub)
    walk.add_parser(sub)
    robots.add_parser(sub)
    replay.add_parser(sub)
    experiment.add_parser(sub)
    use_formatter(parser)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``mpcwalk`` command (exit codes: see the description)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    argv = joined_negative_numbers([token for token in argv if token != "--debug"])
    if "--video" not in argv:
        os.environ["MUJOCO_GL"] = "disable"  # only --video renders: no renderer needed
    else:
        try:
            import mujoco  # noqa: F401  (the renderer starts with it)
        except Exception as exc:
            print(
                f"mpcwalk: error: --video needs MuJoCo's renderer, which does not start "
                f"(MUJOCO_GL={os.environ.get('MUJOCO_GL', '')!r}: {type(exc).__name__}: {exc}); "
                "install its library (EGL or OSMesa) or choose another with MUJOCO_GL.",
                file=sys.stderr,
            )
            return 2
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        code: int = args.run(args)
        return code
    except MpcwalkError as exc:
        print(f"mpcwalk: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("mpcwalk: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # a bug: one line and the traceback in a file, never a raw dump
        from mpcwalk.walking.outputs import save_traceback

        out = getattr(args, "out", None)
        saved = save_traceback(Path(out) if out else None, exc)
        where = f"; traceback saved to {saved}" if saved else ""
        print(f"mpcwalk: internal error: {type(exc).__name__}: {exc}{where}", file=sys.stderr)
        if debug:
            traceback.print_exc()
        return 4


if __name__ == "__main__":
    sys.exit(main())
