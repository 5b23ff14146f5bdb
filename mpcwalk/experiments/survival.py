"""When a walk survives, and the largest push (or speed) it survives.

:func:`survived` is the one criterion of every experiment: a walk survives when it ran to the
end of its schedule standing, neither fallen nor stopped by the controller (faults beyond its
bound), nor interrupted, nor refused with an error. :func:`find_largest_survived` brackets
and bisects the threshold of a monotone survival oracle (the largest impulse of a push, the
fastest command).
"""

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from mpcwalk.exceptions import ConfigurationError

#: The outcome of a walk that survived (``metrics.json``'s ``outcome``).
SURVIVED = "walked"


def survived(walk: Any) -> bool:
    """Whether a walk survived: its outcome is ``"walked"`` (neither ``"fell"`` nor
    ``"stopped"`` by the controller, nor ``"interrupted"``) and it ran without an error.

    Args:
        walk: A :class:`~mpcwalk.walking.result.WalkResult`, its
            :class:`~mpcwalk.walking.metrics.WalkMetrics`, or a row of a results table
            (a mapping with ``outcome`` and, from the sweep engine, ``error``).

    Raises:
        ConfigurationError: A row without an ``outcome`` (a table written before the
            column existed: run its experiment again).
    """
    metrics = getattr(walk, "metrics", walk)
    if isinstance(metrics, Mapping):
        if metrics.get("error"):
            return False
        if "outcome" not in metrics:
            raise ConfigurationError(
                "Expected a row with the walk's 'outcome' (walked, fell, stopped, "
                f"interrupted), got the columns {sorted(metrics)}; run the experiment again "
                "to write it."
            )
        return metrics["outcome"] == SURVIVED
    return metrics.outcome == SURVIVED


@dataclass(frozen=True)
class BisectionResult:
    """Outcome of :func:`find_largest_survived`.

    Attributes:
        largest_survived: Largest value that survived (0 if none was tried and survived).
        smallest_fallen: Smallest value that fell, None if none fell (censored at the limit).
        trials: ``(value, survived)`` in the order they were tried.
    """

    largest_survived: float
    smallest_fallen: float | None
    trials: tuple[tuple[float, bool], ...]

    @property
    def censored(self) -> bool:
        """True when even the upper limit survived (the threshold is above it)."""
        return self.smallest_fallen is None


def find_largest_survived(
    survives: Callable[[float], bool],
    *,
    initial: float,
    upper_limit: float,
    tolerance: float,
    relative_tolerance: float = 0.0,
    lower_limit: float | None = None,
) -> BisectionResult:
    """Threshold of a survival oracle that is monotone (survives below, falls above).

    Brackets from ``initial`` (doubling while it survives, halving while it falls), then
    bisects until the bracket is narrower than ``max(tolerance, relative_tolerance * hi)``.
    Value 0 is assumed to survive and is never tried.

    Args:
        survives: Oracle, e.g. a walk with a push of that impulse.
        initial: First value tried (> 0).
        upper_limit: Largest value tried; if it survives, the result is censored there.
        tolerance: Absolute bracket width at which to stop.
        relative_tolerance: Relative bracket width at which to stop.
        lower_limit: Smallest value tried when halving (default: ``tolerance``); below it
            the result is 0.

    Returns:
        The bracket and every trial.
    """
    if not (0.0 < initial <= upper_limit) or tolerance <= 0.0:
        raise ConfigurationError(
            f"find_largest_survived needs 0 < initial <= upper_limit and tolerance > 0, got "
            f"initial={initial!r}, upper_limit={upper_limit!r}, tolerance={tolerance!r}."
        )
    floor = tolerance if lower_limit is None else lower_limit
    trials: list[tuple[float, bool]] = []

    def trial(value: float) -> bool:
        ok = bool(survives(value))
        trials.append((float(value), ok))
        return ok

    value, lo, hi = initial, 0.0, None
    if trial(value):
        lo = value
        while lo < upper_limit:
            value = round(min(2.0 * lo, upper_limit), 9)
            if value <= lo:  # the limit, rounded, was tried: nothing is left above
                break
            if not trial(value):
                hi = value
                break
            lo = value
        if hi is None:
            return BisectionResult(lo, None, tuple(trials))
    else:
        hi = value
        while hi / 2.0 >= floor:
            value = round(hi / 2.0, 9)
            if trial(value):
                lo = value
                break
            hi = value
    while hi - lo > max(tolerance, relative_tolerance * hi):
        value = round(0.5 * (lo + hi), 9)
        if trial(value):
            lo = value
        else:
            hi = value
    return BisectionResult(lo, hi, tuple(trials))


__all__ = ["SURVIVED", "BisectionResult", "find_largest_survived", "survived"]
