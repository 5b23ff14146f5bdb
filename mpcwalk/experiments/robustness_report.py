"""The tables of the robustness experiment (:mod:`mpcwalk.experiments.robustness`):
markdown for the README, JSON for the scripts."""

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from mpcwalk.experiments.robustness import RobustnessConfig, RobustnessResults
from mpcwalk.walking.markdown import cell, table

#: Goals of the estimator's CoM error RMS [m] (issue 11): 5 mm on the small humanoid, 1 cm
#: on the large robots.
ESTIMATOR_GOALS = {"bioloid-like": 0.005}
ESTIMATOR_GOAL_LARGE = 0.01


def estimator_goal(robot: str) -> float:
    """The goal of the estimator's CoM error RMS on ``robot`` [m]."""
    return ESTIMATOR_GOALS.get(robot, ESTIMATOR_GOAL_LARGE)


def walk_cell(row: dict[str, Any]) -> str:
    """A walk in one cell: ``steps, foot error max [cm], CoP margin p5 [mm]``, or the fall."""
    if row.get("error"):
        return "**error**"
    steps = f"{row['steps_completed']}/{row['steps_planned']}"
    if row["fell"]:
        return f"**fell** {row['fall_time_s']:.1f} s ({steps})"
    margin = row["cop_margin_p05_m"]
    margin_text = "-" if margin is None else f"{1e3 * margin:+.1f} mm"
    return f"{steps}, {cell(row['foot_position_error_cm_max'], 1)} cm, {margin_text}"


def case_tables(
    rows: Sequence[dict[str, Any]], generators: Sequence[str], slow: Sequence[str] = ()
) -> str:
    """One table per robot and walk: a line per case, a column per generator (the command
    in the title is that of the generators not in ``slow``)."""
    parts = []
    groups: dict[tuple[str, str], dict[str, dict[str, dict[str, Any]]]] = {}
    for row in rows:
        cases = groups.setdefault((row["robot"], row["walk"]), {})
        cases.setdefault(row["case"], {})[row["generator"]] = row
    for (robot, walk), cases in groups.items():
        first = next(iter(cases.values()))
        command = next(
            (row for g, row in first.items() if g not in slow), next(iter(first.values()))
        )["command"]
        vx, vy, vyaw = command
        parts.append(
            f"#### {robot}, {walk} (vx {vx:g} m/s, vy {vy:g} m/s, vyaw {vyaw:.3f} rad/s)\n"
        )
        lines = [
            "| case | " + " | ".join(generators) + " |",
            "|---|" + "---|" * len(generators),
        ]
        for case, by_generator in cases.items():
            cells = [walk_cell(by_generator[g]) if g in by_generator else "" for g in generators]
            lines.append(f"| {case} | " + " | ".join(cells) + " |")
        parts.append("\n".join(lines) + "\n")
    return "\n".join(parts)


def summary_table(rows: Sequence[dict[str, Any]], generators: Sequence[str]) -> str:
    """Walks without a fall per generator and robot."""
    robots = list(dict.fromkeys(row["robot"] for row in rows))
    out = []
    for generator in generators:
        line: dict[str, Any] = {"generator": generator}
        for robot in robots:
            mine = [r for r in rows if r["generator"] == generator and r["robot"] == robot]
            walked = sum(not r["fell"] and not r.get("error") for r in mine)
            line[robot] = f"{walked}/{len(mine)}"
        out.append(line)
    return table(out, [("generator", "generator", 0)] + [(r, f"{r}: walked", 0) for r in robots])


def falls_table(rows: Sequence[dict[str, Any]]) -> str:
    """The walks that fell: when, after how many steps, why."""
    falls = [row for row in rows if row["fell"] or row.get("error")]
    if not falls:
        return "No walk falls.\n"
    return table(
        [
            {
                **row,
                "steps": f"{row['steps_completed']}/{row['steps_planned']}",
                "fall_reason": row.get("error") or row["fall_reason"],
            }
            for row in falls
        ],
        [
            ("robot", "robot", 0),
            ("walk", "walk", 0),
            ("case", "case", 0),
            ("generator", "generator", 0),
            ("fall_time_s", "fell at [s]", 1),
            ("steps", "steps", 0),
            ("fall_reason", "why", 0),
        ],
    )


def estimator_table(rows: Sequence[dict[str, Any]]) -> str:
    """The estimator's errors on the nominal walks, against the goals."""
    lines = []
    for row in rows:
        rms = row["estimator_com_error_rms_m"]
        goal = estimator_goal(row["robot"])
        lines.append(
            {
                "robot": row["robot"],
                "generator": row["generator"],
                "walk": f"{row['nb_steps']} steps at {row['command'][0]:g} m/s",
                "seed": row.get("seed", 0),
                "fell": row["fell"],
                "rms": None if rms is None else 1e3 * rms,
                "max": _scaled(row["estimator_com_error_max_m"], 1e3),
                "support": _scaled(row.get("estimator_com_error_support_rms_m"), 1e3),
                "velocity": _scaled(row["estimator_com_velocity_error_rms_m_s"], 1e3),
                "yaw": row["estimator_yaw_drift_deg"],
                "tick": row["estimator_tick_us_median"],
                "goal": f"< {1e3 * goal:g} mm: {'met' if rms is not None and rms < goal else 'NOT met'}",
            }
        )
    return table(
        lines,
        [
            ("robot", "robot", 0),
            ("generator", "generator", 0),
            ("walk", "walk", 0),
            ("seed", "seed", 0),
            ("fell", "fell", 0),
            ("rms", "CoM error RMS [mm]", 2),
            ("max", "CoM error max [mm]", 2),
            ("support", "CoM error relative to the support, RMS [mm]", 2),
            ("velocity", "CoM velocity error RMS [mm/s]", 1),
            ("yaw", "yaw drift [deg]", 2),
            ("tick", "estimator tick [us]", 0),
            ("goal", "goal (CoM RMS)", 0),
        ],
    )


def _slow_text(config: RobustnessConfig) -> str:
    """What the slower generators do differently."""
    if not config.slow_generators:
        return ""
    parts = [
        f"`{name}` takes the same steps {scale:g} times slower"
        + ("" if ratio is None else f", {ratio:g} of each in double support")
        for name, (scale, ratio) in config.slow_generators.items()
    ]
    return "; ".join(parts) + " (the static gaits cannot walk at the robots' default timing).\n"


def estimator_summary(rows: Sequence[dict[str, Any]]) -> str:
    """Per robot, over the seeds: the CoM error RMS (median, range) and how many seeds meet
    the goal."""
    lines = []
    for robot in dict.fromkeys(row["robot"] for row in rows):
        values = [
            row["estimator_com_error_rms_m"]
            for row in rows
            if row["robot"] == robot and row["estimator_com_error_rms_m"] is not None
        ]
        if not values:
            continue
        goal = estimator_goal(robot)
        values.sort()
        lines.append(
            {
                "robot": robot,
                "median": 1e3 * values[len(values) // 2],
                "range": f"{1e3 * values[0]:.1f} to {1e3 * values[-1]:.1f}",
                "met": f"{sum(v < goal for v in values)}/{len(values)} (< {1e3 * goal:g} mm)",
            }
        )
    return table(
        lines,
        [
            ("robot", "robot", 0),
            ("median", "CoM error RMS, median over the seeds [mm]", 1),
            ("range", "range [mm]", 0),
            ("met", "seeds meeting the goal", 0),
        ],
    )


def _scaled(value: float | None, factor: float) -> float | None:
    return None if value is None else factor * value


def format_readme(
    config: RobustnessConfig, results: RobustnessResults, *, command: str = ""
) -> str:
    """The README of the results folder: how it was made, the tables, the definitions."""
    rows, generators = list(results.rows), list(config.generators)
    minutes = results.wall_time_s / 60.0
    text = [
        "# Robustness: walking on the sensors in a world that is not the model\n",
        f"`{command}` ({config.mode} mode; {len(rows) + len(results.estimator)} walks in "
        f"{minutes:.1f} min of wall time, {results.workers} walks at once as Ray tasks).\n",
        "Every generator runs the controller's default closed loop on the state estimated "
        "from the sensors (default sensor noise and one control period of latency), on the "
        "simulated robot perturbed as the case says; the controller's model is never "
        "perturbed. A cell is: steps completed / planned, largest landing error against the "
        "planned footstep (world frame) [cm], 5th percentile of the measured CoP's margin in "
        "the measured support polygon [mm]; or the fall (time, steps). `mass` scales the "
        "torso mass, `com` shifts the torso's CoM (x forward, y left), `friction` is the "
        "floor's coefficient, `latency` is in control periods, `noise` scales the sensor "
        "model. Parameters: `experiments/robustness/robustness.toml`.\n",
    ]
    if results.estimator:
        figures = [row["figure"] for row in results.estimator if row.get("figure")]
        text += [
            "## The estimator on nominal walks\n",
            estimator_summary(results.estimator),
            estimator_table(results.estimator),
            "CoM error: estimated against true CoM (3D, world frame) at the time of the "
            "readings it came from (it holds the odometry's drift); relative to the support: "
            "the same for the CoM relative to the mean of the soles in contact (what the "
            "balance acts on); yaw drift: estimated minus true base yaw at the end, less "
            "that at the start; each seed draws other sensor noise and biases. Figures (first "
            "seed): " + ", ".join(f"`{name}`" for name in figures) + ".\n",
        ]
    if rows:
        text += [
            "## Walks without a fall\n",
            summary_table(rows, generators),
            "## Every case\n",
            _slow_text(config),
            case_tables(rows, generators, list(config.slow_generators)),
            "## The walks that fall\n",
            falls_table(rows),
        ]
    return "\n".join(text)


def write_results(
    out_dir: str | Path,
    config: RobustnessConfig,
    results: RobustnessResults,
    *,
    command: str = "",
) -> list[Path]:
    """Write ``README.md`` (the tables) and ``results.json`` (every row) into ``out_dir``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    readme = out / "README.md"
    readme.write_text(format_readme(config, results, command=command))
    data = {"command": command, "mode": config.mode, **results.to_dict()}
    path = out / "results.json"
    path.write_text(json.dumps(data, indent=1, default=str) + "\n")
    return [readme, path]
