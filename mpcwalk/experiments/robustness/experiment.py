"""The robustness matrix as experiments of the registry: ``robustness`` (every factor),
``robustness_terrain`` (the terrain factors alone: the ``[terrain_only]`` table of the
matrix's ``config.toml``), ``robustness_cadence`` (the terrain factors on every robot at the
terrain cadence: its ``[terrain_cadence]`` table) and ``robustness_torque`` (the other
factors, the robots driven by torque motors: its ``[torque]`` table)."""

import json
from pathlib import Path
from typing import Any

from mpcwalk.experiments.protocol import Experiment, read_table
from mpcwalk.experiments.reporting import read_runs, runs_text
from mpcwalk.experiments.robustness.config import MatrixConfig, load_matrix_config
from mpcwalk.sweep import Sweep
from mpcwalk.walking.specification import WalkSpec


class Robustness(Experiment):
    """Every controller on every robot in worlds that are not the model."""

    name = "robustness"
    summary = "the robustness matrix: every controller on every robot in perturbed worlds"
    package = "mpcwalk.experiments.robustness"

    def config(self, *, quick: bool = False) -> MatrixConfig:
        return load_matrix_config(self.config_file, quick=quick)

    def cases(self, config: MatrixConfig) -> tuple[WalkSpec, ...]:
        from mpcwalk.experiments.robustness.worlds import matrix_cases

        return matrix_cases(config)

    def sweep(self, config: MatrixConfig, out: str | Path | None = None) -> Sweep:
        from mpcwalk.experiments.robustness.worlds import matrix_sweep

        return matrix_sweep(config)

    def figures(self, out: str | Path) -> list[str]:
        from mpcwalk.experiments.robustness.plots import write_figures

        return write_figures(Path(out), read_table(out)[1])

    def report(self, out: str | Path) -> Path:
        from mpcwalk.experiments.robustness.report import write_report

        out = Path(out)
        settings, rows = read_table(out)
        names = sorted(p.name for p in out.glob("matrix_*.png"))
        scaling = out / "scaling.md"
        return write_report(
            out,
            rows,
            header=matrix_header(settings, read_runs(out), len(rows)),
            scaling=scaling.read_text() if scaling.exists() else "",
            figures=names,
            skipped=settings.get("skipped", []),
            terrain_cadence=bool(settings.get("terrain_cadence", False)),
        )


class RobustnessTerrain(Robustness):
    """The terrain part of the robustness matrix: its terrain factors alone, the same
    worlds, on the robots and controllers of its ``[terrain_only]`` table."""

    name = "robustness_terrain"
    summary = "the robustness matrix's terrain factors alone (stairs, slope, stepping stones)"
    variant = "terrain_only"

    def config(self, *, quick: bool = False) -> MatrixConfig:
        return load_matrix_config(self.config_file, quick=quick, variant=self.variant)


class RobustnessCadence(RobustnessTerrain):
    """The terrain factors of the robustness matrix on every robot, each terrain walk at the
    terrain cadence (its ``[terrain_cadence]`` table)."""

    name = "robustness_cadence"
    summary = "the robustness matrix's terrain factors on every robot at the terrain cadence"
    variant = "terrain_cadence"


class RobustnessTorque(RobustnessTerrain):
    """The robustness matrix in torque mode: the same worlds but the terrains, every robot
    driven by torque motors fed by the whole-body inverse dynamics (the ``[torque]`` table)."""

    name = "robustness_torque"
    summary = "the robustness matrix with the robots torque-controlled (inverse dynamics)"
    variant = "torque"


def matrix_header(settings: dict[str, Any], runs: list[dict], nb_cases: int) -> str:
    """The head of the report: the runs that filled the table and what the matrix is."""
    from mpcwalk.experiments.robustness.factors import FACTORS
    from mpcwalk.experiments.robustness.terrains import TERRAIN_APART, TERRAIN_FACTORS

    plans = settings["robots"]
    factors = settings.get("factors") or list(FACTORS)
    variant = settings.get("variant")
    terrain = settings.get("terrain")
    robots = ", ".join(
        f"`{name}` ({', '.join(plan['controllers'])}; {plan['nb_steps']} steps at "
        f"{plan['command'][0]:g} m/s)"
        for name, plan in plans.items()
    )
    present = {c for plan in plans.values() for c in plan["controllers"]}
    slow = (
        ", ".join(
            f"`{name}` {steps} steps"
            for name, steps in settings["slow_controllers"].items()
            if name in present
        )
        or "none here"
    )
    low, high = settings["combination_size"]
    selection = (
        f" This run keeps the worlds of the whole matrix's draws whose factors are all among "
        f"{', '.join(factors)} (table [{variant}]; a combination only when all its factors "
        "are)."
        if variant or settings.get("factors")
        else ""
    )
    on_terrain = ""
    if terrain and set(factors) & set(TERRAIN_FACTORS):
        on_terrain = (
            " Terrain factors (stairs, slope, stones), built to each robot's leg and sole "
            f"lengths: `{json.dumps(terrain)}` ([terrain]); a world whose terrain does not "
            "fit the robot is skipped for it (below); a terrain walk takes, whatever the "
            "controller, the steps that carry it over the terrain: the distance to its far "
            "end and a sole length more over the nominal stride (vx times the step duration; "
            f"the footsteps on a terrain go further), and {terrain['exit_steps']} more; a "
            f"terrain factor combines with neither {', '.join(TERRAIN_APART)} nor another "
            "terrain factor."
        )
    return "\n".join(
        [
            "# The robustness matrix" + (f" ({variant})" if variant else "") + "\n",
            runs_text(runs, nb_cases),
            f"Mode {settings['mode']}. Robots and controllers: {robots}; the controllers with "
            f"their own timing take the same steps at it ({slow}). Worlds of each robot: the "
            f"nominal one ({len(settings['nominal_seeds'])} seeds), each factor alone at "
            f"{settings['levels']} random levels stratified over its range, and "
            f"{settings['combinations']} random combinations of {low} to {high} factors; every "
            f"controller of the robot walks every world, with the world's seed.{selection}"
            f"{on_terrain} Factors ({', '.join(factors)}) and ranges: "
            f"`{json.dumps(settings['ranges'])}` "
            "(`mpcwalk/experiments/robustness/config.toml`). Every walk runs on the estimator, "
            "with the robot's sensor model (scaled by the noise factor) and one control period "
            "of latency unless the latency factor says otherwise. A walk succeeds when it "
            "survives: it runs (an error counts as a failure) and neither falls nor is stopped "
            "by the controller. Table: `results.csv` (one row per walk, its configuration and "
            "metrics); `sweep.json`: the configuration.\n",
        ]
    )


__all__ = ["Robustness", "RobustnessTerrain", "matrix_header"]
