"""``mpcwalk walk``: inputs checked before anything runs, the walk, its outputs written
atomically with ``metrics.json`` last, and an exit code that means one thing.

Exit codes (:data:`EXIT_CODES`): 0 the robot walked, 1 it fell, 2 bad input (before anything
ran), 3 the controller stopped the walk (faults beyond its bound), 4 internal error, 130
interrupted (SIGINT; the partial walk's log and metrics are written, ``interrupted: true``).
"""

import shutil
from functools import partial
from pathlib import Path

from mpcwalk.exceptions import ConfigurationError, MpcwalkError
from mpcwalk.walking.outputs import (
    METRICS_FILE,
    check_out_dir,
    log_mujoco_messages,
    write_atomic,
    write_json,
)

#: What each exit code of ``mpcwalk`` means.
EXIT_CODES = {
    0: "walked (or the command succeeded)",
    1: "the robot fell",
    2: "bad input, refused before anything ran",
    3: "the controller stopped the walk: faults beyond its bound",
    4: "internal error (traceback saved under --out; --debug prints it)",
    130: "interrupted (SIGINT): the partial walk's results are written",
}
_OUTCOME_EXIT = {"walked": 0, "fell": 1, "stopped": 3, "interrupted": 130}


def _command(args):
    """The velocity command of ``args`` (None: a path, or the planner's default)."""
    velocity = (args.vx, args.vy, args.vyaw)
    if args.path is not None and any(v is not None for v in velocity):
        raise ConfigurationError(
            "Give either a velocity command (--vx, --vy, --vyaw) or --path FILE.mdat, not both."
        )
    if args.duration is not None and args.steps is not None:
        raise ConfigurationError("Give either --duration or --steps, not both.")
    if args.path is None and args.duration is None and args.steps is None:
        raise ConfigurationError(
            "A walk from a velocity command needs --duration S (walking time) or --steps N."
        )
    if args.path is None and any(v is not None for v in velocity):
        return tuple(0.0 if v is None else v for v in velocity)
    return None  # the planner's default: 0.1 m/s, or the legs' reach at slow steps


def run_walk_command(args, *, observer=None) -> int:
    """Run ``mpcwalk walk``; bad input raises an MpcwalkError (exit code 2 in ``main``)
    before anything is created."""
    from mpcwalk.sim import parse_push
    from mpcwalk.walking.cli import _by_hand, summary
    from mpcwalk.walking.runner import run_walk
    from mpcwalk.walking.world_arguments import ground_options, world_options

    command = _command(args)
    pushes = [parse_push(text) for text in args.push]
    world = {**world_options(args), **ground_options(args)}
    by_hand = _by_hand(args)
    out = check_out_dir(args.out, overwrite=args.overwrite)
    created = not out.exists()
    if args.video:  # written during the walk
        out.mkdir(parents=True, exist_ok=True)
    log_mujoco_messages(out)
    try:
        result = run_walk(
            args.robot,
            args.generator,
            controller=args.controller,
            command=command,
            path=args.path,
            nb_steps=args.steps,
            duration=args.duration,
            step_duration=args.step_duration,
            double_support_ratio=args.ds_ratio,
            step_height=args.step_height,
            control_period=args.control_period,
            pushes=pushes,
            video=out / "walk.mp4" if args.video else None,
            progress=not args.no_progress,
            feedback=by_hand.get("feedback"),
            stabilizer=by_hand.get("stabilizer"),
            generator_options=None if args.solver is None else {"solver": args.solver},
            controller_options=by_hand.get("controller_options"),
            arm_swing=by_hand.get("arm_swing"),
            yaw_reference=bool(pushes),
            observer=observer,
            **world,
        )
    except MpcwalkError:
        if created and out.is_dir() and not any(out.iterdir()):
            shutil.rmtree(out)  # a refused input leaves nothing behind
        raise
    out.mkdir(parents=True, exist_ok=True)
    (out / METRICS_FILE).unlink(missing_ok=True)  # --overwrite: no stale metrics meanwhile
    written = write_outputs(result, out, command=command, args=args)
    print(summary(result))
    m = result.metrics
    for warning in m.warnings:
        print(f"warning: {warning}")
    if m.outcome == "stopped":
        print(f"STOPPED by the controller: {m.stop_reason}")
    if m.outcome == "interrupted":
        print("INTERRUPTED: the partial walk's log and metrics are written")
    print("wrote " + ", ".join(str(path) for path in written))
    return _OUTCOME_EXIT[m.outcome]


def write_outputs(result, out: Path, *, command, args) -> list[Path]:
    """The log, the figures (and the video), then ``metrics.json`` last, each atomically."""
    from mpcwalk.walking.figures import plot_estimator, plot_walk_over_time, plot_walk_top_view

    log_path = out / f"walk_log.{args.log_format}"
    written = [write_atomic(log_path, lambda tmp: result.log.save(tmp))]
    what = (
        f"v = ({command[0]:g} m/s, {command[1]:g} m/s, {command[2]:g} rad/s)" if command else "path"
    )
    if args.path is not None:
        what = str(args.path)
    title = f"{result.robot}, {result.generator}: {what}, T = {result.config.step_duration_s:g} s"
    if len(result.log):
        import matplotlib.pyplot as plt

        plots = [("top_view.png", plot_walk_top_view), ("com_cop.png", plot_walk_over_time)]
        if result.config.state_source == "estimator":
            plots.append(("estimator.png", plot_estimator))
        for name, plot in plots:
            figure = plot(result.schedule, result.log, title=title)
            written.append(write_atomic(out / name, partial(figure.savefig, dpi=120)))
            plt.close(figure)
    if args.video:
        written.append(out / "walk.mp4")
    written.append(write_json(out / METRICS_FILE, result.to_dict()))
    return written
