"""N-step capturability of the linear inverted pendulum on rectangular feet (Koolen 2012).

The divergent component of motion (DCM, or capture point) ``xi = c + c_dot / omega`` of the
LIPM obeys ``xi_dot = omega (xi - p)`` with the ZMP ``p`` in the support. A state is
*N-step capturable* when N steps or fewer can bring the robot to rest. Koolen et al. 2012
("Capturability-based analysis and control of legged locomotion, Part 1", IJRR) give the
capture regions of a point-foot or disc-foot LIPM; this module gives them for the flat
rectangular soles and the rectangular landing regions of :mod:`mpcwalk.footsteps`, in the
frame of the stance foot, for feet that do not turn (straight walking):

- 0 steps: the DCM in the sole, ``C_0 = S``;
- with a step of landing region ``R`` (relative to the stance foot) that lands ``t`` after
  now, the DCM at landing is ``e^{omega t} xi - (e^{omega t} - 1) p`` for the average ZMP
  ``p`` in ``S`` (any ZMP history in the convex sole gives such an average), and the robot
  must then be ``N - 1``-step capturable from the new foot:
  ``C_N = (1 - e^{-omega t}) S  +  e^{-omega t} (R + C'_{N-1})`` (Minkowski sums), where
  ``C'_{N-1}`` is the region of the remaining steps relative to the new foot (the other
  leg's landing region next).

Rectangles add and scale as rectangles, so every region is an axis-aligned rectangle of the
stance foot's frame. An impulse ``J`` [N s] on the mass ``m`` moves the DCM by
``J / (m omega)``: the largest impulse recovered in a direction is ``m omega`` times the
distance from the DCM before the push to the region's border along that direction.

The closed form for a push at rest over the foot centre (:func:`capture_impulse_bound`): with
the ZMP at most ``d`` from the foot centre in the push's direction, the robot stops without
stepping when ``J <= m omega d``; with one step that lands ``t`` after the push, at most
``L`` further in that direction, the DCM has grown by ``exp(omega t)`` and the bound becomes
``m omega (d + L exp(-omega t))``.

Cross-over steps are not allowed: the landing region of a left swing foot lies left of the
stance foot (``y >= y_min > 0``), so a push towards the stance leg is captured by the next
step of the *other* leg, which is what the two-step region shows.
"""

import math
from dataclasses import dataclass

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Side
from mpcwalk.footsteps.reachability import ReachabilityRectangle

GRAVITY = 9.81  # [m/s^2]


@dataclass(frozen=True)
class Box:
    """Axis-aligned rectangle ``[x_low, x_high] x [y_low, y_high]`` [m]."""

    x_low: float
    x_high: float
    y_low: float
    y_high: float

    def __add__(self, other: "Box") -> "Box":
        """Minkowski sum."""
        return Box(
            self.x_low + other.x_low,
            self.x_high + other.x_high,
            self.y_low + other.y_low,
            self.y_high + other.y_high,
        )

    def scaled(self, factor: float) -> "Box":
        """The rectangle scaled about the origin by ``factor >= 0``."""
        return Box(
            factor * self.x_low, factor * self.x_high, factor * self.y_low, factor * self.y_high
        )

    def grown(self, dx: float, dy: float) -> "Box":
        """The rectangle grown by ``dx`` [m] on both sides along x and ``dy`` along y."""
        return Box(self.x_low - dx, self.x_high + dx, self.y_low - dy, self.y_high + dy)

    def contains(self, point) -> bool:
        """Whether ``point`` (x, y) lies in the rectangle (borders included)."""
        x, y = float(point[0]), float(point[1])
        return self.x_low <= x <= self.x_high and self.y_low <= y <= self.y_high

    def ray_distance(self, point, direction: float) -> float:
        """Distance [m] from ``point`` (inside) to the border along ``direction`` [rad]
        (0: +x, pi/2: +y); 0 when ``point`` is outside."""
        if not self.contains(point):
            return 0.0
        x, y = float(point[0]), float(point[1])
        c, s = math.cos(direction), math.sin(direction)
        distances = []
        if c > 1e-12:
            distances.append((self.x_high - x) / c)
        elif c < -1e-12:
            distances.append((self.x_low - x) / c)
        if s > 1e-12:
            distances.append((self.y_high - y) / s)
        elif s < -1e-12:
            distances.append((self.y_low - y) / s)
        return float(min(distances))


def sole_box(length: float, width: float) -> Box:
    """The sole ``length`` x ``width`` [m] centred on the foot."""
    if not (length > 0.0 and width > 0.0):
        raise ConfigurationError(
            f"The sole needs a positive length and width, got {length!r} x {width!r} m."
        )
    return Box(-0.5 * length, 0.5 * length, -0.5 * width, 0.5 * width)


def landing_box(reach: ReachabilityRectangle, swing: Side) -> Box:
    """Where the ``swing`` foot may land relative to the stance foot (no turning)."""
    if swing == Side.LEFT:
        return Box(reach.x_min, reach.x_max, reach.y_min, reach.y_max)
    return Box(reach.x_min, reach.x_max, -reach.y_max, -reach.y_min)


def capture_region(
    nb_steps: int,
    *,
    omega: float,
    sole: Box,
    reach: ReachabilityRectangle,
    first_swing: Side,
    first_step_time: float,
    step_time: float,
) -> Box:
    """The N-step capture region of the DCM in the stance foot's frame [m].

    Args:
        nb_steps: Steps allowed, N >= 0.
        omega: LIPM natural frequency ``sqrt(g / z_c)`` [1/s].
        sole: The sole (:func:`sole_box`).
        reach: Landing region of each step relative to the foot it leaves.
        first_swing: The leg that steps first (the other one stands); the legs alternate.
        first_step_time: Time from now to the first landing [s] (the remaining swing of a
            fixed schedule, or the earliest landing a timing adaptation allows).
        step_time: Time between two later landings [s].
    """
    if isinstance(nb_steps, bool) or int(nb_steps) != nb_steps or nb_steps < 0:
        raise ConfigurationError(f"nb_steps must be an integer >= 0, got {nb_steps!r}.")
    for name, value in (
        ("omega", omega),
        ("first_step_time", first_step_time),
        ("step_time", step_time),
    ):
        if not (math.isfinite(value) and value >= 0.0):
            raise ConfigurationError(f"{name} must be a non-negative number, got {value!r}.")
    region = sole
    swings = [first_swing if i % 2 == 0 else first_swing.other for i in range(int(nb_steps))]
    for index in reversed(range(int(nb_steps))):  # the last step first
        t = first_step_time if index == 0 else step_time
        decay = math.exp(-omega * t)
        region = sole.scaled(1.0 - decay) + (landing_box(reach, swings[index]) + region).scaled(
            decay
        )
    return region


def capture_regions(max_steps: int, **options) -> list[Box]:
    """The capture regions with exactly 0, 1, ..., ``max_steps`` steps
    (:func:`capture_region`'s keyword ``options``): a state is capturable in at most N steps
    when it lies in one of the first N + 1 (a step is not always a help: a left foot that
    must land left of the stance foot cannot help against a push to the right)."""
    return [capture_region(n, **options) for n in range(int(max_steps) + 1)]


def flywheel_regions(regions: list[Box], offset: tuple[float, float]) -> list[Box]:
    """The capture regions of the LIPM with a flywheel (Pratt et al. 2006), used once from
    now: each of ``regions`` (the LIPM's, :func:`capture_regions`) grown by the farthest the
    flywheel moves the capture point along x and y, ``offset`` [m]
    (:func:`mpcwalk.models.flywheel.cmp_offset_bound`). The DCM's capture condition is
    linear in the CMP history, so a flywheel torque starting now shifts it by the same amount
    whatever the steps that follow; zero offsets give the LIPM's regions."""
    dx, dy = (float(v) for v in offset)
    if not (math.isfinite(dx) and math.isfinite(dy) and dx >= 0.0 and dy >= 0.0):
        raise ConfigurationError(
            f"The flywheel's offset must be two non-negative distances [m], got {offset!r}."
        )
    return [box.grown(dx, dy) for box in regions]


def largest_impulse(
    regions: Box | list[Box], dcm, direction: float, *, mass: float, omega: float
) -> float:
    """The largest impulse [N s] along ``direction`` [rad] (stance foot's frame) after
    which the DCM ``dcm`` (x, y) [m] is still in one of ``regions``: ``m omega`` times the
    largest distance to a region's border along ``direction`` (0 when ``dcm`` is in none)."""
    if not (mass > 0.0 and omega > 0.0):
        raise ConfigurationError(
            f"largest_impulse needs a positive mass and omega, got {mass!r} kg, {omega!r} 1/s."
        )
    boxes = [regions] if isinstance(regions, Box) else list(regions)
    return mass * omega * max(box.ray_distance(dcm, direction) for box in boxes)


def capture_impulse_bound(
    direction: float,
    *,
    mass: float,
    com_height: float,
    half_length: float = 0.05,
    half_width: float = 0.03,
    step_reach: tuple[float, float, float] | None = None,
    step_time: float = 0.25,
    gravity: float = GRAVITY,
) -> float:
    """Largest impulse [N s] the LIPM at rest over the foot centre absorbs, without a step or
    with one step.

    Args:
        direction: Push direction [rad] in the foot frame (0: forward).
        mass: Robot mass [kg].
        com_height: CoM height z_c [m].
        half_length: Half sole length [m] (ZMP reach forward and backward).
        half_width: Half sole width [m] (ZMP reach sideways).
        step_reach: ``(forward, backward, lateral)`` reach of one step [m]; None: no step.
        step_time: Time from the push to the step's landing [s].
        gravity: [m/s^2].

    Returns:
        ``m omega (d + L exp(-omega t))`` with ``d`` the sole's extent and ``L`` the step's
        reach in that direction (``L = 0`` without a step).

    Raises:
        ConfigurationError: A mass or CoM height that is not positive.
    """
    if mass <= 0.0 or com_height <= 0.0:
        raise ConfigurationError(
            f"capture_impulse_bound needs mass > 0 kg and com_height > 0 m, got {mass!r} kg "
            f"and {com_height!r} m."
        )
    omega = math.sqrt(gravity / com_height)
    origin = (0.0, 0.0)
    d = Box(-half_length, half_length, -half_width, half_width).ray_distance(origin, direction)
    reach = 0.0
    if step_reach is not None:
        forward, backward, lateral = step_reach
        reach = Box(-backward, forward, -lateral, lateral).ray_distance(origin, direction)
    return mass * omega * (d + reach * math.exp(-omega * step_time))
