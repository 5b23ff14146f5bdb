"""Where a control tick's time goes: a profile of whole walks, summarised per part.

Runs each walk once under ``cProfile`` (one process, one after the other) and writes
``profile.md`` beside a JSON of the figures: the wall time of the loop split into the
simulation (MuJoCo's steps, the ground truth and the sensor model), the estimator, the
pattern generator (the QP's update and solve), the whole-body IK, the rest of the
controller, and the loop's own bookkeeping (fall check, log). Profiling slows Python code
more than the compiled solvers, so the shares are indicative; the timings without the
profiler are ``mpcwalk bench loop``'s.

    python experiments/performance/profile_tick.py --out results/performance
"""

import argparse
import cProfile
import json
import platform
import pstats
from pathlib import Path

from mpcwalk.walking.runner import run_walk

WALKS = (
    ("bioloid-like", "mpc", (0.1, 0.0, 0.0)),
    ("bioloid-like", "mpc-steps", (0.1, 0.0, 0.0)),
    ("g1", "mpc", (0.2, 0.0, 0.0)),
)

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
    profiler = cProfile.Profile()
    profiler.enable()
    result = run_walk(robot, generator, command=command, nb_steps=nb_steps, progress=False)
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


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/performance"))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    rows = [profile_walk(robot, generator, command) for robot, generator, command in WALKS]
    lines = [
        "# Where a control tick's time goes",
        "",
        "Each walk (12 steps, default sensors and estimator) run once under `cProfile`, one "
        "process. Microseconds per 10 ms control tick, cumulative per part (the profiler slows "
        "the Python parts more than MuJoCo and the solvers: shares are indicative; the "
        "unprofiled timings are `mpcwalk bench loop`'s).",
        f"Machine: {platform.machine()}, Python {platform.python_version()}.",
        "Command: `python experiments/performance/profile_tick.py --out results/performance`",
        "",
        "| part | " + " | ".join(f"{r['robot']} {r['generator']}" for r in rows) + " |",
        "|---|" + "---:|" * len(rows),
    ]
    for label, _ in PARTS:
        cells = " | ".join(f"{r['parts_us_per_tick'][label]:.0f}" for r in rows)
        lines.append(f"| {label} | {cells} |")
    (args.out / "profile.md").write_text("\n".join(lines) + "\n")
    (args.out / "profile.json").write_text(json.dumps(rows, indent=2) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
