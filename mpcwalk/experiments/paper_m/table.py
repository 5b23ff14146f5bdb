"""Paper M's comparison as a table: rows, goal checks and the report of a run.

:func:`table_rows`, :func:`goal_checks` and :func:`format_table` turn the JSON-ready results of
:func:`mpcwalk.experiments.paper_m.run.run_paper_m` into the table (also usable on results
read back from ``results.json``); :func:`format_report` writes the ``report.md`` of a run.
"""

import json
from collections.abc import Mapping, Sequence
from typing import Any

from mpcwalk.experiments import reporting

#: Minimum ratio of the median impulse survived to paper M's whole engine's (``paper-m``): the
#: QP controllers with feedback 1.5x, the footstep-adaptive MPC 2x.
IMPULSE_GOALS = {"preview": 1.5, "mpc": 1.5, "mpc-steps": 2.0}
#: Largest relative error of the mean yaw rate against the command.
YAW_RATE_TOLERANCE = 0.05
#: The controller the impulse ratios are taken against.
BASELINE = "paper-m"

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
    """The goals: impulse ratios against paper M's engine (:data:`IMPULSE_GOALS`) and
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
    return reporting.table(
        ([PAPER_M_ROW] if with_paper else []) + list(rows), TABLE_COLUMNS, marks=_FELL_MARKS
    )


def format_goals(goals: Sequence[Mapping[str, Any]]) -> str:
    """Markdown list of the goal checks."""
    return (
        "".join(
            f"- {'**met**' if g['met'] else '**not met**'}: {g['controller']}, "
            f"{g['goal']} ({reporting.cell(g['value'])})\n"
            for g in goals
        )
        or "- (none run)\n"
    )


def format_report(results: Mapping[str, Any]) -> str:
    """``report.md`` of a results directory: command, table, goals, definitions, details."""
    config, lines = results["config"], []
    sweep, dist, turn = config["push_sweep"], config["disturbance"], config["turning"]
    lines += [
        "# Paper M's experiments on the bioloid-like robot",
        "",
        f"Made by `{results.get('command') or 'run_paper_m'}` ({results['mode']} mode: "
        f"{results['nb_tasks']} tasks in {results['wall_time_s']:.0f} s wall, "
        f"workers: {results.get('workers') or 'one per core'}). Controllers "
        "(`mpcwalk.experiments.paper_m.walks.CONTROLLERS`, keyword arguments of `run_walk`):",
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
        f"{sweep['relative_tolerance']:g} x upper); survived = walked to the end of the run "
        "(neither fell nor was stopped by the controller). Success rate: share of the grid impulses "
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
            cells = [reporting.cell(row["per_direction_Ns"].get(d), 3) for d in directions]
            lines.append(
                f"| {name} | " + " | ".join(cells) + " | "
                f"{reporting.cell(row['success_rate_runs'])} | {row['nb_walks']} | "
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
                    f"{e['fastest_m_s']:.3f} | {reporting.cell(e['fastest_measured_m_s'], 3)} | "
                    f"{e['limited_by']} |"
                )
        lines.append("")
    figures = sorted(p for p in results.get("figures", []))
    if figures:
        lines += ["## Figures", ""] + [f"`{name}`\n\n![{name}]({name})\n" for name in figures]
    return "\n".join(lines)
