"""One case of a sweep: a walk's whole configuration (:class:`WalkCase`).

A case is a robot, a named controller (:mod:`mpcwalk.walking.controllers`), a velocity
command and a number of steps, pushes, how the simulated world differs from the model (torso
mass, CoM offset, friction, sensor noise, latency, servo strength, ground tilt and bumps),
the seed, and labels saying what the sweep made of it (a factor, a level). It runs with
:func:`mpcwalk.walking.runner.run_walk` (:meth:`WalkCase.walk_arguments`), reruns alone with
the ``mpcwalk walk`` command of :meth:`WalkCase.command_line`, and is known by the hash of its
configuration (:attr:`WalkCase.case_id`): the same case, the same walk.
"""

import hashlib
import json
import shlex
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from mpcwalk.exceptions import ConfigurationError

Push = tuple[float, float, float, float, float]
"""A push on the torso: start [s], duration [s], world force (fx, fy, fz) [N]."""

#: Columns of a case in a results table (then its labels, then the run's columns).
CASE_COLUMNS = (
    "case_id",
    "robot",
    "controller",
    "vx",
    "vy",
    "vyaw",
    "nb_steps",
    "pushes",
    "mass_scale",
    "com_dx",
    "com_dy",
    "friction",
    "noise_scale",
    "latency_periods",
    "servo_strength",
    "ground_tilt",
    "ground_tilt_direction",
    "ground_roughness",
    "seed",
    "control_period",
)


def _text(value: float) -> str:
    """A number as the command line reads it back exactly."""
    return repr(float(value)) if not float(value).is_integer() else f"{float(value):g}"


@dataclass(frozen=True)
class WalkCase:
    """A walk of a sweep (see the module docstring); the defaults are the nominal world.

    Attributes:
        robot: Robot name.
        controller: Named controller configuration (``mpcwalk controllers``).
        command: ``(vx [m/s], vy [m/s], vyaw [rad/s])``.
        nb_steps: Steps that follow the command (a closing step is added).
        pushes: Pushes on the torso (:data:`Push`).
        mass_scale: Factor on the torso mass of the simulated robot.
        com_offset: Shift (dx, dy) [m] of its torso's CoM.
        friction: Friction coefficient of the floor contacts (None: the model's).
        noise_scale: Factor on the sensor model's noise and bias.
        latency_periods: Sensing-to-actuation latency [control periods] (None: the sensor
            model's, one).
        servo_strength: Factor on the servos' gains and torque limits.
        ground_tilt: Slope of the ground [deg], up towards ``ground_tilt_direction`` [deg].
        ground_tilt_direction: See ``ground_tilt``.
        ground_roughness: Largest bump height of the ground [m].
        seed: Seed of the sensor noise and of the bumps.
        control_period: Controller tick [s].
        labels: ``(name, value)`` pairs saying what the sweep made of the case (columns of
            the table; not part of the walk).
    """

    robot: str
    controller: str
    command: tuple[float, float, float] = (0.1, 0.0, 0.0)
    nb_steps: int = 8
    pushes: tuple[Push, ...] = ()
    mass_scale: float = 1.0
    com_offset: tuple[float, float] = (0.0, 0.0)
    friction: float | None = None
    noise_scale: float = 1.0
    latency_periods: int | None = None
    servo_strength: float = 1.0
    ground_tilt: float = 0.0
    ground_tilt_direction: float = 0.0
    ground_roughness: float = 0.0
    seed: int = 0
    control_period: float = 0.01
    labels: tuple[tuple[str, Any], ...] = ()

    def __post_init__(self) -> None:
        clash = [name for name, _ in self.labels if name in CASE_COLUMNS]
        if clash:
            raise ConfigurationError(f"Labels {clash} would hide columns of the case.")
        if len(self.command) != 3:
            raise ConfigurationError(f"A command is (vx, vy, vyaw), got {self.command!r}.")

    @property
    def case_id(self) -> str:
        """Hash of the configuration and labels (16 hexadecimal digits)."""
        text = json.dumps(asdict(self), sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def label(self, name: str, default: Any = None) -> Any:
        """The value of a label."""
        return dict(self.labels).get(name, default)

    @property
    def latency(self) -> float | None:
        """The latency [s] (None: the sensor model's)."""
        if self.latency_periods is None:
            return None
        return round(self.latency_periods * self.control_period, 9)

    def walk_arguments(self) -> dict[str, Any]:
        """Keyword arguments of :func:`~mpcwalk.walking.runner.run_walk` (the robot apart)."""
        from mpcwalk.sim import ExternalForce

        return {
            "controller": self.controller,
            "command": tuple(self.command),
            "nb_steps": self.nb_steps,
            "control_period": self.control_period,
            "pushes": [
                ExternalForce(start, duration, np.array([fx, fy, fz], dtype=float))
                for start, duration, fx, fy, fz in self.pushes
            ],
            "mass_scale": self.mass_scale,
            "com_offset": tuple(self.com_offset),
            "friction": self.friction,
            "noise_scale": self.noise_scale,
            "latency": self.latency,
            "servo_strength": self.servo_strength,
            "ground_tilt": self.ground_tilt,
            "ground_tilt_direction": self.ground_tilt_direction,
            "ground_roughness": self.ground_roughness,
            "seed": self.seed,
        }

    def command_line(self, out: str = "walk") -> str:
        """The ``mpcwalk walk`` command that reruns this case alone (options left at their
        defaults are left out)."""
        vx, vy, vyaw = self.command
        words = ["mpcwalk", "walk", "--robot", self.robot, "--controller", self.controller]
        words += ["--vx", _text(vx), "--vy", _text(vy), "--vyaw", _text(vyaw)]
        words += ["--steps", str(self.nb_steps)]
        for push in self.pushes:
            words += ["--push", ",".join(_text(v) for v in push)]
        options = (
            ("--mass-scale", self.mass_scale, 1.0),
            ("--friction", self.friction, None),
            ("--noise-scale", self.noise_scale, 1.0),
            ("--latency", self.latency, None),
            ("--servo-strength", self.servo_strength, 1.0),
            ("--ground-tilt", self.ground_tilt, 0.0),
            ("--ground-tilt-direction", self.ground_tilt_direction, 0.0),
            ("--ground-roughness", self.ground_roughness, 0.0),
        )
        for option, value, default in options:
            if value != default and value is not None:
                words += [option, _text(value)]
        if tuple(self.com_offset) != (0.0, 0.0):
            words += ["--com-offset", ",".join(_text(v) for v in self.com_offset)]
        if self.control_period != 0.01:
            words += ["--control-period", _text(self.control_period)]
        words += ["--seed", str(self.seed), "--out", out]
        joined: list[str] = []  # a value starting with "-" is glued to its option
        for word in words:
            if word.startswith("-") and not word.startswith("--") and joined:
                joined[-1] = f"{joined[-1]}={word}"
            else:
                joined.append(word)
        return shlex.join(joined)

    def to_columns(self) -> dict[str, Any]:
        """The case as columns of a results table (:data:`CASE_COLUMNS`, then the labels)."""
        vx, vy, vyaw = self.command
        dx, dy = self.com_offset
        values = {
            **{k: v for k, v in asdict(self).items() if k in CASE_COLUMNS},
            "case_id": self.case_id,
            "vx": vx,
            "vy": vy,
            "vyaw": vyaw,
            "pushes": [list(push) for push in self.pushes],
            "com_dx": dx,
            "com_dy": dy,
        }
        return {**{c: values[c] for c in CASE_COLUMNS}, **dict(self.labels)}


__all__ = ["CASE_COLUMNS", "Push", "WalkCase"]
