"""Footstep re-aiming: every step re-aimed from the measured support foot (paper A, sec. 3.3).

Paper A walks with a state machine (begin, lift left, lower left, lift right, lower right):
the state follows the contact schedule of a footstep path: ``BEGIN`` while both feet stand
before the first step, then for each step ``LIFT_<side>`` from the start of the step to the
middle of its single support (weight shift and lift) and ``LOWER_<side>`` until the end of
the step (lowering and weight transfer), and ``DONE`` after the last step.

As a :class:`~mpcwalk.control.stabilizers.base.Stabilizer` (registered as ``"reaim"``) it
re-aims every step: when the single support of step ``k`` begins, the step's global target
is taken into the frame of the *measured* support foot (its yaw from the IMU, or from the
sole), clamped into the reachability rectangle, and the landing is carried into the
controller's kinematic reference frame through the support foot (``L_ref = S_ref S_meas^-1
L``). Each foot keeps the offset ``L_ref - L`` of its last landing; the swing foot moves from
its lift offset to its landing offset with paper M's ``h(phi)``, and the CoM and torso-yaw
targets move with the mean offset of the feet. The measured drift of the support foot is
therefore corrected at every step and does not accumulate.

The re-aiming moves the landings horizontally (x, y, yaw): a footstep on a tilted tread keeps
its height, roll and pitch (never flattened). Given a ``height_map`` (the ground's height and
world roll and pitch at a point), a clamped landing takes the ground's where it lands instead,
and the feet's targets move by that height and tilt too (``surface_offsets``); the CoM's
height still follows the planned footsteps.
"""

import math
from dataclasses import replace
from enum import Enum

import numpy as np

from mpcwalk.control.stabilizers.base import GaitTargets, Stabilizer, StabilizerInput
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Footstep, HeightMap, Side, wrap_angle
from mpcwalk.footsteps.reachability import ATLAS_REACHABILITY, ReachabilityRectangle
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.interpolation import step_interpolation
from mpcwalk.gait.swing_foot import FeetState, FootState


class GaitState(str, Enum):
    """States of paper A's gait."""

    BEGIN = "begin"
    LIFT_LEFT = "lift left"
    LOWER_LEFT = "lower left"
    LIFT_RIGHT = "lift right"
    LOWER_RIGHT = "lower right"
    DONE = "done"


_LIFT = {Side.LEFT: GaitState.LIFT_LEFT, Side.RIGHT: GaitState.LIFT_RIGHT}
_LOWER = {Side.LEFT: GaitState.LOWER_LEFT, Side.RIGHT: GaitState.LOWER_RIGHT}
#: Allowed transitions (the cycle of paper A plus begin and done).
TRANSITIONS = {
    GaitState.BEGIN: {GaitState.LIFT_LEFT, GaitState.LIFT_RIGHT, GaitState.DONE},
    GaitState.LIFT_LEFT: {GaitState.LOWER_LEFT},
    GaitState.LOWER_LEFT: {GaitState.LIFT_RIGHT, GaitState.LIFT_LEFT, GaitState.DONE},
    GaitState.LIFT_RIGHT: {GaitState.LOWER_RIGHT},
    GaitState.LOWER_RIGHT: {GaitState.LIFT_LEFT, GaitState.LIFT_RIGHT, GaitState.DONE},
    GaitState.DONE: set(),
}


def _yaw_of(rotation: np.ndarray) -> float:
    return math.atan2(rotation[1, 0], rotation[0, 0])


class FootstepReaiming(Stabilizer):
    """Re-aims every step from the measured support foot, following the gait's states (paper
    A's state machine).

    Args:
        rectangle: Reachability rectangle of the landings around the support foot (None: the
            robot's own, from its leg limits, taken at :meth:`reset`).
        yaw_source: ``"imu"`` (paper A: the support foot's yaw is the estimated base yaw, from
            the IMU, plus the reference offset between the base and the support foot) or
            ``"sole"`` (the estimated sole yaw).
        reaim: Re-aim the steps (False: the state machine only tracks the states).
        height_map: Ground at a world point, ``(x, y) -> (z [m], roll [rad], pitch [rad])``
            (world roll and pitch of the ground), where a clamped landing takes its height and
            tilt; None (default): the landing keeps its planned height, roll and pitch.
    """

    name = "reaim"

    def __init__(
        self,
        rectangle: ReachabilityRectangle | None = None,
        *,
        yaw_source: str = "imu",
        reaim: bool = True,
        height_map: HeightMap | None = None,
    ) -> None:
        if yaw_source not in ("imu", "sole"):
            raise ConfigurationError(f"yaw_source must be 'imu' or 'sole', got {yaw_source!r}.")
        self.holds_heading = bool(reaim)
        self._rectangle = rectangle
        self.rectangle: ReachabilityRectangle = (
            rectangle if rectangle is not None else ATLAS_REACHABILITY
        )
        """The rectangle in use: the given one, else the robot's from :meth:`reset`."""
        self.yaw_source = yaw_source
        self.reaim = bool(reaim)
        self.height_map = height_map
        self.schedule: ContactSchedule | None = None
        self._reset_state()

    def _reset_state(self) -> None:
        self.state = GaitState.BEGIN
        self.history: list[tuple[float, GaitState]] = [(0.0, GaitState.BEGIN)]
        """(time [s], state entered) in order."""
        self.offsets: dict[Side, np.ndarray] = {s: np.zeros(3) for s in Side}
        """Per foot (dx [m], dy [m], dyaw [rad]) of its last landing in the reference frame."""
        self.surface_offsets: dict[Side, np.ndarray] = {s: np.zeros(3) for s in Side}
        """Per foot (dz [m], droll [rad], dpitch [rad]) of its last landing: the height map's
        ground against the planned footstep (zeros without a height map)."""
        self._lift_offset = np.zeros(3)
        self._lift_surface = np.zeros(3)
        self._aimed_step = -1
        self.landings: list[Footstep] = []
        """Re-aimed world landings, one per step (measured support frame, clamped)."""
        self.nb_clamped = 0

    def reset(self, inputs: StabilizerInput) -> None:
        """Start over at ``BEGIN`` on the schedule of ``inputs``."""
        self.schedule = inputs.schedule
        if self._rectangle is None:
            self.rectangle = inputs.robot.leg_limits.rectangle()
        self._reset_state()

    def state_at(self, t: float) -> GaitState:
        """State of the gait at time ``t`` [s] along the schedule (no side effect)."""
        schedule = self._require_schedule()
        if t < schedule.walk_start:
            return GaitState.BEGIN
        k = int(math.floor((t - schedule.walk_start) / schedule.step_duration + 1e-12))
        if k >= schedule.plan.nb_steps:
            return GaitState.DONE
        side = schedule.plan.steps[k].side
        phase = t - schedule.walk_start - k * schedule.step_duration
        return _LIFT[side] if phase < 0.5 * (schedule.t_b + schedule.t_e) else _LOWER[side]

    def update(self, t: float) -> GaitState:
        """Advance the state machine to time ``t`` and return the state.

        Raises:
            ConfigurationError: A transition outside :data:`TRANSITIONS` (time went back).
        """
        state = self.state_at(t)
        if state is not self.state:
            if state not in TRANSITIONS[self.state]:
                raise ConfigurationError(
                    f"The footstep re-aiming cannot go from '{self.state.value}' to "
                    f"'{state.value}' at t = {t:g} s; times must increase."
                )
            self.state = state
            self.history.append((float(t), state))
        return state

    def _require_schedule(self) -> ContactSchedule:
        if self.schedule is None:
            raise ConfigurationError(
                "FootstepReaiming needs a schedule: call reset(inputs) or set .schedule."
            )
        return self.schedule

    def aim_step(self, k: int, support_measured: Footstep) -> np.ndarray:
        """Re-aim step ``k`` from the measured support foot; returns the landing's offset
        ``(dx, dy, dyaw)`` in the reference frame (also stored for the swing foot).

        The landing keeps the planned height, roll and pitch, or takes the height map's
        where it lands (their change is stored in :attr:`surface_offsets`)."""
        schedule = self._require_schedule()
        goal = schedule.plan.steps[k]
        planned_support = schedule.plan.support_foot(k)
        result = self.rectangle.clamp_footstep(support_measured, goal, self.height_map)
        landing = result.footstep
        self.surface_offsets[goal.side] = np.array(
            [
                landing.position[2] - goal.position[2],
                landing.roll - goal.roll,
                landing.pitch - goal.pitch,
            ]
        )
        self.nb_clamped += int(result.local.was_clamped)
        self.landings.append(landing)
        offset = self.offsets[planned_support.side]
        support_ref = Footstep(
            planned_support.side,
            planned_support.position + np.array([*offset[:2], 0.0]),
            float(planned_support.yaw + offset[2]),
        )
        local = support_measured.to_local(landing.xy)
        local_yaw = float(wrap_angle(landing.yaw - support_measured.yaw))
        xy_ref = support_ref.to_world(local)
        yaw_ref = support_ref.yaw + local_yaw
        return np.array(
            [xy_ref[0] - goal.xy[0], xy_ref[1] - goal.xy[1], float(wrap_angle(yaw_ref - goal.yaw))]
        )

    def _measured_support(
        self, inputs: StabilizerInput, side: Side, state: EstimatedState
    ) -> Footstep:
        index = 0 if side is Side.LEFT else 1
        position = np.array(state.sole_positions[index], dtype=float)
        yaw = float(state.sole_yaws[index])
        if self.yaw_source == "imu":
            q_ref = inputs.q_ref  # reference base yaw vs reference sole yaw
            base_rotation = _quaternion_xyzw_matrix(q_ref[3:7])
            sole_ref = inputs.robot.compute_sole_placements(q_ref)[index]
            yaw = state.yaw + float(wrap_angle(_yaw_of(sole_ref.rotation) - _yaw_of(base_rotation)))
        return Footstep(side, position, float(wrap_angle(yaw)))

    def adjust_targets(self, inputs: StabilizerInput) -> GaitTargets:
        """The targets moved by the offsets of the re-aimed landings (see the module)."""
        t, targets = inputs.time, inputs.targets
        feet, com_xy, torso_yaw = targets.feet, targets.com_xy, targets.torso_yaw
        state = self.update(t)
        schedule = self._require_schedule()
        if not self.reaim or state in (GaitState.BEGIN,):
            return targets
        k = feet.step_index
        swing = schedule.plan.steps[k].side if 0 <= k < schedule.plan.nb_steps else None
        h = 1.0
        if swing is not None:
            phi = schedule.step_phase(t)
            h = float(
                step_interpolation(
                    phi,
                    schedule.t_b / schedule.step_duration,
                    schedule.t_e / schedule.step_duration,
                )
            )
            estimate = inputs.state
            if self._aimed_step < k and not feet[swing].in_contact and estimate is not None:
                self._lift_offset = self.offsets[swing].copy()
                self._lift_surface = self.surface_offsets[swing].copy()
                support = self._measured_support(inputs, swing.other, estimate)
                self.offsets[swing] = self.aim_step(k, support)
                self._aimed_step = k
        current, surface = {}, {}
        for side in Side:
            if side is swing and self._aimed_step == k:
                current[side] = (1.0 - h) * self._lift_offset + h * self.offsets[side]
                surface[side] = (1.0 - h) * self._lift_surface + h * self.surface_offsets[side]
            else:
                current[side] = self.offsets[side]
                surface[side] = self.surface_offsets[side]
        states = {side: _moved(feet[side], current[side], surface[side]) for side in Side}
        mean = 0.5 * (current[Side.LEFT] + current[Side.RIGHT])
        return GaitTargets(
            FeetState(feet.time, feet.step_index, states[Side.LEFT], states[Side.RIGHT]),
            np.asarray(com_xy) + mean[:2],
            torso_yaw + float(mean[2]),
            inputs.targets.flywheel,
        )


def _moved(foot: FootState, offset: np.ndarray, surface: np.ndarray) -> FootState:
    """``foot`` moved by ``offset`` (dx, dy, dyaw) and ``surface`` (dz, droll, dpitch): its
    other fields (height, roll and pitch without a height map, velocities) kept."""
    position = np.array(foot.position, dtype=float)
    position[:2] += offset[:2]
    changes: dict = {"position": position, "yaw": foot.yaw + float(offset[2])}
    if np.any(surface):
        position[2] += surface[0]
        changes.update(roll=foot.roll + float(surface[1]), pitch=foot.pitch + float(surface[2]))
    return replace(foot, **changes)


def _quaternion_xyzw_matrix(q: np.ndarray) -> np.ndarray:
    x, y, z, w = (float(c) for c in q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
