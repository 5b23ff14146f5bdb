"""``mpcwalk walk``: a walk specification from the options (or a ``spec.toml``), checked
before anything runs, the walk, its outputs written atomically with ``metrics.json`` last,
and an exit code that means one thing.

It writes into ``--out``: ``spec.toml`` (the walk, every default spelled out: ``mpcwalk walk
--spec DIR/spec.toml`` walks it again), ``metrics.json``, the per-tick log
(``walk_log.npz``, or ``.csv`` with ``--log-format csv``), ``top_view.png``,
``com_cop.png``, ``estimator.png`` (when the controller walked on the estimator), on a
terrain (``--terrain FILE``) ``terrain.toml`` and ``side_view.png`` and, with ``--video``,
``walk.mp4``.
"""

import argparse
import shutil

from mpcwalk.cli.console import out_path, summary
from mpcwalk.cli.exits import OUTCOME_EXIT
from mpcwalk.cli.walk_options import add_walk_options, spec_from_args
from mpcwalk.exceptions import MpcwalkError
from mpcwalk.walking.outputs import check_out_dir, log_mujoco_messages


def add_parser(sub) -> argparse.ArgumentParser:
    """Add ``walk`` to ``sub`` (the result of ``add_subparsers``)."""
    p = sub.add_parser(
        "walk",
        help="simulate a robot walking in MuJoCo and write its spec, metrics, log, plots (and "
        "a video)",
        description="Plan footsteps from a velocity command (paper M) or a .mdat path file "
        "(paper A), drive the robot with a pattern generator, the whole-body IK and its "
        "position servos in MuJoCo, and write spec.toml (the walk, to walk it again with "
        "--spec), metrics.json, the per-tick log, a top-view plot and a CoM/CoP-over-time plot "
        "into --out (and walk.mp4 with --video). On a terrain (--terrain FILE: stairs, slopes, "
        "platforms, stepping stones, rough patches) it also writes terrain.toml and a side "
        "view, side_view.png. Walking defaults (step duration, swing height, leg limits) come "
        "from the robot's preset.",
    )
    add_walk_options(p)
    p.add_argument("--video", action="store_true", help="render walk.mp4 (offscreen)")
    p.add_argument(
        "--view",
        action="store_true",
        help="show the walk live in the browser (3D viewer on --view-port), in real time",
    )
    p.add_argument("--view-port", type=int, default=8080, help="port of the live viewer")
    p.add_argument(
        "--log-format", choices=("npz", "csv"), default="npz", help="format of the per-tick log"
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--out", type=out_path, required=True, help="output directory")
    p.add_argument(
        "--overwrite",
        action="store_true",
        help="replace an earlier run in --out (refused otherwise)",
    )
    p.epilog = (
        "Exit status: 0 when the robot walked the whole schedule, 1 when it fell, 2 on bad "
        "input, 3 when the controller stopped the walk."
    )
    p.set_defaults(run=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run ``mpcwalk walk`` (live in the browser with ``--view``)."""
    if not args.view:
        return walk(args)
    from mpcwalk.robot import load_robot
    from mpcwalk.viewer.live import LiveView

    spec = spec_from_args(args, out=args.out)  # bad input: refused before a server starts
    view = LiveView(load_robot(spec.robot), port=args.view_port, terrain=spec.world.terrain)
    print(f"the walk, live on http://127.0.0.1:{view.server.get_port()}")
    try:
        return walk(args, observer=view)
    finally:
        view.close()


def walk(args: argparse.Namespace, *, observer=None) -> int:
    """The walk of ``args``; bad input raises an MpcwalkError (exit code 2) before anything
    is created."""
    from mpcwalk.walking.outputs import write_walk_outputs
    from mpcwalk.walking.runner import run_walk

    spec = spec_from_args(args, out=args.out)
    out = check_out_dir(args.out, overwrite=args.overwrite)
    created = not out.exists()
    if args.video:  # written during the walk
        out.mkdir(parents=True, exist_ok=True)
    with log_mujoco_messages(out):
        try:
            result = run_walk(spec, observer=observer)
        except MpcwalkError:
            if created and out.is_dir() and not any(out.iterdir()):
                shutil.rmtree(out)  # a refused input leaves nothing behind
            raise
        written = write_walk_outputs(result, out, log_format=args.log_format)
    print(summary(result))
    m = result.metrics
    for warning in m.warnings:
        print(f"warning: {warning}")
    if m.outcome == "stopped":
        print(f"STOPPED by the controller: {m.stop_reason}")
    if m.outcome == "interrupted":
        print("INTERRUPTED: the partial walk's log and metrics are written")
    print("wrote " + ", ".join(str(path) for path in written))
    return OUTCOME_EXIT[m.outcome]
