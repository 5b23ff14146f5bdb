"""Paper M's comparison in one call: every experiment, the table, the goals, the figures.

:func:`run_paper_m` runs the walks of :mod:`mpcwalk.experiments.paper_m` as Ray tasks (the
sweep engine's :func:`~mpcwalk.sweep.map_tasks`, on this machine or a cluster) and writes ``results.json``, ``README.md`` (table, goal checks, definitions, from
:mod:`mpcwalk.experiments.paper_m_table`) and the figures into one directory.
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
from mpcwalk.experiments.paper_m_table import format_readme, goal_checks, table_rows
from mpcwalk.experiments.push_sweep import SweepCase, summarize_sweep
from mpcwalk.sweep import Task, map_tasks
from mpcwalk.walking.metrics import yaw_deviation_deg


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
    address: str | None = None,
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
        workers: Walks at once (default: one per core; on a cluster, its CPUs).
        address: Ray cluster (None: ``RAY_ADDRESS``, else a local Ray instance).
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
    robot = config.robot
    tasks: list[Task] = []
    keys: list[tuple[str, Any]] = []
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
    outputs = map_tasks(
        tasks, workers=workers, address=address, progress=progress, description="paper M walks"
    )
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
    walks: dict[str, dict[str, Any]] = {"turning": {}, "disturbance": {}}
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
            "fall_time_s": pushed.metrics.fall_time_s,
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
