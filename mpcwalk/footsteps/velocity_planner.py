"""Velocity-driven footstep planner (paper M, sec. 3.1, eq. 5).

The torso follows the omnidirectional (unicycle-like) model of paper M,

    x_dot = vx cos(psi) - vy sin(psi),  y_dot = vx sin(psi) + vy cos(psi),  psi_dot = vyaw,

sampled once per step (sample time ``T``). Step ``k`` puts the swing foot at
the torso pose at the end of the step, offset sideways by the nominal half
stance width; heuristics then keep each landing inside the leg's reach and
outside the self-collision zone of the support foot (a rectangle of the
support-foot frame, see :mod:`.reachability`). Landings aim at the model's
torso poses, which are absolute, so a clamped landing delays one step but
never makes the feet drift from the commanded path.
"""

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError, InfeasibleCommand
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, StepTiming, wrap_angle
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.footsteps.reachability import opening_side
from mpcwalk.footsteps.terrain_steps import place_on_terrain
from mpcwalk.terrain import Terrain, TerrainReach


@dataclass(frozen=True)
class VelocityCommand:
    """Walking velocity in the robot's local frame.

    Attributes:
        vx: Forward velocity, in [m/s].
        vy: Lateral velocity (positive to the left), in [m/s].
        vyaw: Yaw rate (positive counter-clockwise), in [rad/s].
    """

    vx: float = 0.0  # [m/s]
    vy: float = 0.0  # [m/s]
    vyaw: float = 0.0  # [rad/s]

    def __post_init__(self) -> None:
        for name in ("vx", "vy", "vyaw"):
            value = getattr(self, name)
            if isinstance(value, (bool, np.bool_, str, bytes)):
                raise ConfigurationError(
                    f"Velocity command {name} must be a number [m/s or rad/s], got {value!r}; "
                    "e.g. VelocityCommand(0.1, 0.0, 0.0)."
                )
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise ConfigurationError(
                    f"Velocity command {name} must be a number, got {value!r}."
                ) from None
            if not np.isfinite(value):
                raise ConfigurationError(
                    f"Velocity command {name} must be finite, got {value!r}; send 0.0 to stand still."
                )
            object.__setattr__(self, name, value)


#: Forward speed [m/s] of a walk given no command (paper M's experiments).
DEFAULT_FORWARD_SPEED = 0.1


def integrate_torso(
    command: VelocityCommand, start, nb_samples: int, sampling_period: float
) -> np.ndarray:
    """Torso poses of eq. 5 with the command held over each sample.

    The model is integrated exactly over each sample (constant body-frame
    velocity: an arc of a circle), which for a constant command is also
    exact over the whole walk.

    Args:
        command: Velocity command, robot local frame.
        start: Initial torso pose ``(x [m], y [m], yaw [rad])``.
        nb_samples: Number of samples (steps).
        sampling_period: Sample time ``T``, in [s].

    Returns:
        Torso poses ``(x, y, yaw)``, shape (nb_samples + 1, 3).
    """
    dyaw = command.vyaw * sampling_period
    if abs(dyaw) > 1e-9:
        sin_c, cos_c = np.sin(dyaw) / dyaw, (1.0 - np.cos(dyaw)) / dyaw
    else:  # series of sin(a)/a and (1 - cos(a))/a
        sin_c, cos_c = 1.0 - dyaw**2 / 6.0, dyaw / 2.0
    local = sampling_period * np.array(
        [command.vx * sin_c - command.vy * cos_c, command.vx * cos_c + command.vy * sin_c]
    )
    poses = np.empty((nb_samples + 1, 3))
    poses[0] = np.asarray(start, dtype=float)
    for k in range(nb_samples):
        c, s = np.cos(poses[k, 2]), np.sin(poses[k, 2])
        poses[k + 1, :2] = poses[k, :2] + np.array([[c, -s], [s, c]]) @ local
        poses[k + 1, 2] = poses[k, 2] + dyaw
    return poses


def as_velocity_command(command) -> "VelocityCommand":
    """A :class:`VelocityCommand` from itself or any three numbers (vx, vy, vyaw)."""
    if isinstance(command, VelocityCommand):
        return command
    try:
        values = np.asarray(command, dtype=float).ravel()
    except (TypeError, ValueError):
        values = np.empty(0)
    if values.shape != (3,):
        raise ConfigurationError(f"A velocity command is (vx, vy, vyaw), got {command!r}.")
    return VelocityCommand(*values)


class VelocityPlanner:
    """Footsteps that follow a velocity command (paper M, sec. 3.1).

    Args:
        limits: Per-step reach of the legs.
        timing: Step duration ``T`` (the sample time of eq. 5) and phases.
    """

    def __init__(self, limits: LegLimits = LegLimits(), timing: StepTiming = StepTiming()) -> None:
        self.limits = limits
        self.timing = timing
        self.rectangle = limits.rectangle()

    def default_command(self) -> VelocityCommand:
        """The command of a walk given none: forward at paper M's 0.1 m/s, or at the legs'
        reach per step when the steps are slower (paper A's 12 s steps)."""
        return VelocityCommand(
            min(DEFAULT_FORWARD_SPEED, self.limits.max_step_forward / self.timing.step_duration),
            0.0,
            0.0,
        )

    def check_command(self, command: VelocityCommand) -> None:
        """Raise InfeasibleCommand when the command exceeds the legs' reach.

        In two consecutive steps each foot moves once and the torso twice,
        so a foot moves ``2 v T`` per cycle: the sum of its landing offset
        and of the other foot's. Forward, both offsets are bounded by
        ``max_step_forward``: ``vx T <= max_step_forward`` (backward alike).
        Sideways (and in yaw) one landing opens the stance and the next
        closes it: ``2 |vy| T <= (2 h + max_step_lateral) - 2 y_sep`` with
        ``h`` the half stance width, and ``2 |vyaw| T <= max_step_yaw +
        max_step_yaw_inward``. Within these limits a clamped landing lags by
        a constant amount that the next landing makes up; beyond them the
        lag would grow every cycle, so the command is refused.
        """
        T, lim = self.timing.step_duration, self.limits
        if command.vx > lim.max_step_forward / T or -command.vx > lim.max_step_backward / T:
            bound = lim.max_step_forward if command.vx > 0.0 else lim.max_step_backward
            raise InfeasibleCommand("vx", command.vx, bound / T, "m/s")
        lateral_bound = (lim.half_stance_width - lim.y_sep + 0.5 * lim.max_step_lateral) / T
        if abs(command.vy) > lateral_bound:
            raise InfeasibleCommand("vy", command.vy, lateral_bound, "m/s")
        yaw_bound = 0.5 * (lim.max_step_yaw + lim.max_step_yaw_inward) / T
        if abs(command.vyaw) > yaw_bound:
            raise InfeasibleCommand("vyaw", command.vyaw, yaw_bound, "rad/s")

    def torso_poses(
        self, command: VelocityCommand, nb_steps: int, start=(0.0, 0.0, 0.0)
    ) -> np.ndarray:
        """Torso poses of the model at the step boundaries, shape (nb_steps + 1, 3)."""
        return integrate_torso(command, start, nb_steps, self.timing.step_duration)

    def plan(
        self,
        command: VelocityCommand | Sequence[float],
        nb_steps: int,
        *,
        initial_left: Footstep | None = None,
        initial_right: Footstep | None = None,
        first_swing: Side | str | None = None,
        stop: bool = True,
        terrain: Terrain | None = None,
        reach: TerrainReach | None = None,
    ) -> FootstepPlan:
        """Plan ``nb_steps`` steps at a constant command.

        Args:
            command: Velocity command (or ``(vx, vy, vyaw)``).
            nb_steps: Steps that follow the command.
            initial_left: Left foot at the start (default: side by side at
                the origin, ``half_stance_width`` to the left).
            initial_right: Right foot at the start.
            first_swing: First foot to move. Default: the foot on the side
                of the lateral velocity, else of the turn, else the right
                foot, so that the first step opens the stance outward.
            stop: Append one step that puts the swing foot side by side
                with the last landing (the plan then has ``nb_steps + 1``
                steps), so the walk ends in double support centred on the
                last torso pose of the model (up to the lag of a clamped
                last landing).
            terrain: The ground to walk (None: the flat floor, the plan as ever): every
                landing is moved along its heading onto a top that holds the sole
                (:mod:`~mpcwalk.footsteps.terrain_steps`), the closing step beside the
                last landing on its top.
            reach: What the legs and soles cross on ``terrain`` (needed with it).

        Returns:
            The footstep plan with this planner's timing.

        Raises:
            InfeasibleCommand: The command exceeds the legs' reach.
            InfeasibleStep: A landing finds no place on ``terrain`` within ``reach``.
            ConfigurationError: NaN command, negative ``nb_steps``, bad side, a terrain
                without its reach.
        """
        command = as_velocity_command(command)
        if (
            isinstance(nb_steps, bool)
            or not isinstance(nb_steps, (int, np.integer))
            or nb_steps < 0
        ):
            raise ConfigurationError(f"nb_steps must be a non-negative integer, got {nb_steps!r}.")
        self.check_command(command)
        h = self.limits.half_stance_width
        left = (
            initial_left
            if initial_left is not None
            else Footstep(Side.LEFT, np.array([0.0, h, 0.0]))
        )
        right = (
            initial_right
            if initial_right is not None
            else Footstep(Side.RIGHT, np.array([0.0, -h, 0.0]))
        )
        if left.side is not Side.LEFT or right.side is not Side.RIGHT:
            raise ConfigurationError(
                "initial_left must be a left Footstep and initial_right a right one."
            )
        start_yaw = right.yaw + 0.5 * float(wrap_angle(left.yaw - right.yaw))
        torso = self.torso_poses(command, nb_steps, [*(0.5 * (left.xy + right.xy)), start_yaw])
        side = (
            Side.parse(first_swing)
            if first_swing is not None
            else opening_side(command.vy, command.vyaw)
        )
        feet = {Side.LEFT: left, Side.RIGHT: right}
        height = 0.5 * (left.position[2] + right.position[2])
        steps: list[Footstep] = []
        for k in range(nb_steps):
            x, y, yaw = torso[k + 1]
            offset = side.sign * h * np.array([-np.sin(yaw), np.cos(yaw)])
            position = np.array([x + offset[0], y + offset[1], height])
            target = Footstep(side, position, float(wrap_angle(yaw)))
            feet[side] = self.rectangle.clamp_footstep(feet[side.other], target).footstep
            steps.append(feet[side])
            side = side.other
        if stop and nb_steps > 0:
            support = feet[side.other]
            xy = support.to_world(np.array([0.0, side.sign * 2.0 * h]))
            landing = np.array([xy[0], xy[1], support.position[2]])
            steps.append(Footstep(side, landing, support.yaw))
        plan = FootstepPlan(left, right, tuple(steps), self.timing)
        if terrain is None:
            return plan
        if reach is None:
            raise ConfigurationError(
                "Footsteps on a terrain need the legs' reach there: pass reach="
                "TerrainReach.for_leg(sole_length, sole_width, leg_length)."
            )
        return place_on_terrain(
            plan, terrain, reach, limits=self.limits, closing=stop and nb_steps > 0
        )


def plan_from_velocity(
    vx: float,
    vy: float,
    vyaw: float,
    nb_steps: int,
    *,
    limits: LegLimits = LegLimits(),
    timing: StepTiming = StepTiming(),
    **options,
) -> FootstepPlan:
    """One-call form of :meth:`VelocityPlanner.plan`.

    Args:
        vx: Forward velocity, in [m/s].
        vy: Lateral velocity, in [m/s].
        vyaw: Yaw rate, in [rad/s].
        nb_steps: Steps that follow the command.
        limits: Per-step reach of the legs.
        timing: Step timing.
        **options: ``initial_left``, ``initial_right``, ``first_swing``, ``stop``,
            ``terrain``, ``reach``.
    """
    return VelocityPlanner(limits, timing).plan(VelocityCommand(vx, vy, vyaw), nb_steps, **options)
