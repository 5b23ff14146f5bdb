"""Robustness of every pattern generator to a world that is not the model.

Each generator walks with the same closed loop (the controller's feedback on the estimated
CoM and its balance stabilizer: DCM integral action, ZMP distribution between the feet, foot
damping, CoM-offset estimate; the default of the QP generators, switched on here for the
closed forms too), on the state estimated from the sensors, while the simulated robot differs
from
the controller's model: torso mass, CoM offset, friction, latency, sensor noise, and a heavier
torso combined with each of the others. The cases, robots, walks and generators are data
(``experiments/robustness/robustness.toml``, read by
:func:`~mpcwalk.experiments.robustness_config.load_config`);
:func:`run_robustness` runs every walk as a Ray task (:func:`mpcwalk.sweep.map_tasks`) and
returns one row per walk, and
:mod:`mpcwalk.experiments.robustness_report` writes the tables.

The same module measures the estimator on a nominal walk of each robot
(:func:`estimator_row`: the four ``estimator_*`` keys of ``metrics.json``).
"""

import dataclasses
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import MpcwalkError
from mpcwalk.experiments.robustness_config import (
    DEFAULT_CONFIG,
    RobustnessCase,
    RobustnessConfig,
    RobustnessWalk,
    build_cases,
    load_config,
)
from mpcwalk.sweep import Task, map_tasks, worker_robot
from mpcwalk.walking.runner import run_walk

__all__ = [
    "DEFAULT_CONFIG",
    "ROW_METRICS",
    "RobustnessCase",
    "RobustnessConfig",
    "RobustnessResults",
    "RobustnessWalk",
    "build_cases",
    "estimator_row",
    "estimator_tasks",
    "load_config",
    "robustness_tasks",
    "run_robustness",
    "walk_row",
]

#: The metrics of a walk kept in a row of the table.
ROW_METRICS = (
    "fell",
    "fall_time_s",
    "steps_completed",
    "steps_planned",
    "foot_position_error_cm_mean",
    "foot_position_error_cm_max",
    "foot_step_error_cm_max",
    "cop_margin_min_m",
    "cop_margin_p05_m",
    "estimator_com_error_rms_m",
    "estimator_com_error_max_m",
    "estimator_com_error_support_rms_m",
    "estimator_com_velocity_error_rms_m_s",
    "estimator_yaw_drift_deg",
    "estimator_tick_us_median",
    "controller_tick_us_median",
    "real_time_factor",
)


def walk_row(
    robot: str,
    generator: str,
    walk: RobustnessWalk,
    case: RobustnessCase,
    control_period: float,
) -> dict[str, Any]:
    """One walk of the table (a Ray task): the case, then :data:`ROW_METRICS`.

    A walk the library refuses (an :class:`~mpcwalk.exceptions.MpcwalkError`: an infeasible
    command, a solver that fails to build) is a row with its ``error`` and no metrics; the
    other walks go on.
    """
    start = time.perf_counter()
    model = worker_robot(robot)
    row: dict[str, Any] = {
        "robot": robot,
        "walk": walk.name,
        "command": list(walk.command),
        "case": case.name,
        "generator": generator,
    }
    try:
        result = run_walk(
            model,
            generator,
            control_period=control_period,
            progress=False,
            feedback=True,
            controller_options={"balance": True},
            **walk.walk_arguments(model),
            **case.walk_arguments(control_period),
        )
    except MpcwalkError as error:
        return {**row, **dict.fromkeys(ROW_METRICS), "error": str(error)}
    metrics = result.metrics.to_dict()
    return {
        **row,
        "step_duration_s": result.config.step_duration_s,
        **{key: metrics[key] for key in ROW_METRICS},
        "fall_reason": metrics["fall_reason"],
        "error": None,
        "config": result.config.to_dict(),
        "wall_time_s": time.perf_counter() - start,
    }


def robustness_tasks(config: RobustnessConfig) -> list[Task]:
    """Every walk of the table (robot by robot, walk, case, generator)."""
    tasks: list[Task] = []
    for robot, walks in config.robots.items():
        for walk in walks:
            for case in config.cases:
                for generator in config.generators:
                    if generator in config.slow_generators:
                        mine = walk.slowed(*config.slow_generators[generator])
                    else:
                        mine = walk
                    tasks.append((walk_row, (robot, generator, mine, case, config.control_period)))
    return tasks


def estimator_row(
    robot: str,
    generator: str,
    walk: RobustnessWalk,
    control_period: float,
    figure: str | None = None,
    seed: int = 0,
) -> dict[str, Any]:
    """A nominal walk on the estimator (a Ray task): its row, and the figure of
    the estimated state against the ground truth written to ``figure`` (a PNG file)."""
    result = run_walk(
        worker_robot(robot),
        generator,
        command=walk.command,
        nb_steps=walk.nb_steps,
        control_period=control_period,
        progress=False,
        seed=seed,
    )
    if figure is not None and len(result.log):
        import matplotlib.pyplot as plt

        from mpcwalk.walking.figures import plot_estimator

        title = f"{robot}, {generator}: {walk.nb_steps} steps at {walk.command[0]:g} m/s"
        fig = plot_estimator(result.schedule, result.log, title=title)
        fig.savefig(figure, dpi=110)
        plt.close(fig)
    metrics = result.metrics.to_dict()
    return {
        "robot": robot,
        "generator": generator,
        "command": list(walk.command),
        "nb_steps": walk.nb_steps,
        "seed": seed,
        **{key: metrics[key] for key in ROW_METRICS},
        "latency_s": result.config.latency_s,
        "figure": None if figure is None else Path(figure).name,
    }


def estimator_tasks(config: RobustnessConfig, out_dir: str | Path | None = None) -> list[Task]:
    """The nominal walks of :attr:`RobustnessConfig.estimator_walks`, one per seed of
    :attr:`RobustnessConfig.estimator_seeds` (the first seed's figure into ``out_dir`` as
    ``estimator_<robot>.png``, or none)."""
    tasks: list[Task] = []
    for robot, walk in config.estimator_walks.items():
        for i, seed in enumerate(config.estimator_seeds):
            figure = None
            if out_dir is not None and i == 0:
                figure = str(Path(out_dir) / f"estimator_{robot}.png")
            arguments = (robot, config.estimator_generator, walk, config.control_period)
            tasks.append((estimator_row, (*arguments, figure, seed)))
    return tasks


@dataclass(frozen=True)
class RobustnessResults:
    """What :func:`run_robustness` measured.

    Attributes:
        rows: One row per walk of the table (:func:`walk_row`).
        estimator: One row per nominal walk of the estimator measurement.
        wall_time_s: Wall time of the whole run [s].
        workers: Walks at once.
    """

    rows: tuple[dict[str, Any], ...]
    estimator: tuple[dict[str, Any], ...]
    wall_time_s: float
    workers: int

    def falls(self) -> list[dict[str, Any]]:
        """The rows of the walks that fell (or could not run)."""
        return [row for row in self.rows if row["fell"] or row.get("error")]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready."""
        return dataclasses.asdict(self)


def run_robustness(
    config: RobustnessConfig,
    *,
    workers: int | None = None,
    progress: bool = True,
    figures_dir: str | Path | None = None,
    address: str | None = None,
) -> RobustnessResults:
    """Run the estimator walks and every walk of the table, as Ray tasks.

    Args:
        config: What to run (:func:`load_config`).
        workers: Walks at once (default: one per core).
        address: Ray cluster (None: ``RAY_ADDRESS``, else a local Ray instance).
        progress: Show a progress bar over the walks.
        figures_dir: Folder of the estimator figures (None: no figure).
    """
    import os

    workers = (os.cpu_count() or 1) if workers is None else workers
    if figures_dir is not None:
        Path(figures_dir).mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    tasks = estimator_tasks(config, figures_dir) + robustness_tasks(config)
    rows = map_tasks(
        tasks, workers=workers, address=address, progress=progress, description="robustness walks"
    )
    nb_estimator = len(config.estimator_walks) * len(config.estimator_seeds)
    return RobustnessResults(
        rows=tuple(rows[nb_estimator:]),
        estimator=tuple(rows[:nb_estimator]),
        wall_time_s=time.perf_counter() - start,
        workers=workers,
    )
