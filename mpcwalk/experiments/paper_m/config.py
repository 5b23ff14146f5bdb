"""Paper M's experiments: their parameters, read from the ``config.toml`` beside this module.

1. turning walk (paper M Fig. 1): yaw after 3.5 s of walking and mean yaw rate
   (:class:`TurningConfig`);
2. disturbances F1, F2 (paper M Fig. 2): yaw deviation after F2 against the same walk without
   pushes, with the stabilizer off and on (:class:`DisturbanceConfig`);
3. push recovery: largest impulse survived per direction and gait phase
   (:class:`~mpcwalk.experiments.paper_m.push_grid.PushSweepConfig`);
4. speed: the fastest forward walk that survives (:class:`SpeedConfig`).

:func:`load_config` reads them (``quick=True``: the ``[quick]`` tables over the others).
"""

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.paper_m.push_grid import PushSweepConfig
from mpcwalk.experiments.protocol import config_path, mode_name, read_config, unknown_keys
from mpcwalk.sim import ExternalForce

#: The parts of paper M's comparison (:func:`mpcwalk.experiments.paper_m.run.run_paper_m`).
PARTS = ("turning", "disturbance", "push", "speed")

DEFAULT_CONFIG = config_path("mpcwalk.experiments.paper_m")


@dataclass(frozen=True)
class TurningConfig:
    """Paper M's turning walk: command ``(vx [m/s], vy [m/s], vyaw [rad/s])``, walking time
    [s], and the walking time [s] at which the yaw is read (paper M: about 70 deg at 3.5 s)."""

    command: tuple[float, float, float] = (0.1, 0.0, math.pi / 9.0)
    walking_duration: float = 10.0
    yaw_check_time: float = 3.5


@dataclass(frozen=True)
class DisturbanceConfig:
    """Paper M's disturbance walk: command, walking time [s], pushes as
    ``(start [s], duration [s], (fx, fy, fz) [N])`` on the torso, the stabilizer toggled for
    the ratio of the yaw deviations."""

    command: tuple[float, float, float] = (0.1, 0.0, 0.0)
    walking_duration: float = 5.0
    pushes: tuple[tuple[float, float, tuple[float, float, float]], ...] = (
        (0.0, 0.1, (0.0, 5.0, 0.0)),
        (3.0, 0.05, (10.0, 5.0, 0.0)),
    )
    stabilizer: str = "gyro"

    def external_forces(self) -> list[ExternalForce]:
        """The pushes as :class:`~mpcwalk.sim.ExternalForce` on the torso."""
        return [
            ExternalForce(start, duration, np.array(force, dtype=float))
            for start, duration, force in self.pushes
        ]

    @property
    def last_push_end(self) -> float:
        """End of the last push [s] (the yaw deviation is measured after it)."""
        return max(start + duration for start, duration, _ in self.pushes)


@dataclass(frozen=True)
class SpeedConfig:
    """Speed search: step durations tried [s], commanded steps per walk, tolerance [m/s]."""

    step_durations: tuple[float, ...] = (0.5, 0.4)
    nb_steps: int = 10
    tolerance: float = 0.005


@dataclass(frozen=True)
class PaperMConfig:
    """All of paper M's experiments (see the module docstring): the robot, the mode
    (``"full"`` or ``"quick"``), the controllers compared (names of
    :data:`~mpcwalk.experiments.paper_m.walks.CONTROLLERS`; None: all), the parts run
    (:data:`PARTS`) and each part's parameters."""

    robot: str = "bioloid-like"
    mode: str = "full"
    controllers: tuple[str, ...] | None = None
    parts: tuple[str, ...] = PARTS
    turning: TurningConfig = field(default_factory=TurningConfig)
    disturbance: DisturbanceConfig = field(default_factory=DisturbanceConfig)
    push_sweep: PushSweepConfig = field(default_factory=PushSweepConfig)
    speed: SpeedConfig = field(default_factory=SpeedConfig)


def _tuples(value):
    if isinstance(value, list):
        return tuple(_tuples(v) for v in value)
    return value


def _section(cls, values: Mapping[str, Any], where: str):
    from dataclasses import fields

    unknown_keys(values, [f.name for f in fields(cls)], where)
    return cls(**{key: _tuples(value) for key, value in values.items()})


_SECTIONS = {
    "turning": TurningConfig,
    "disturbance": DisturbanceConfig,
    "push_sweep": PushSweepConfig,
    "speed": SpeedConfig,
}


def load_config(path: str | Path = DEFAULT_CONFIG, *, quick: bool = False) -> PaperMConfig:
    """Read the experiments' parameters from a TOML file; ``quick`` applies its
    ``[quick]`` table (``controllers``, ``parts``) and its ``[quick.*]`` tables over the
    others (the reduced grid).

    Raises:
        ConfigurationError: An unknown key, part or section.
    """
    data, small = read_config(path, quick=quick)
    unknown_keys(data, ["robot", "controllers", "parts", *_SECTIONS], "paper M")
    unknown_keys(small, ["controllers", "parts", *_SECTIONS], "quick")
    values: dict[str, Any] = {"robot": data.get("robot", "bioloid-like"), "mode": mode_name(quick)}
    for key in ("controllers", "parts"):
        if key in small or key in data:
            values[key] = tuple(small.get(key, data.get(key, ())))
    wrong = sorted(set(values.get("parts", PARTS)) - set(PARTS))
    if wrong:
        raise ConfigurationError(f"Unknown part(s) {wrong} of paper M; the parts are {PARTS}.")
    for name, cls in _SECTIONS.items():
        values[name] = _section(cls, {**data.get(name, {}), **small.get(name, {})}, name)
    return PaperMConfig(**values)


__all__ = [
    "DEFAULT_CONFIG",
    "PARTS",
    "DisturbanceConfig",
    "PaperMConfig",
    "SpeedConfig",
    "TurningConfig",
    "load_config",
]
