"""The robustness experiment's configuration: cases, walks, generators, read from TOML.

A :class:`RobustnessCase` is one way the simulated world differs from the model (keywords of
:func:`~mpcwalk.walking.runner.run_walk`); a :class:`RobustnessWalk` is a command, a number
of steps and a timing; :func:`load_config` reads them all
(``experiments/robustness/robustness.toml``) into a :class:`RobustnessConfig`.
"""

import dataclasses
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.package_data import EXPERIMENT_DATA, package_data_dir

DEFAULT_CONFIG = package_data_dir(EXPERIMENT_DATA) / "robustness" / "robustness.toml"

#: The perturbation keywords a case may set (those of :func:`run_walk`), besides the latency.
CASE_KEYS = ("mass_scale", "com_offset", "friction", "servo_strength", "noise_scale")


@dataclass(frozen=True)
class RobustnessCase:
    """One way the simulated world differs from the model.

    Attributes:
        name: Name in the tables (e.g. ``"mass x1.3"``).
        world: Keywords of :func:`run_walk` (``mass_scale``, ``com_offset`` (dx, dy) [m],
            ``friction``, ``servo_strength``, ``noise_scale``); empty for the nominal case.
        latency_periods: Sensing-to-actuation latency [control periods], None for the
            sensor model's default (one).
    """

    name: str
    world: Mapping[str, Any] = field(default_factory=dict)
    latency_periods: int | None = None

    def walk_arguments(self, control_period: float) -> dict[str, Any]:
        """The keyword arguments of :func:`run_walk` of this case."""
        arguments = dict(self.world)
        if self.latency_periods is not None:
            arguments["latency"] = self.latency_periods * control_period
        return arguments

    def changes(self) -> set[str]:
        """What the case changes (its keywords, ``latency``)."""
        return set(self.world) | ({"latency"} if self.latency_periods is not None else set())

    def combined(self, other: "RobustnessCase") -> "RobustnessCase":
        """This case and ``other`` at once, named ``"<this> + <other>"``."""
        latency = other.latency_periods
        return RobustnessCase(
            f"{self.name} + {other.name}",
            {**self.world, **other.world},
            self.latency_periods if latency is None else latency,
        )


@dataclass(frozen=True)
class RobustnessWalk:
    """A walk of a robot: its name in the tables, the command ``(vx [m/s], vy [m/s], vyaw
    [rad/s])``, the number of steps (a closing step is added), and its timing: the step
    duration as a multiple of the robot's (the command divided by it, so that the steps stay
    the same) and the double-support ratio (None: the robot's)."""

    name: str
    command: tuple[float, float, float]
    nb_steps: int
    slowdown: float = 1.0
    double_support_ratio: float | None = None

    def slowed(self, slowdown: float, double_support_ratio: float | None) -> "RobustnessWalk":
        """The same steps, ``slowdown`` times slower, with this double-support ratio."""
        return dataclasses.replace(
            self,
            command=tuple(c / slowdown for c in self.command),  # type: ignore[arg-type]
            slowdown=float(slowdown),
            double_support_ratio=double_support_ratio,
        )

    def walk_arguments(self, robot) -> dict[str, Any]:
        """The command, steps and timing keywords of :func:`run_walk` on ``robot``."""
        arguments: dict[str, Any] = {"command": self.command, "nb_steps": self.nb_steps}
        if self.slowdown != 1.0:
            arguments["step_duration"] = self.slowdown * robot.gait.step_duration
        if self.double_support_ratio is not None:
            arguments["double_support_ratio"] = self.double_support_ratio
        return arguments


@dataclass(frozen=True)
class RobustnessConfig:
    """What :func:`run_robustness` runs.

    Attributes:
        robots: Robot name -> its walks.
        generators: Pattern generators, each with the controller's default closed loop.
        slow_generators: Generator -> (step duration factor, double-support ratio) of the
            generators that take the same steps more slowly (the static gaits).
        cases: The cases, combinations included, in table order.
        control_period: Controller tick [s].
        estimator_walks: Robot name -> the nominal walk whose estimator errors are measured.
        estimator_generator: Generator of those walks.
        estimator_seeds: Seeds of the sensor noise of those walks (one walk per seed; the
            figure is that of the first).
        mode: ``"full"`` or ``"quick"``.
    """

    robots: Mapping[str, tuple[RobustnessWalk, ...]]
    generators: tuple[str, ...]
    cases: tuple[RobustnessCase, ...]
    slow_generators: Mapping[str, tuple[float, float | None]] = field(default_factory=dict)
    control_period: float = 0.01
    estimator_walks: Mapping[str, RobustnessWalk] = field(default_factory=dict)
    estimator_generator: str = "mpc"
    estimator_seeds: tuple[int, ...] = (0,)
    mode: str = "full"


def _walk(name: str, values: Mapping[str, Any], nb_steps: int, where: str) -> RobustnessWalk:
    command = values.get(name)
    if command is None or len(command) != 3:
        raise ConfigurationError(
            f"[{where}] needs {name} = [vx, vy, vyaw] (m/s, m/s, rad/s), got {command!r}."
        )
    vx, vy, vyaw = (float(c) for c in command)
    return RobustnessWalk(name, (vx, vy, vyaw), int(nb_steps))


def _case(values: Mapping[str, Any]) -> RobustnessCase:
    unknown = sorted(set(values) - {"name", "latency_periods", *CASE_KEYS})
    if "name" not in values or unknown:
        raise ConfigurationError(
            f"A [[cases]] entry needs a name and takes {['latency_periods', *CASE_KEYS]}; "
            f"got {dict(values)!r}."
        )
    world = {key: values[key] for key in CASE_KEYS if key in values}
    if "com_offset" in world:
        world["com_offset"] = tuple(float(v) for v in world["com_offset"])
    return RobustnessCase(str(values["name"]), world, values.get("latency_periods"))


def build_cases(singles: Sequence[RobustnessCase], combine_with: str | None) -> tuple:
    """The single cases, then ``combine_with`` combined with every single case that changes
    something else (not the nominal case, nor a case changing the same quantity)."""
    cases = list(singles)
    if combine_with is not None:
        by_name = {case.name: case for case in singles}
        if combine_with not in by_name:
            raise ConfigurationError(
                f"combine_with = {combine_with!r} is not a case; the cases are {list(by_name)}."
            )
        base = by_name[combine_with]
        cases += [
            base.combined(case)
            for case in singles
            if case.changes() and not case.changes() & base.changes()
        ]
    return tuple(cases)


def read_toml_mode(path: str | Path, mode: str) -> tuple[dict, dict]:
    """The TOML table of an experiment and its ``[quick]`` table when ``mode`` is
    ``"quick"`` (empty for ``"full"``).

    Raises:
        ConfigurationError: Another mode.
    """
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # the tomli package is tomllib before Python 3.11
        import tomli as tomllib

    if mode not in ("full", "quick"):
        raise ConfigurationError(f"mode must be 'full' or 'quick', got {mode!r}.")
    with open(path, "rb") as stream:
        data = tomllib.load(stream)
    return data, (data.get("quick", {}) if mode == "quick" else {})


def load_config(path: str | Path = DEFAULT_CONFIG, *, mode: str = "full") -> RobustnessConfig:
    """Read the experiment from a TOML file; ``mode="quick"`` applies its ``[quick]`` table
    (fewer robots, walks, generators, cases and steps).

    Raises:
        ConfigurationError: Another mode, or a malformed table.
    """
    data, quick = read_toml_mode(path, mode)
    nb_steps = int(quick.get("nb_steps", data.get("nb_steps", 20)))
    singles = [_case(values) for values in data.get("cases", [])]
    cases = build_cases(singles, data.get("combine_with"))
    if "cases" in quick:
        names = {case.name: case for case in cases}
        missing = [name for name in quick["cases"] if name not in names]
        if missing:
            raise ConfigurationError(f"[quick] cases {missing} are not cases of {path}.")
        cases = tuple(names[name] for name in quick["cases"])
    walk_names = quick.get("walks", ["forward", "turning"])
    robots = {
        robot: tuple(
            _walk(name, data["walks"][robot], nb_steps, f"walks.{robot}") for name in walk_names
        )
        for robot in quick.get("robots", data["robots"])
    }
    estimator = data.get("estimator", {})
    estimator_walks = {
        robot: _walk("forward", {"forward": command}, estimator.get("nb_steps", 20), "estimator")
        for robot, command in estimator.get("commands", {}).items()
        if not quick or robot in quick.get("estimator_robots", [])
    }
    return RobustnessConfig(
        robots=robots,
        generators=tuple(quick.get("generators", data["generators"])),
        cases=cases,
        control_period=float(data.get("control_period", 0.01)),
        estimator_walks=estimator_walks,
        slow_generators={
            name: (float(timing["step_duration_scale"]), timing.get("double_support_ratio"))
            for name, timing in data.get("slow_generators", {}).items()
        },
        estimator_generator=str(estimator.get("generator", "mpc")),
        estimator_seeds=tuple(int(seed) for seed in estimator.get("seeds", [0])),
        mode=mode,
    )
