"""Tolerance levels of the solver benchmark (the conventions of qpbenchmark).

A solve is a *success* at a level when the back-end says it found a solution
and the primal residual, the dual residual and the duality gap of that
solution, recomputed by the benchmark on the same problem, are all below the
level's tolerance. The levels are those of ``qpsolvers/qpbenchmark``:
``default`` (solver defaults, validated at 1), ``low`` (1e-3), ``mid``
(1e-6) and ``high`` (1e-9), each asking the solvers for that absolute
accuracy and no relative one. One addition: a solve that takes longer than
the level's time limit is a timeout, never a success, even when the back-end
has no time limit of its own and came back with a solution.
"""

import math
from dataclasses import dataclass

from mpcwalk.exceptions import ConfigurationError

#: Names of the levels, in increasing accuracy.
LEVEL_NAMES = ("default", "low", "mid", "high")
#: Name of each level in qpbenchmark's test sets.
QPBENCHMARK_NAMES = {
    "default": "default",
    "low": "low_accuracy",
    "mid": "mid_accuracy",
    "high": "high_accuracy",
}
_EPS = {"default": None, "low": 1e-3, "mid": 1e-6, "high": 1e-9}


@dataclass(frozen=True)
class ToleranceLevel:
    """Validation tolerances of one accuracy level.

    Attributes:
        name: ``"default"``, ``"low"``, ``"mid"`` or ``"high"``.
        primal: Largest primal residual (constraint violation) of a success,
            in the units of the constraints ([m] for the support rows).
        dual: Largest dual residual ``||P x + q + A^T y||_inf``.
        gap: Largest duality gap.
        runtime: Time limit of one solve, in [s].
        eps: Absolute tolerance asked of the solvers, or None for their own
            defaults.
    """

    name: str
    primal: float
    dual: float
    gap: float
    runtime: float  # [s]
    eps: float | None

    @property
    def qpbenchmark_name(self) -> str:
        """Name of the same settings in qpbenchmark (e.g. ``"mid_accuracy"``)."""
        return QPBENCHMARK_NAMES[self.name]

    def is_timeout(self, runtime: float) -> bool:
        """Whether a solve of ``runtime`` [s] exceeded the time limit."""
        return not runtime <= self.runtime

    def is_success(
        self,
        found: bool,
        primal: float | None,
        dual: float | None,
        gap: float | None,
        runtime: float,
    ) -> bool:
        """qpbenchmark's success test (missing residuals fail it), plus the time limit."""
        if not found or primal is None or dual is None or gap is None:
            return False
        if not all(math.isfinite(v) for v in (primal, dual, gap)):
            return False
        return (
            primal < self.primal
            and dual < self.dual
            and gap < self.gap
            and not self.is_timeout(runtime)
        )


def tolerance_levels(time_limit: float = 1.0) -> dict[str, ToleranceLevel]:
    """The four levels, keyed by name, with the same time limit.

    Args:
        time_limit: Time limit of one solve, in [s]. qpbenchmark uses 10 s;
            1 s is already a hundred control periods of a walking MPC.

    Raises:
        ConfigurationError: Non-positive time limit.
    """
    if not (
        isinstance(time_limit, (int, float)) and math.isfinite(time_limit) and time_limit > 0.0
    ):
        raise ConfigurationError(
            f"The time limit of one solve must be a positive number of seconds, got "
            f"{time_limit!r}; 1.0 is the benchmark's default."
        )
    levels = {}
    for name in LEVEL_NAMES:
        eps = _EPS[name]
        tol = 1.0 if eps is None else eps
        levels[name] = ToleranceLevel(name, tol, tol, tol, float(time_limit), eps)
    return levels


def select_levels(names, time_limit: float = 1.0) -> dict[str, ToleranceLevel]:
    """Levels called ``names`` (an iterable of level names), in benchmark order.

    Raises:
        ConfigurationError: Unknown level name.
    """
    levels = tolerance_levels(time_limit)
    names = list(names)
    unknown = [n for n in names if n not in levels]
    if unknown:
        raise ConfigurationError(
            f"Unknown tolerance level(s) {', '.join(unknown)}; the levels are "
            f"{', '.join(LEVEL_NAMES)}."
        )
    return {n: levels[n] for n in LEVEL_NAMES if n in names}
