"""Where a control tick's time goes: one walk under ``cProfile``, summarised per part.

:func:`profile_walk` splits the wall time of the loop into the simulation (MuJoCo's steps,
the ground truth and the sensor model), the estimator, the pattern generator (the QP's
update and solve), the whole-body IK, the rest of the controller, and the loop's own
bookkeeping (fall check, log). Profiling slows Python code more than the compiled solvers,
so the shares are indicative; the timings without the profiler are ``mpcwalk bench loop``'s.
"""

import cProfile
import pstats

from mpcwalk.walking.runner import run_walk

#: The parts of a tick, each the cumulative time of one function (file suffix, name).
PARTS = (
    ("loop", ("walking/control_loop.py", "run")),
    ("simulation (MuJoCo, ground truth, sensor model)", ("sim/simulation.py", "step")),
    ("  of which MuJoCo's steps", ("~", "<built-in method mujoco._functions.mj_step>")),
    ("  of which the ground truth", ("sim/ground_truth.py", "read")),
    ("estimator", ("estimation/estimator.py", "update")),
    ("controller tick", ("control/controller.py", "step")),
    ("  of which the generator", ("control/faults.py", "step_generator")),
    ("  of which the IK", ("control/faults.py", "ik_step")),
    (
        "  of which the joint targets (feed-forward, stabilizer)",
        ("control/controller.py", "_joint_targets"),
    ),
    ("fall check", ("sim/fall_detection.py", "check")),
    ("log", ("walking/log.py", "append")),
)


def _cumulative(stats: pstats.Stats, suffix: str, name: str) -> tuple[float, int]:
    for (filename, _, function), (_, calls, _, cumulative, _) in stats.stats.items():  # type: ignore[attr-defined]
        if function == name and (suffix == "~" or filename.replace("\\", "/").endswith(suffix)):
            return cumulative, calls
    return 0.0, 0


def profile_walk(robot: str, generator: str, command, nb_steps: int = 12) -> dict:
    """Walk ``robot`` with the named controller ``generator`` under ``cProfile``: the ticks, whether it fell,
    the loop's time [s] and the microseconds per tick of each part of :data:`PARTS`."""
    profiler = cProfile.Profile()
    profiler.enable()
    result = run_walk(robot, controller=generator, command=command, nb_steps=nb_steps)
    profiler.disable()
    stats = pstats.Stats(profiler)
    loop, _ = _cumulative(stats, *PARTS[0][1])
    parts = {}
    for label, (suffix, name) in PARTS:
        seconds, _ = _cumulative(stats, suffix, name)
        parts[label] = seconds
    nb_ticks = int(round(result.metrics.time_simulated_s / result.config.control_period_s))
    return {
        "robot": robot,
        "generator": generator,
        "ticks": nb_ticks,
        "fell": bool(result.metrics.fell),
        "loop_s": loop,
        "parts_us_per_tick": {k: 1e6 * v / nb_ticks for k, v in parts.items()},
    }


__all__ = ["PARTS", "profile_walk"]
