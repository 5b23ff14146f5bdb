"""Paper M's comparison in one call: every experiment, the table, the goals, the figures.

:func:`run_paper_m` runs the walks of :mod:`mpcwalk.experiments.paper_m` in worker processes
and writes ``results.json``, ``README.md`` (table, goal checks, definitions) and the figures
into one directory; :func:`table_rows`, :func:`goal_checks` and :func:`format_table` turn the
JSON-ready results into the table (also usable on results read back from ``results.json``).
"""

import json
import time
from collections.abc import Mapping, Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Any

from mpcwalk.experiments.paper_m import (
    CONTROLLERS,
    EXPERIMENTS,
    PaperMConfig,
    controller_availability,
    has_stabilizer,
    load_config,
    push_case_task,
    speed_task,
    turning_summary,
    walk_task,
    with_stabilizer,
)
from mpcwalk.experiments.parallel_walks import run_tasks
from mpcwalk.experiments.push_sweep import SweepCase, summarize_sweep
from mpcwalk.walking import markdown
from mpcwalk.walking.report import yaw_deviation_deg

#: Minimum ratio of the median impulse survived to the open-loop analytic gait's.
IMPULSE_GOALS = {"mpc": 2.0, "mpc-steps": 3.0}
#: Largest relative error of the mean yaw rate against the command.
YAW_RATE_TOLERANCE = 0.05
#: The controller the impulse ratios are taken against.
BASELINE = "analytic"

PAPER_M_ROW = {
    "controller": "paper M (reported, own robot)",
    "turning_yaw_deg": 70.0,
    "turning_yaw_rate_deg_s": 20.0,
    "stabilizer_ratio": 0.4,
}

_PUSH_NOTE = (
    "largest impulse survived: per (direction, phase), bracketing and bisection on "
    "the impulse of a 0.1 s torso push; median over the grid"
)


def _key(kwargs: Mapping[str, Any]) -> str:
    return json.dumps(kwargs, sort_keys=True, default=str)


def _disturbance_variants(kwargs, stabilizer: str, gyro_ok: bool):
    """(without, with) stabilizer variants of a controller (None where not available)."""
    if has_stabilizer(kwargs):
        return with_stabilizer(kwargs, None), dict(kwargs)
    return dict(kwargs), (with_stabilizer(kwargs, stabilizer) if gyro_ok else None)


def run_paper_m(
    out_dir,
    config: PaperMConfig | None = None,
    *,
    controllers: Mapping[str, Mapping[str, Any]] = CONTROLLERS,
    names: Sequence[str] | None = None,
    experiments: Sequence[str] = EXPERIMENTS,
    workers: int | None = None,
    progress: bool = True,
    plots: bool = True,
    command: str = "",
) -> dict[str, Any]:
    """Run paper M's experiments for the controllers and write the results into ``out_dir``.

    Args:
        out_dir: Output directory (created).
        config: Parameters (default: :func:`load_config` of the full mode).
        controllers: Name -> :func:`run_walk` keyword arguments.
        names: Controllers to run (default: all that are available here).
        experiments: Some of :data:`EXPERIMENTS`.
        workers: Worker processes (default: one per core).
        progress: Progress bar.
        plots: Write the figures.
        command: The command line, written into the README.

    Returns:
        The results (as written to ``results.json``).
    """
    config = config or load_config()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    availability = controller_availability(controllers)
    wanted = list(names or controllers)
    selected = [n for n in wanted if availability.get(n, "unknown controller") is None]
    skipped = {n: availability.get(n, "unknown controller") for n in wanted if n not in selected}
    gyro_ok = (
        controller_availability({"g": {"stabilizer": config.disturbance.stabilizer}})["g"] is None
    )
    robot, tasks, keys = config.robot, [], []
    sweep, speed = config.push_sweep, config.speed
    if "push" in experiments:
        for name in selected:
            for direction in sweep.directions_deg:
                for phase in sweep.phases:
                    keys.append(("push", name))
                    tasks.append(
                        (
                            push_case_task,
                            (
                                robot,
                                dict(controllers[name]),
                                sweep,
                                SweepCase(name, direction, phase),
                            ),
                        )
                    )
    if "speed" in experiments:
        for name in selected:
            for T in speed.step_durations:
                keys.append(("speed", name))
                tasks.append((speed_task, (robot, dict(controllers[name]), speed, T)))
    if "turning" in experiments:
        turning = config.turning
        for name in selected:
            keys.append(("turning", name))
            tasks.append(
                (
                    walk_task,
                    (
                        robot,
                        dict(controllers[name]),
                        {"command": turning.command, "duration": turning.walking_duration},
                    ),
                )
            )
    variants: dict[str, dict[str, Any]] = {}
    if "disturbance" in experiments:
        dist = config.disturbance
        for name in selected:
            for kwargs in _disturbance_variants(controllers[name], dist.stabilizer, gyro_ok):
                if kwargs is None or _key(kwargs) in variants:
                    continue
                variants[_key(kwargs)] = kwargs
                for pushed in (True, False):
                    keys.append(("disturbance", (_key(kwargs), pushed)))
                    tasks.append(
                        (
                            walk_task,
                            (
                                robot,
                                kwargs,
                                {
                                    "command": dist.command,
                                    "duration": dist.walking_duration,
                                    "pushes": dist.external_forces() if pushed else [],
                                },
                            ),
                        )
                    )
    start = time.perf_counter()
    outputs = run_tasks(tasks, workers=workers, progress=progress, description="paper M walks")
    wall = time.perf_counter() - start
    results: dict[str, Any] = {
        "command": command,
        "mode": config.mode,
        "config": asdict(config),
        "controllers": {n: dict(controllers[n]) for n in selected},
        "skipped": skipped,
        "wall_time_s": wall,
        "workers": workers,
        "nb_tasks": len(tasks),
    }
    walks = {"turning": {}, "disturbance": {}}
    cases = [out_ for key, out_ in zip(keys, outputs) if key[0] == "push"]
    if "push" in experiments:
        results["push_sweep"] = {
            "summary": summarize_sweep(cases, sweep),
            "cases": [r.to_dict() for r in cases],
        }
    if "speed" in experiments:
        results["speed"] = {}
        for (kind, name), out_ in zip(keys, outputs):
            if kind == "speed":
                results["speed"].setdefault(name, []).append(out_)
    if "turning" in experiments:
        results["turning"] = {}
        for (kind, name), out_ in zip(keys, outputs):
            if kind == "turning":
                walks["turning"][name] = out_
                results["turning"][name] = turning_summary(out_, config.turning)
    if "disturbance" in experiments:
        runs = {key: out_ for (kind, key), out_ in zip(keys, outputs) if kind == "disturbance"}
        results["disturbance"] = _disturbance_results(
            selected, controllers, config, runs, gyro_ok, walks["disturbance"]
        )
    results["rows"] = table_rows(results)
    results["goals"] = goal_checks(results["rows"])
    if plots:
        from mpcwalk.experiments.paper_m_plots import write_figures

        results["figures"] = write_figures(out, results, walks, cases, config)
    (out / "results.json").write_text(json.dumps(results, indent=1, default=str) + "\n")
    (out / "README.md").write_text(format_readme(results))
    return results


def _disturbance_results(selected, controllers, config, runs, gyro_ok, walks) -> dict[str, Any]:
    dist, after = config.disturbance, config.disturbance.last_push_end

    def measure(kwargs):
        if kwargs is None:
            return None
        pushed, reference = runs[(_key(kwargs), True)], runs[(_key(kwargs), False)]
        return {
            "stabilizer": kwargs.get("stabilizer"),
            "fell": bool(pushed.fall.fell),
            "fall_time_s": pushed.metrics.get("fall_time_s"),
            "reference_fell": bool(reference.fall.fell),
            "yaw_deviation_deg": yaw_deviation_deg(pushed.log, reference.log, after),
            "yaw_deviation_final_deg": yaw_deviation_deg(
                pushed.log, reference.log, after, statistic="final"
            ),
            "_walks": (pushed, reference),
        }

    out = {}
    for name in selected:
        off, on = _disturbance_variants(controllers[name], dist.stabilizer, gyro_ok)
        own, without, with_ = measure(dict(controllers[name])), measure(off), measure(on)
        walks[name] = {
            "own": own.pop("_walks"),
            "off": without.pop("_walks"),
            "on": with_.pop("_walks") if with_ else None,
        }
        ratio = None
        if with_ and without["yaw_deviation_deg"] > 0.0:
            ratio = with_["yaw_deviation_deg"] / without["yaw_deviation_deg"]
        out[name] = {
            **own,
            "without_stabilizer": without,
            "with_stabilizer": with_,
            "stabilizer_ratio": ratio,
        }
    return out


def table_rows(results: Mapping[str, Any]) -> list[dict[str, Any]]:
    """One row per controller from the results of :func:`run_paper_m`."""
    names = list(results.get("controllers", {}))
    push = results.get("push_sweep", {}).get("summary", {})
    base = push.get(BASELINE, {}).get("median_impulse_Ns")
    rows = []
    for name in names:
        turn = results.get("turning", {}).get(name, {})
        dist = results.get("disturbance", {}).get(name, {})
        sweep = push.get(name, {})
        speeds = results.get("speed", {}).get(name, [])
        fastest = max(speeds, key=lambda s: s["fastest_m_s"], default=None)
        impulse = sweep.get("median_impulse_Ns")
        rows.append(
            {
                "controller": name,
                "turning_fell": turn.get("fell"),
                "turning_yaw_deg": turn.get("yaw_at_check_deg"),
                "turning_yaw_rate_deg_s": turn.get("yaw_rate_deg_s"),
                "turning_yaw_rate_error_percent": turn.get("yaw_rate_error_percent"),
                "disturbance_fell": dist.get("fell"),
                "yaw_deviation_deg": dist.get("yaw_deviation_deg"),
                "stabilizer_ratio": dist.get("stabilizer_ratio"),
                "stabilizer_pair_fell": None
                if not dist
                else any(
                    (dist.get(k) or {}).get("fell", False)
                    for k in ("without_stabilizer", "with_stabilizer")
                ),
                "impulse_median_Ns": impulse,
                "impulse_ratio": impulse / base if impulse is not None and base else None,
                "push_success_rate": sweep.get("success_rate_grid"),
                "fastest_m_s": None if fastest is None else fastest["fastest_m_s"],
                "fastest_step_duration_s": None if fastest is None else fastest["step_duration_s"],
                "speed_limited_by": None if fastest is None else fastest["limited_by"],
            }
        )
    return rows


def goal_checks(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """The issue's goals: impulse ratios against the analytic gait (:data:`IMPULSE_GOALS`) and
    the turning yaw rate within :data:`YAW_RATE_TOLERANCE` of the command."""
    checks = []
    for row in rows:
        name = row["controller"]
        if name in IMPULSE_GOALS and row.get("impulse_median_Ns") is not None:
            ratio = row.get("impulse_ratio")
            checks.append(
                {
                    "controller": name,
                    "goal": f"impulse >= {IMPULSE_GOALS[name]:g} x {BASELINE}",
                    "value": ratio,
                    "met": ratio is not None and ratio >= IMPULSE_GOALS[name],
                }
            )
        error = row.get("turning_yaw_rate_error_percent")
        if row.get("turning_fell") is not None:
            checks.append(
                {
                    "controller": name,
                    "goal": "turning yaw rate within "
                    f"{100 * YAW_RATE_TOLERANCE:g} % of the command, no fall",
                    "value": error,
                    "met": error is not None
                    and not row["turning_fell"]
                    and abs(error) <= 100.0 * YAW_RATE_TOLERANCE,
                }
            )
    return checks


TABLE_COLUMNS = (
    ("controller", "controller", 0),
    ("turning_fell", "turning: fell", 0),
    ("turning_yaw_deg", "yaw after 3.5 s [deg]", 1),
    ("turning_yaw_rate_deg_s", "yaw rate [deg/s] (cmd 20)", 2),
    ("turning_yaw_rate_error_percent", "yaw rate err. [%]", 1),
    ("disturbance_fell", "F1+F2: fell", 0),
    ("yaw_deviation_deg", "yaw dev. after F2 [deg]", 2),
    ("stabilizer_ratio", "yaw dev. gyro / none", 2),
    ("impulse_median_Ns", "impulse survived, median [N s]", 3),
    ("impulse_ratio", f"x {BASELINE}", 2),
    ("push_success_rate", "push success rate", 2),
    ("fastest_m_s", "fastest vx [m/s]", 3),
    ("fastest_step_duration_s", "at T [s]", 2),
    ("speed_limited_by", "speed limited by", 0),
)


#: Cells marked "(fell)" when the run(s) they come from fell.
_FELL_MARKS = {"yaw_deviation_deg": "disturbance_fell", "stabilizer_ratio": "stabilizer_pair_fell"}


def format_table(rows: Sequence[Mapping[str, Any]], *, with_paper: bool = True) -> str:
    """Markdown table of the rows (paper M's reported numbers first); a yaw deviation or
    ratio measured on a walk that fell is marked "(fell)"."""
    return markdown.table(
        ([PAPER_M_ROW] if with_paper else []) + list(rows), TABLE_COLUMNS, marks=_FELL_MARKS
    )


def format_goals(goals: Sequence[Mapping[str, Any]]) -> str:
    """Markdown list of the goal checks."""
    return (
        "".join(
            f"- {'**met**' if g['met'] else '**not met**'}: {g['controller']}, "
            f"{g['goal']} ({markdown.cell(g['value'])})\n"
            for g in goals
        )
        or "- (none run)\n"
    )


def format_readme(results: Mapping[str, Any]) -> str:
    """``README.md`` of a results directory: command, table, goals, definitions, details."""
    config, lines = results["config"], []
    sweep, dist, turn = config["push_sweep"], config["disturbance"], config["turning"]
    lines += [
        "# Paper M's experiments on the bioloid-like robot",
        "",
        f"Made by `{results.get('command') or 'run_paper_m'}` ({results['mode']} mode: "
        f"{results['nb_tasks']} tasks in {results['wall_time_s']:.0f} s wall, "
        f"workers: {results.get('workers') or 'one per core'}). Controllers "
        "(`mpcwalk.experiments.paper_m.CONTROLLERS`, keyword arguments of `run_walk`):",
        "",
    ]
    lines += [f"- `{n}`: `{json.dumps(k, default=str)}`" for n, k in results["controllers"].items()]
    lines += [f"- skipped `{n}`: {why}" for n, why in results.get("skipped", {}).items()]
    lines += ["", format_table(results["rows"]), "## Goals", "", format_goals(results["goals"])]
    lines += [
        "## Definitions",
        "",
        f"- Turning walk: command {turn['command']} (m/s, m/s, rad/s), "
        f"{turn['walking_duration']:g} s of walking after 1 s standing; yaw of the IMU "
        f"{turn['yaw_check_time']:g} s after walking starts; mean yaw rate over whole "
        "steps, from the end of the first step to the last step boundary before the "
        "closing step (or the fall).",
        f"- Disturbances: command {dist['command']}, pushes on the torso "
        f"(start [s], duration [s], force [N]) {dist['pushes']}. Yaw deviation after F2: "
        "largest |yaw - yaw of the same controller's walk without the pushes| from the end "
        "of F2 to the end of the shorter run (`yaw_deviation_deg`); ratio: with the "
        f"`{dist['stabilizer']}` stabilizer over without (paper M: about 0.4).",
        f"- Push recovery: {_PUSH_NOTE}; command {sweep['command']}, "
        f"{sweep['nb_steps']} steps (+ closing step), push in step {sweep['push_step']} "
        f"(0-based) at phases {list(sweep['phases'])}, directions "
        f"{[float(d) for d in sweep['directions_deg']]} deg (0 forward, 90 left), bracket "
        f"from {sweep['initial_impulse']:g} N s, stop at max({sweep['tolerance']:g} N s, "
        f"{sweep['relative_tolerance']:g} x upper); survived = no fall until the end of the "
        "run. Success rate: share of the grid impulses "
        f"{list(sweep['impulse_grid'])} N s at or below each cell's largest impulse "
        "survived (the oracle taken as monotone). LIPM bounds (figure): m omega d without "
        "a step, m omega (d + L exp(-omega t)) with one step (`capture_impulse_bound`).",
        "- Speed: bisection of vx up to the kinematic bound max_step_forward / T (the "
        f"velocity planner refuses more), {config['speed']['nb_steps']} commanded steps, "
        f"step durations {list(config['speed']['step_durations'])} s.",
        "",
    ]
    summary = results.get("push_sweep", {}).get("summary", {})
    if summary:
        directions = [f"{float(d):g}" for d in sweep["directions_deg"]]
        lines += [
            "## Largest impulse survived per direction [N s] (median over phases)",
            "",
            "| controller | "
            + " | ".join(f"{d} deg" for d in directions)
            + " | success rate of the walks run | walks | wall [s] |",
            "|" + "---|" * (len(directions) + 4),
        ]
        for name, row in summary.items():
            cells = [markdown.cell(row["per_direction_Ns"].get(d), 3) for d in directions]
            lines.append(
                f"| {name} | " + " | ".join(cells) + " | "
                f"{markdown.cell(row['success_rate_runs'])} | {row['nb_walks']} | "
                f"{row['wall_time_s']:.0f} |"
            )
        lines.append("")
    if results.get("speed"):
        lines += [
            "## Speed search",
            "",
            "| controller | T [s] | bound [m/s] | fastest [m/s] | measured [m/s] | limited by |",
            "|---|---|---|---|---|---|",
        ]
        for name, entries in results["speed"].items():
            for e in entries:
                lines.append(
                    f"| {name} | {e['step_duration_s']:g} | {e['bound_m_s']:.3f} | "
                    f"{e['fastest_m_s']:.3f} | {markdown.cell(e['fastest_measured_m_s'], 3)} | "
                    f"{e['limited_by']} |"
                )
        lines.append("")
    figures = sorted(p for p in results.get("figures", []))
    if figures:
        lines += ["## Figures", ""] + [f"`{name}`\n\n![{name}]({name})\n" for name in figures]
    return "\n".join(lines)
