"""The push map on the sweep engine: the largest push each controller survives, per direction,
phase of the step and walking speed, and its ratio to ``paper-m``'s in the same cell.

A case (:class:`PushCase`) is one controller pushed in one direction (of ``nb_directions``
around the robot, 0 deg forward, 90 deg left) at one phase of the pushed step (of
``nb_phases``, from the step's start) while walking forward at one speed (a share of the
robot's nominal speed; 0: stepping in place). Its runner (:func:`run_push_case`) brackets and
bisects the impulse of a 0.1 s torso push (:func:`~mpcwalk.experiments.push_sweep.
find_largest_survived`), in units of the LIPM's no-step capture bound in that direction, and
returns the largest impulse survived. :func:`write_push_report` writes the table of ratios
and the heat maps.
"""

import json
import math
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from mpcwalk.experiments.push_sweep import capture_impulse_bound, find_largest_survived
from mpcwalk.sweep import Sweep, worker_robot
from mpcwalk.walking.markdown import table

REFERENCE = "paper-m"

#: What the runner of a push case returns.
PUSH_COLUMNS = (
    "capture_bound_Ns",
    "largest_survived_Ns",
    "smallest_fallen_Ns",
    "largest_share",
    "censored",
    "nb_walks",
    "trials",
)


@dataclass(frozen=True)
class PushMapConfig:
    """The grid and the bisection (impulses as shares of the no-step capture bound)."""

    robot: str = "bioloid-like"
    controllers: tuple[str, ...] = (REFERENCE, "preview", "mpc", "mpc-steps")
    nb_directions: int = 16
    nb_phases: int = 6
    speed_shares: tuple[float, ...] = (0.0, 0.5, 1.0)
    nb_steps: int = 5
    push_step: int = 2
    push_duration: float = 0.1
    initial_share: float = 0.5
    max_share: float = 3.0
    tolerance_share: float = 0.05
    relative_tolerance: float = 0.1
    control_period: float = 0.01
    seed: int = 0

    def quick(self) -> "PushMapConfig":
        """A small grid: 4 directions, 2 phases, the nominal speed, paper-m and mpc."""
        return replace(
            self, controllers=(REFERENCE, "mpc"), nb_directions=4, nb_phases=2, speed_shares=(1.0,)
        )

    def settings(self) -> dict[str, Any]:
        """The configuration as JSON."""
        return asdict(self)


@dataclass(frozen=True)
class PushCase:
    """One cell of the push map for one controller."""

    config: PushMapConfig
    controller: str
    direction_deg: float
    phase: float
    speed_share: float

    @property
    def case_id(self) -> str:
        """The cell and the controller (the rest is the sweep's settings)."""
        return f"{self.controller}/{self.direction_deg:g}/{self.phase:.4f}/{self.speed_share:g}"

    def to_columns(self) -> dict[str, Any]:
        """Columns of the results table."""
        return {
            "case_id": self.case_id,
            "robot": self.config.robot,
            "controller": self.controller,
            "direction_deg": self.direction_deg,
            "phase": self.phase,
            "speed_share": self.speed_share,
        }


def push_map_cases(config: PushMapConfig) -> tuple[PushCase, ...]:
    """Every cell for every controller (controller by controller)."""
    return tuple(
        PushCase(
            config,
            controller,
            round(360.0 * i / config.nb_directions, 4),
            j / config.nb_phases,
            speed,
        )
        for controller in config.controllers
        for speed in config.speed_shares
        for j in range(config.nb_phases)
        for i in range(config.nb_directions)
    )


def run_push_case(case: PushCase) -> dict[str, Any]:
    """The largest impulse ``case.controller`` survives in its cell (walks by bisection)."""
    from mpcwalk.footsteps.velocity_planner import VelocityPlanner
    from mpcwalk.sim import ExternalForce
    from mpcwalk.walking.controller_resolution import default_timing
    from mpcwalk.walking.controllers import controller_config
    from mpcwalk.walking.runner import run_walk

    config = case.config
    robot = worker_robot(config.robot)
    generator = controller_config(case.controller).generator
    timing = default_timing(generator, robot.gait, None, None)
    nominal = VelocityPlanner(robot.leg_limits, timing).default_command().vx
    start = 1.0 + (config.push_step + case.phase) * timing.step_duration
    angle = math.radians(case.direction_deg)
    bound = capture_impulse_bound(
        angle,
        mass=robot.total_mass,
        com_height=robot.com_height,
        half_length=0.5 * robot.sole_size[0],
        half_width=0.5 * robot.sole_size[1],
    )

    def survives(impulse: float) -> bool:
        magnitude = impulse / config.push_duration
        force = (magnitude * math.cos(angle), magnitude * math.sin(angle), 0.0)
        result = run_walk(
            robot,
            controller=case.controller,
            command=(case.speed_share * nominal, 0.0, 0.0),
            nb_steps=config.nb_steps,
            control_period=config.control_period,
            pushes=[ExternalForce(start, config.push_duration, np.asarray(force, dtype=float))],
            seed=config.seed,
        )
        return not result.fall.fell

    found = find_largest_survived(
        survives,
        initial=config.initial_share * bound,
        upper_limit=config.max_share * bound,
        tolerance=config.tolerance_share * bound,
        relative_tolerance=config.relative_tolerance,
    )
    return {
        "capture_bound_Ns": bound,
        "largest_survived_Ns": found.largest_survived,
        "smallest_fallen_Ns": found.smallest_fallen,
        "largest_share": found.largest_survived / bound,
        "censored": found.censored,
        "nb_walks": len(found.trials),
        "trials": [[round(value, 6), ok] for value, ok in found.trials],
    }


def push_map_sweep(config: PushMapConfig) -> Sweep:
    """The push map as a sweep of the engine."""
    return Sweep(
        name="push-map",
        cases=push_map_cases(config),
        runner=run_push_case,
        columns=PUSH_COLUMNS,
        settings=config.settings(),
        timeout=1800.0,
    )


def ratios(rows: list[dict]) -> dict[str, list[tuple[tuple, float | None]]]:
    """Per controller, ``(cell, ratio to paper-m)`` of every cell (None: paper-m survived
    nothing there, or a row has an error)."""
    cell = lambda r: (r["direction_deg"], r["phase"], r["speed_share"])
    reference = {cell(r): r["largest_survived_Ns"] for r in rows if r["controller"] == REFERENCE}
    out: dict[str, list[tuple[tuple, float | None]]] = {}
    for row in rows:
        ref, value = reference.get(cell(row)), row.get("largest_survived_Ns")
        ratio = value / ref if ref and value is not None and not row.get("error") else None
        out.setdefault(row["controller"], []).append((cell(row), ratio))
    return out


def _median(values: list[float]) -> float | None:
    values = sorted(values)
    if not values:
        return None
    middle = len(values) // 2
    return values[middle] if len(values) % 2 else 0.5 * (values[middle - 1] + values[middle])


def summary_table(rows: list[dict]) -> str:
    """Per controller: median impulse, median ratio to paper-m, cells at or above it."""
    lines = []
    for controller, pairs in ratios(rows).items():
        mine = [r for r in rows if r["controller"] == controller and not r.get("error")]
        values = [v for _, v in pairs if v is not None]
        lines.append(
            {
                "controller": controller,
                "cells": len(pairs),
                "impulse": _median([r["largest_survived_Ns"] for r in mine]),
                "share": _median([r["largest_share"] for r in mine]),
                "ratio": _median(values),
                "above": f"{sum(v >= 1.0 for v in values)}/{len(values)}",
                "censored": sum(bool(r["censored"]) for r in mine),
                "walks": sum(int(r["nb_walks"]) for r in mine),
                "errors": sum(bool(r.get("error")) for r in rows if r["controller"] == controller),
            }
        )
    return table(
        lines,
        [
            ("controller", "controller", 0),
            ("cells", "cells", 0),
            ("impulse", "largest impulse survived, median [N s]", 3),
            ("share", "of the no-step capture bound, median", 2),
            ("ratio", f"ratio to {REFERENCE} per cell, median", 2),
            ("above", f"cells at or above {REFERENCE}", 0),
            ("censored", "cells censored at the largest push", 0),
            ("walks", "walks", 0),
            ("errors", "errors", 0),
        ],
    )


def write_push_report(out_dir: str | Path, rows, config: PushMapConfig, runs: str) -> Path:
    """Write ``report.md`` and ``push_ratio_*.png`` (ratio to paper-m per direction and
    phase, one per controller and speed) into ``out_dir``; returns the report's path."""
    import matplotlib.pyplot as plt
    import numpy as np

    out = Path(out_dir)
    rows = list(rows)
    names = []
    directions = sorted({r["direction_deg"] for r in rows})
    phases = sorted({r["phase"] for r in rows})
    for controller, pairs in ratios(rows).items():
        if controller == REFERENCE:
            continue
        for speed in config.speed_shares:
            grid = np.full((len(phases), len(directions)), np.nan)
            for (direction, phase, share), value in pairs:
                if share == speed and value is not None:
                    grid[phases.index(phase), directions.index(direction)] = value
            fig, ax = plt.subplots(figsize=(1.2 + 0.5 * len(directions), 1.0 + 0.4 * len(phases)))
            image = ax.imshow(np.log2(grid), cmap="RdBu", vmin=-2, vmax=2, aspect="auto")
            for (i, j), value in np.ndenumerate(grid):
                if np.isfinite(value):
                    ax.text(j, i, f"{value:.1f}", ha="center", va="center", fontsize=6)
            ax.set_xticks(range(len(directions)), [f"{d:g}" for d in directions], fontsize=7)
            ax.set_yticks(range(len(phases)), [f"{p:.2f}" for p in phases], fontsize=7)
            ax.set_xlabel("push direction [deg] (0: forward, 90: left)")
            ax.set_ylabel("phase [share of the step]")
            ax.set_title(f"{controller} / {REFERENCE}, speed x{speed:g}", fontsize=9)
            fig.colorbar(image, ax=ax, fraction=0.03, label="log2 ratio")
            fig.tight_layout()
            name = f"push_ratio_{controller}_speed{speed:g}.png"
            fig.savefig(out / name, dpi=100)
            plt.close(fig)
            names.append(name)
    text = [
        f"# Push map: {config.robot}\n",
        runs,
        f"Grid: {config.nb_directions} directions, {config.nb_phases} phases per step, speeds "
        f"{', '.join(f'x{s:g}' for s in config.speed_shares)} of the robot's nominal speed; "
        f"a {config.push_duration:g} s push on the torso in step {config.push_step} of "
        f"{config.nb_steps}; per cell, the largest impulse survived by bracketing and "
        f"bisection (from {config.initial_share:g} up to {config.max_share:g} times the "
        "LIPM's no-step capture bound in that direction). Settings: "
        f"`{json.dumps(config.settings())}`.\n",
        summary_table(rows),
        "\n".join(f"![{n}]({n})" for n in names) + "\n",
    ]
    path = out / "report.md"
    path.write_text("\n".join(text))
    return path


__all__ = [
    "PUSH_COLUMNS",
    "PushCase",
    "PushMapConfig",
    "push_map_cases",
    "push_map_sweep",
    "ratios",
    "run_push_case",
    "summary_table",
    "write_push_report",
]
