"""Exceptions raised by mpcwalk.

Every error the library raises on purpose derives from :class:`MpcwalkError`.
Messages say what was expected, what came, and how to fix it.
"""

from collections.abc import Sequence
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
    """The requested QP solver is unknown or not installed."""

    def __init__(self, solver: str, available: Sequence[str]) -> None:
        self.solver = solver
        self.available = list(available)
        super().__init__(
            f"QP solver '{solver}' is not available; the available solvers are "
            f"{', '.join(self.available) or '(none)'}. Install it with "
            f"`pip install qpsolvers[{solver}]` or pick one from that list."
        )


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


class NotReset(MpcwalkError, RuntimeError):
    """A generator was stepped before :meth:`reset` gave it a schedule."""
