"""Paper M's comparison in one call: every part, the table, the goals, the figures.

:func:`run_paper_m` runs the push sweep's cells and the speed searches on the sweep engine
(:func:`~mpcwalk.experiments.paper_m.cases.paper_m_sweep`: resumable, rows in
``results.csv``), then the turning and disturbance walks, whose logs the figures draw, as Ray
tasks (:func:`~mpcwalk.sweep.map_tasks`); it writes ``results.json``, ``report.md`` (table,
goal checks, definitions, from :mod:`mpcwalk.experiments.paper_m.table`) and the figures
into one folder.
"""

import json
import time
from collections.abc import Mapping
from dataclasses import asdict
from pathlib import Path
from typing import Any

from mpcwalk.experiments.paper_m.cases import cell_results, paper_m_sweep, speed_results
from mpcwalk.experiments.paper_m.config import PaperMConfig, load_config
from mpcwalk.experiments.paper_m.push_grid import summarize_sweep
from mpcwalk.experiments.paper_m.table import format_report, goal_checks, table_rows
from mpcwalk.experiments.paper_m.walks import (
    CONTROLLERS,
    controller_availability,
    has_stabilizer,
    turning_summary,
    walk_task,
    with_stabilizer,
)
from mpcwalk.experiments.reporting import record_run
from mpcwalk.sweep import Task, map_tasks, run_sweep
from mpcwalk.walking.metrics import yaw_deviation_deg
from mpcwalk.walking.specification import ControllerSpec


def _key(spec: ControllerSpec) -> str:
    return json.dumps(asdict(spec), sort_keys=True, default=str)


def _disturbance_variants(spec: ControllerSpec, stabilizer: str, gyro_ok: bool):
    """(without, with) stabilizer variants of a controller (None where not available)."""
    if has_stabilizer(spec):
        return with_stabilizer(spec, None), spec
    return spec, (with_stabilizer(spec, stabilizer) if gyro_ok else None)


def run_paper_m(
    out_dir,
    config: PaperMConfig | None = None,
    *,
    controllers: Mapping[str, ControllerSpec] = CONTROLLERS,
    workers: int | None = None,
    address: str | None = None,
    progress: bool = True,
    plots: bool = True,
    overwrite: bool = False,
    command: str = "",
) -> dict[str, Any] | None:
    """Run paper M's experiments for the controllers and write the results into ``out_dir``.

    Args:
        out_dir: Output directory (created).
        config: Parameters (default: :func:`load_config`'s full mode); its ``controllers``
            (None: all that are available here) and ``parts`` say what runs.
        controllers: Name -> its controller.
        workers: Walks at once (default: one per core; on a cluster, its CPUs).
        address: Ray cluster (None: ``RAY_ADDRESS``, else a local Ray instance).
        progress: Progress bars.
        plots: Write the figures.
        overwrite: Start afresh in a folder holding another configuration.
        command: The command line, written into ``runs.json`` and the report.

    Returns:
        The results (as written to ``results.json``); None while cases of the sweep are
        missing (the same call runs them).
    """
    config = config or load_config()
    out = Path(out_dir)
    availability = controller_availability(controllers)
    wanted = list(config.controllers or controllers)
    selected = [n for n in wanted if availability.get(n, "unknown controller") is None]
    skipped = {n: availability.get(n, "unknown controller") for n in wanted if n not in selected}
    gyro_ok = (
        controller_availability(
            {"g": ControllerSpec(stabilizers=(config.disturbance.stabilizer,))}
        )["g"]
        is None
    )
    robot, experiments = config.robot, config.parts
    start = time.perf_counter()
    sweep = paper_m_sweep(config, {name: controllers[name] for name in selected})
    run = run_sweep(
        sweep, out, workers=workers, address=address, overwrite=overwrite, progress=progress
    )
    record_run(out, run, command=command, address=address)
    if not run.complete:
        return None
    tasks: list[Task] = []
    keys: list[tuple[str, Any]] = []
    if "turning" in experiments:
        turning = config.turning
        for name in selected:
            keys.append(("turning", name))
            tasks.append(
                (
                    walk_task,
                    (
                        robot,
                        controllers[name],
                        {"command": turning.command, "duration": turning.walking_duration},
                    ),
                )
            )
    variants: dict[str, dict[str, Any]] = {}
    if "disturbance" in experiments:
        dist = config.disturbance
        for name in selected:
            for spec in _disturbance_variants(controllers[name], dist.stabilizer, gyro_ok):
                if spec is None or _key(spec) in variants:
                    continue
                variants[_key(spec)] = spec
                for pushed in (True, False):
                    keys.append(("disturbance", (_key(spec), pushed)))
                    tasks.append(
                        (
                            walk_task,
                            (
                                robot,
                                spec,
                                {
                                    "command": dist.command,
                                    "duration": dist.walking_duration,
                                    "pushes": dist.external_forces() if pushed else [],
                                },
                            ),
                        )
                    )
    outputs = map_tasks(
        tasks, workers=workers, address=address, progress=progress, description="paper M walks"
    )
    wall = time.perf_counter() - start
    results: dict[str, Any] = {
        "command": command,
        "mode": config.mode,
        "config": asdict(config),
        "controllers": {n: asdict(controllers[n]) for n in selected},
        "skipped": skipped,
        "wall_time_s": wall,
        "workers": workers,
        "nb_tasks": len(sweep.cases) + len(tasks),
    }
    walks: dict[str, dict[str, Any]] = {"turning": {}, "disturbance": {}}
    cases = cell_results(run.rows)
    if "push" in experiments:
        results["push_sweep"] = {
            "summary": summarize_sweep(cases, config.push_sweep),
            "cases": [r.to_dict() for r in cases],
        }
    if "speed" in experiments:
        results["speed"] = speed_results(run.rows)
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
        from mpcwalk.experiments.paper_m.plots import write_figures

        results["figures"] = write_figures(out, results, walks, cases, config)
    (out / "results.json").write_text(json.dumps(results, indent=1, default=str) + "\n")
    (out / "report.md").write_text(format_report(results))
    return results


def _disturbance_results(selected, controllers, config, runs, gyro_ok, walks) -> dict[str, Any]:
    dist, after = config.disturbance, config.disturbance.last_push_end

    def measure(spec):
        if spec is None:
            return None
        pushed, reference = runs[(_key(spec), True)], runs[(_key(spec), False)]
        return {
            "stabilizer": "+".join(spec.stabilizers) or None,
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
        own, without, with_ = measure(controllers[name]), measure(off), measure(on)
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
