"""Exceptions raised by mpcwalk.

Every error the library raises on purpose derives from :class:`MpcwalkError`.
Messages say what was expected, what came, and how to fix it.
"""

from collections.abc import Mapping, Sequence
from typing import Any


class MpcwalkError(Exception):
    """Root of all mpcwalk errors."""


class ConfigurationError(MpcwalkError, ValueError):
    """A parameter has a value outside its valid range (e.g. a negative step duration)."""


class InfeasibleCommand(MpcwalkError, ValueError):
    """A velocity command lies beyond what the robot's legs can achieve."""

    def __init__(self, name: str, value: float, limit: float, unit: str = "") -> None:
        self.name = name
        self.value = value
        self.limit = limit
        unit_str = f" {unit}" if unit else ""
        super().__init__(
            f"Velocity command {name}={value:g}{unit_str} exceeds its limit "
            f"|{name}| <= {limit:g}{unit_str}; lower the command or raise the limit "
            "(longer legs, longer steps or shorter step duration)."
        )


class InfeasibleStep(MpcwalkError, ValueError):
    """A footstep cannot be reached from the current support foot."""


class FootstepFileError(MpcwalkError, ValueError):
    """A footstep path file (.mdat) is malformed.

    Attributes:
        path: File name (or ``"<string>"``).
        line: One-based line number, or None for whole-file problems.
        field: Name of the offending field, or None.
    """

    def __init__(
        self,
        message: str,
        *,
        path: str = "<string>",
        line: int | None = None,
        field: str | None = None,
    ) -> None:
        self.path = path
        self.line = line
        self.field = field
        where = path if line is None else f"{path}:{line}"
        if field is not None:
            where += f" (field '{field}')"
        super().__init__(f"{where}: {message}")


class SolverNotFound(MpcwalkError, ValueError):
    """The requested QP solver is unknown or not installed.

    Attributes:
        solver: The name asked for.
        available: Solvers available on this installation.
        installable: Known solvers that are not installed -> how to install them.
        install: How to install ``solver`` when it is known but not installed, else "".
    """

    def __init__(
        self,
        solver: str,
        available: Sequence[str],
        installable: Mapping[str, str] | None = None,
        *,
        install: str = "",
    ) -> None:
        self.solver = solver
        self.available = list(available)
        self.installable = dict(installable or {})
        self.install = install
        names = ", ".join(self.available) or "(none)"
        if install:
            message = (
                f"Solver '{solver}' is not installed; install it with `{install}`, or choose "
                f"one of the available solvers: {names}."
            )
        else:
            message = f"Unknown solver '{solver}'; available: {names}"
            if self.installable:
                groups: dict[str, list[str]] = {}  # install command, <name> for the name
                for name, how in self.installable.items():
                    groups.setdefault(how.replace(name, "<name>"), []).append(name)
                hints = ", ".join(f"{', '.join(n)} (`{how}`)" for how, n in groups.items())
                message += f"; installable: {hints}"
            message += "."
        super().__init__(message)


class GeneratorNotFound(MpcwalkError, ValueError):
    """The requested pattern generator name is unknown."""

    def __init__(self, name: str, available: Sequence[str]) -> None:
        self.name = name
        self.available = list(available)
        super().__init__(
            f"Unknown pattern generator '{name}'; choose one of {', '.join(self.available)}."
        )


class NoSolutionFound(MpcwalkError):
    """A QP solver returned no solution.

    Attributes:
        solver: Name of the solver.
        status: The solver's own status, as a string.
        problem: The problem that failed, for inspection.
    """

    def __init__(self, solver: str, status: str = "", problem: Any = None) -> None:
        self.solver = solver
        self.status = status
        self.problem = problem
        super().__init__(
            f"QP solver '{solver}' found no solution (status: {status or 'unknown'}). "
            "The support polygon constraints may be infeasible from the current state; "
            "check the footsteps and the measured CoM state."
        )


class ControllerStopped(MpcwalkError):
    """The controller stopped the walk: too many fallback ticks in a row (faults beyond its
    bound, :mod:`mpcwalk.control.faults`). A controlled stop, not bad input: the walk's log
    and metrics are written (outcome ``stopped``, exit code 3).

    Attributes:
        reason: Why, in words.
    """

    def __init__(self, reason: str) -> None:
        self.reason = reason
        super().__init__(f"The controller stopped the walk: {reason}.")


class NotReset(MpcwalkError, RuntimeError):
    """A generator was stepped before :meth:`reset` gave it a schedule."""


class RobotNotFound(MpcwalkError, ValueError):
    """The requested robot has no preset, or its description is not installed."""

    def __init__(self, name: str, available: Sequence[str], reason: str = "") -> None:
        self.name = name
        self.available = list(available)
        why = f" ({reason})" if reason else ""
        super().__init__(
            f"Unknown robot '{name}'{why}; choose one of {', '.join(self.available) or '(none)'}."
        )


class FrameNotFound(MpcwalkError, LookupError):
    """A frame (Pinocchio frame, MuJoCo site or URDF link) does not exist in a robot."""

    def __init__(self, frame: str, available: Sequence[str], robot: str = "") -> None:
        self.frame = frame
        self.available = sorted(available)
        where = f" in robot '{robot}'" if robot else ""
        super().__init__(
            f"Frame '{frame}' not found{where}; the frames that exist are: "
            f"{', '.join(self.available)}."
        )


class PackageDataNotFound(MpcwalkError, FileNotFoundError):
    """The data shipped with mpcwalk (robot descriptions, presets, experiment configs) is
    not installed as a folder beside the package."""

    def __init__(self, package: str, reason: str) -> None:
        self.package = package
        super().__init__(
            f"mpcwalk's data package '{package}' was expected installed with mpcwalk, but "
            f"{reason}; install mpcwalk with pip (`pip install -e .` in a checkout of the "
            "repository, or from a wheel) instead of putting its source on sys.path."
        )


class SensorModelError(ConfigurationError):
    """A sensor model has a noise, bias, resolution or latency outside its range.

    Attributes:
        field: Name of the offending field.
        value: The value it was given.
    """

    def __init__(self, field: str, value: Any, expected: str) -> None:
        self.field = field
        self.value = value
        super().__init__(
            f"SensorModel.{field} must be {expected}, got {value!r}; fix it, or start from "
            "SensorModel.for_robot(robot) and use scaled(x) or with_latency(n)."
        )


class PerturbationError(ConfigurationError):
    """A perturbation of the simulated robot (mass, CoM offset, friction, servo strength)
    lies outside its range.

    Attributes:
        field: Name of the offending field.
        value: The value it was given.
    """

    def __init__(self, field: str, value: Any, expected: str) -> None:
        self.field = field
        self.value = value
        super().__init__(
            f"Perturbation.{field} must be {expected}, got {value!r}; choose a value in that "
            "range (Perturbation() is the robot as modelled)."
        )
