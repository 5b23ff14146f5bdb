"""The robustness matrix's configuration: robots, controllers, factors and their ranges,
read from the ``config.toml`` beside this module (:func:`load_matrix_config`), with one of
its variant tables over it (``[quick]``: the test suite's; ``[terrain_only]``: the terrain
factors alone; ``[terrain_cadence]``: the terrain factors alone, every terrain walk at the
terrain cadence; ``[torque]``: the robots driven by torque motors and the inverse
dynamics)."""

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.protocol import config_path, mode_name, read_config
from mpcwalk.experiments.robustness.terrains import TerrainLayout
from mpcwalk.sim.actuation import check_actuation

DEFAULT_MATRIX = config_path("mpcwalk.experiments.robustness")


@dataclass(frozen=True)
class RobotPlan:
    """A robot's part of the matrix: its controllers, nominal command and steps."""

    controllers: tuple[str, ...]
    command: tuple[float, float, float]
    nb_steps: int


@dataclass(frozen=True)
class MatrixConfig:
    """The matrix (see its ``config.toml`` for each entry)."""

    robots: Mapping[str, RobotPlan]
    ranges: Mapping[str, Any]
    slow_controllers: Mapping[str, int] = field(default_factory=dict)
    levels: int = 3
    combinations: int = 10
    combination_size: tuple[int, int] = (2, 4)
    nominal_seeds: tuple[int, ...] = (0,)
    seed: int = 0
    timeout: float = 900.0
    control_period: float = 0.01
    mode: str = "full"
    factors: tuple[str, ...] | None = None
    terrain: TerrainLayout = field(default_factory=TerrainLayout)
    variant: str | None = None
    actuation: str = "position"
    terrain_cadence: bool = False

    def settings(self) -> dict[str, Any]:
        """The parameters as JSON (the sweep's fingerprint)."""
        return (
            {
                "robots": {name: vars(plan) for name, plan in self.robots.items()},
                "ranges": dict(self.ranges),
                "slow_controllers": dict(self.slow_controllers),
                "levels": self.levels,
                "combinations": self.combinations,
                "combination_size": list(self.combination_size),
                "nominal_seeds": list(self.nominal_seeds),
                "seed": self.seed,
                "timeout": self.timeout,
                "control_period": self.control_period,
                "mode": self.mode,
                "factors": None if self.factors is None else list(self.factors),
                "terrain": vars(self.terrain),
                "variant": self.variant,
            }
            | ({} if self.actuation == "position" else {"actuation": self.actuation})
            | ({"terrain_cadence": True} if self.terrain_cadence else {})
        )


def load_matrix_config(
    path: str | Path = DEFAULT_MATRIX, *, quick: bool = False, variant: str | None = None
) -> MatrixConfig:
    """Read the matrix from TOML; ``variant`` applies the table of that name (e.g.
    ``"terrain_only"``), then ``quick`` its ``[quick]`` table. A variant table holds
    ``robots``, ``controllers``, ``nb_steps``, ``levels``, ``combinations``,
    ``nominal_seeds``, ``factors`` (the factors of the worlds, default: all), ranges of
    ``[factors]``, ``terrain``, a table of entries of ``[terrain]``, ``actuation``
    (:data:`~mpcwalk.sim.actuation.ACTUATIONS`, default ``"position"``) and
    ``terrain_cadence`` (true: the walks on a terrain at the terrain cadence,
    :attr:`~mpcwalk.walking.specification.PlanSpec.terrain_cadence`; default false).

    Raises:
        ConfigurationError: A malformed table, or a variant the file does not hold.
    """
    data, quick_table = read_config(path, quick=quick)
    if variant is not None and not isinstance(data.get(variant), dict):
        raise ConfigurationError(f"The matrix file {path} holds no [{variant}] table.")
    overlay = {**(data[variant] if variant else {}), **quick_table}
    try:
        robots = {
            name: RobotPlan(
                tuple(overlay.get("controllers", plan["controllers"])),
                tuple(float(v) for v in plan["command"]),  # type: ignore[arg-type]
                int(overlay.get("nb_steps", plan["nb_steps"])),
            )
            for name, plan in data["robots"].items()
            if name in overlay.get("robots", data["robots"])
        }
        ranges = dict(data["factors"])
        ranges.update({k: v for k, v in overlay.items() if k in ranges})
        low, high = data.get("combination_size", (2, 4))
        factors = overlay.get("factors")
        layout = overlay.get("terrain", {})
        cadence = overlay.get("terrain_cadence", False)
        if not isinstance(cadence, bool):
            raise ConfigurationError(
                f"Malformed matrix file {path}: terrain_cadence must be true or false, got "
                f"{cadence!r}."
            )
        return MatrixConfig(
            robots=robots,
            ranges=ranges,
            slow_controllers={k: int(v) for k, v in data.get("slow_controllers", {}).items()},
            levels=int(overlay.get("levels", data.get("levels", 3))),
            combinations=int(overlay.get("combinations", data.get("combinations", 10))),
            combination_size=(int(low), int(high)),
            nominal_seeds=tuple(overlay.get("nominal_seeds", data.get("nominal_seeds", [0]))),
            seed=int(data.get("seed", 0)),
            timeout=float(data.get("timeout", 900.0)),
            control_period=float(data.get("control_period", 0.01)),
            mode=mode_name(quick),
            factors=None if factors is None else tuple(str(f) for f in factors),
            terrain=TerrainLayout.from_table({**data.get("terrain", {}), **layout}),
            variant=variant,
            actuation=check_actuation(overlay.get("actuation", "position")),
            terrain_cadence=cadence,
        )
    except (KeyError, TypeError, ValueError) as error:
        raise ConfigurationError(f"Malformed matrix file {path}: {error!r}.") from None


__all__ = ["DEFAULT_MATRIX", "MatrixConfig", "RobotPlan", "load_matrix_config"]
