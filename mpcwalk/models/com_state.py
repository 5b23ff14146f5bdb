"""The horizontal CoM state every pattern generator starts from and hands out."""

from dataclasses import dataclass, field

import numpy as np

from mpcwalk.exceptions import ConfigurationError


def _vec2(value, name: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float).ravel()
    if arr.shape == (3,):
        arr = arr[:2]
    if arr.shape != (2,) or not np.all(np.isfinite(arr)):
        raise ConfigurationError(f"{name} must be 2 finite numbers (x, y), got {value!r}.")
    return arr


@dataclass(frozen=True)
class ComState:
    """Horizontal CoM state.

    Attributes:
        position: CoM ground projection, shape (2,), in [m].
        velocity: Shape (2,), in [m]/[s].
        acceleration: Shape (2,), in [m]/[s]^2, or None when unknown (a
            generator then keeps its own estimate).
    """

    position: np.ndarray
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(2))
    acceleration: np.ndarray | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", _vec2(self.position, "ComState.position"))
        object.__setattr__(self, "velocity", _vec2(self.velocity, "ComState.velocity"))
        if self.acceleration is not None:
            object.__setattr__(
                self, "acceleration", _vec2(self.acceleration, "ComState.acceleration")
            )

    @classmethod
    def trusted(
        cls,
        position: np.ndarray,
        velocity: np.ndarray,
        acceleration: np.ndarray | None = None,
    ) -> "ComState":
        """A state built without the checks of the constructor, for values valid by
        construction (float arrays of shape (2,) computed on the hot path: the
        controller's measured and observed states, every tick)."""
        state = object.__new__(cls)
        object.__setattr__(state, "position", position)
        object.__setattr__(state, "velocity", velocity)
        object.__setattr__(state, "acceleration", acceleration)
        return state

    def as_cart_table(self, default_acceleration=None) -> np.ndarray:
        """State matrix of shape (3, 2): rows position [m], velocity [m/s], acceleration
        [m/s^2] (``default_acceleration``, else zero, when the state has none)."""
        acc = self.acceleration
        if acc is None:
            acc = np.zeros(2) if default_acceleration is None else default_acceleration
        return np.vstack([self.position, self.velocity, acc])
