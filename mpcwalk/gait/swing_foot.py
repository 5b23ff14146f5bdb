"""Swing-foot and torso-yaw trajectories of paper M (eq. 19-23).

During step ``k`` the swing foot goes from its lift pose (its footstep
before the step) to its landing pose ``plan.steps[k]``:

- its horizontal pose ``(x, y, yaw)`` follows ``(1 - h) p[k] + h p[k+1]``
  (eq. 21), with ``h`` of :func:`~mpcwalk.gait.interpolation.step_interpolation`;
  its roll and pitch (a footstep on a tilted tread) follow the same law, from the
  lift-off's to the landing's;
- its height is the ground height, interpolated with ``h`` between the two
  footsteps, plus ``z_step * v`` (eq. 22-23) with ``v`` of
  :func:`~mpcwalk.gait.interpolation.swing_height_profile`.

The torso yaw follows ``(1 - h) psi[k] + h psi[k+1]`` (eq. 19), where
``psi[k]`` is the mean yaw of the two feet at the start of step ``k``; it
does not change in double support. Velocities are the analytic time
derivatives of these expressions.
"""

import math
from dataclasses import replace

import numpy as np

from mpcwalk._checks import as_float, frozen_array
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Footstep, Side, wrap_angle
from mpcwalk.gait import heel_off
from mpcwalk.gait.contact_schedule import ContactSchedule, Phase
from mpcwalk.gait.ctraj import ctraj_swing
from mpcwalk.gait.foot_state import FeetState, FootState
from mpcwalk.gait.interpolation import step_interpolation_scalar, swing_height_scalar
from mpcwalk.gait.swing_clearance import SwingClearance, with_height
from mpcwalk.gait.swing_retarget import QuinticRetarget
from mpcwalk.terrain import Terrain

__all__ = ["SWING_PROFILES", "FeetState", "FootState", "SwingFootTrajectory"]


def _static_state(foot: Footstep) -> FootState:
    return FootState(
        frozen_array(foot.position),
        foot.yaw,
        frozen_array(np.zeros(3)),
        0.0,
        True,
        foot.roll,
        foot.pitch,
    )


def _retargeted(state: FootState, retarget: QuinticRetarget, t: float) -> FootState:
    """``state`` with its horizontal position and velocity on ``retarget`` at ``t`` [s]."""
    xy, vxy, _ = retarget.evaluate(t)
    position, velocity = np.array(state.position), np.array(state.linear_velocity)
    position[:2], velocity[:2] = xy, vxy
    return replace(state, position=frozen_array(position), linear_velocity=frozen_array(velocity))


#: Swing-foot profiles: paper M's cosines, paper A's Cartesian quintic lift and lower.
SWING_PROFILES = ("cosine", "ctraj")


class SwingFootTrajectory:
    """Feet and torso-yaw references along a contact schedule (paper M).

    Args:
        schedule: Contact schedule of the walk.
        step_height: Maximum height ``z_step`` of the swing foot above the
            ground, reached in the middle of single support, in [m]
            (paper M, Table 1: 0.04 m).
        profile: ``"cosine"`` (paper M eq. 21-23: h and v) or ``"ctraj"``
            (paper A: the foot is lifted from its pose to an apex above the
            middle of the step, then lowered onto the landing pose, each half
            a Cartesian trajectory with the quintic time law of
            :func:`~mpcwalk.gait.ctraj.ctraj`: zero velocity and acceleration
            at lift-off, apex and touchdown).
        terrain: The ground (None: the flat floor). A swing over ground higher than its
            footholds rises, travels, then lowers, clearing the terrain by ``clearance``
            (:mod:`~mpcwalk.gait.swing_clearance`); the others keep ``profile``.
        clearance: Least height [m] of the swing sole above the terrain (default:
            ``step_height``, at least 1 cm).

    Raises:
        ConfigurationError: If ``schedule`` is not a ContactSchedule or
            ``step_height`` is negative or not finite.
    """

    def __init__(
        self,
        schedule: ContactSchedule,
        step_height: float = 0.04,
        profile: str = "cosine",
        *,
        terrain: Terrain | None = None,
        clearance: float | None = None,
    ) -> None:
        if profile not in SWING_PROFILES:
            raise ConfigurationError(
                f"Swing profile must be one of {', '.join(SWING_PROFILES)}, got {profile!r}."
            )
        self.profile = profile
        if not isinstance(schedule, ContactSchedule):
            raise ConfigurationError(
                f"SwingFootTrajectory needs a ContactSchedule, got "
                f"{type(schedule).__name__}; build one with ContactSchedule(plan)."
            )
        step_height = as_float(step_height)
        if not np.isfinite(step_height) or step_height < 0.0:
            raise ConfigurationError(
                f"step_height must be a non-negative number of metres, got "
                f"{step_height!r}; paper M uses 0.04 m."
            )
        self.schedule = schedule
        self.step_height = step_height
        self.step_duration = schedule.step_duration
        self.phi_b = schedule.t_b / schedule.step_duration
        self.phi_e = schedule.t_e / schedule.step_duration
        self.torso_yaws = self._torso_waypoint_yaws()
        self.terrain_clearance = (
            SwingClearance(terrain, schedule.foot, step_height, clearance)
            if terrain is not None and not terrain.is_flat
            else None
        )
        # step index -> (h, horizontal position (2,), yaw, height offset, roll, pitch) the
        # swing restarts from
        self._restarts: dict[int, tuple[float, np.ndarray, float, float, float, float]] = {}
        self._travels: set[int] = set()  # steps restarted on their terrain swing's travel law
        self._retargets: dict[int, QuinticRetarget] = {}  # step -> its horizontal quintic
        self._static_states: dict[int, tuple[Footstep, FootState]] = {}

    def restart_swing(
        self, t: float, foot: FootState, acceleration: np.ndarray | None = None
    ) -> None:
        """Continue the swing in progress at ``t`` from ``foot`` (its pose then) towards
        this schedule's landing: the landing moved during the swing (footstep-adaptive
        generator), and the horizontal position and the angles must not jump. From ``t`` on,
        they cover what is left of the way with the rest of the interpolant h (a terrain
        swing's travel law: it still lowers after its travel), rescaled
        ``(h - h(t)) / (1 - h(t))``; the height follows the profile, offset by the foot's
        height above it at ``t`` fading out by touch-down (none when only the landing
        moved; the schedule's clock jumping ahead, a landing brought forward, needs it). No
        effect outside a single support.

        With the foot's horizontal ``acceleration`` [m/s^2] (shape (2,) or (3,)) given, the
        horizontal position is instead re-planned as a quintic of time from the foot's
        position, velocity and acceleration at ``t`` to the landing at rest
        (:class:`~mpcwalk.gait.swing_retarget.QuinticRetarget`, late step adjustment):
        position, velocity and acceleration do not jump, whatever the interpolant."""
        t = self._check_time(t)
        k, h, _ = self._interpolants(t)
        if (
            not (0 <= k < self.schedule.plan.nb_steps)
            or not self.schedule.phase(t).single_support
            or h >= 1.0 - 1e-9
        ):
            return
        landing = self.schedule.plan.steps[k]
        lift = self.schedule.stance(t)[landing.side]
        profile = self._swing_state(t, lift, landing, h, 0.0).position[2]
        height = float(foot.position[2]) - float(profile)
        shaped = self._shaped(t, lift, landing)
        self._travels.discard(k)
        if shaped is not None and shaped[0] < 1.0 - 1e-9:  # a terrain swing: travel, lower
            h = shaped[0]
            self._travels.add(k)
        self._retargets.pop(k, None)
        remaining = self.schedule.walk_start + k * self.step_duration + self.schedule.t_e - t
        if acceleration is not None and remaining > 1e-6:
            self._retargets[k] = QuinticRetarget(
                t,
                remaining,
                np.asarray(foot.position[:2], dtype=float),
                np.asarray(foot.linear_velocity[:2], dtype=float),
                np.asarray(acceleration, dtype=float)[:2],
                np.asarray(landing.position[:2], dtype=float),
            )
        self._restarts[k] = (
            h,
            np.array(foot.position[:2], dtype=float),
            float(foot.yaw),
            height,
            float(foot.roll),
            float(foot.pitch),
        )

    def _torso_waypoint_yaws(self) -> np.ndarray:
        """Torso yaw ``psi[k]`` at the start of each step (and after the last),
        shape (nb_steps + 1,), in [rad], unwrapped so that consecutive values
        differ by less than pi."""
        yaws: list[float] = []
        for stance in self.schedule.plan.stances():
            left, right = stance[Side.LEFT].yaw, stance[Side.RIGHT].yaw
            mean = left + 0.5 * float(wrap_angle(right - left))
            if yaws:
                mean = yaws[-1] + float(wrap_angle(mean - yaws[-1]))
            yaws.append(mean)
        return frozen_array(yaws)

    def _interpolants(self, t: float, phase: Phase | None = None) -> tuple[int, float, float]:
        """Active step, ``h`` and ``dh/dt`` at time ``t`` (``phase``: the schedule's phase
        at ``t``, when the caller has it).

        In double support ``h`` is exactly 0 or 1 and ``dh/dt`` exactly 0, as
        the schedule's phases say (robust to the rounding of ``phi`` at the
        phase boundaries).
        """
        k = self.schedule.step_index(t)
        if k < 0 or k >= self.schedule.plan.nb_steps:
            return k, 0.0, 0.0
        phi = self.schedule.step_phase(t)
        if phase is None:
            phase = self.schedule.phase(t)
        if not phase.single_support:
            return k, (0.0 if phi < 0.5 else 1.0), 0.0
        h, dh = step_interpolation_scalar(phi, self.phi_b, self.phi_e, self.step_duration)
        return k, h, dh

    @staticmethod
    def _check_time(t) -> float:
        t = as_float(t)
        if not math.isfinite(t):
            raise ConfigurationError(f"Time must be a finite number of seconds, got {t!r}.")
        return t

    def foot_poses(self, t: float) -> FeetState:
        """Poses and velocities of both feet at time ``t`` [s].

        Returns:
            The feet state. A foot on the ground sits exactly on its footstep
            with zero velocity; the swing foot follows eq. 21-23.
        """
        return self._foot_poses(self._check_time(t))

    def references(self, t: float) -> tuple[FeetState, float]:
        """:meth:`foot_poses` and :meth:`torso_yaw` at ``t`` [s] in one call (the
        controller's tick)."""
        t = self._check_time(t)
        phase = self.schedule.phase(t)
        return self._foot_poses(t, phase), self._torso_yaw(t, phase)

    def _static(self, foot: Footstep) -> FootState:
        """The state of a foot resting on ``foot`` (built once per footstep: read-only)."""
        cached = self._static_states.get(id(foot))
        if cached is None or cached[0] is not foot:
            cached = self._static_states[id(foot)] = (foot, _static_state(foot))
        return cached[1]

    def _foot_poses(self, t: float, phase: Phase | None = None) -> FeetState:
        schedule = self.schedule
        if phase is None:
            phase = schedule.phase(t)
        k, h, dh = self._interpolants(t, phase)
        stance = schedule.stance(t)
        in_contact = phase.feet
        states: dict[Side, FootState] = {side: self._static(foot) for side, foot in stance.items()}
        if 0 <= k < schedule.plan.nb_steps:
            landing = schedule.plan.steps[k]
            swing = landing.side
            lift = stance[swing]
            if swing in in_contact:
                phi = schedule.step_phase(t)
                states[swing] = self._static(lift if phi < 0.5 else landing)
                if phi < 0.5 and self.terrain_clearance is not None:  # heel-off, stepping down
                    states[swing] = heel_off.before_lift(self, states[swing], lift, landing, t)
            else:
                states[swing] = self._swing_state(t, lift, landing, h, dh)
                if k in self._restarts:
                    law = self._shaped(t, lift, landing) if k in self._travels else None
                    hr, dhr = (h, dh) if law is None else law[:2]
                    states[swing] = self._restarted(
                        states[swing], landing, hr, dhr, *self._restarts[k]
                    )
                if k in self._retargets:
                    states[swing] = _retargeted(states[swing], self._retargets[k], t)
        return FeetState(t, k, states[Side.LEFT], states[Side.RIGHT])

    def _swing_state(
        self, t: float, lift: Footstep, landing: Footstep, h: float, dh: float
    ) -> FootState:
        phi = self.schedule.step_phase(t)
        shaped = self._shaped(t, lift, landing)
        if shaped is not None:
            state = self._blend(lift, landing, shaped[0], shaped[1], 0.0, 0.0)
            state = with_height(state, shaped[2], shaped[3])
            return heel_off.in_swing(self, state, lift, landing, phi)
        if self.profile == "ctraj":
            h, dh, v, dv = ctraj_swing(phi, self.phi_b, self.phi_e, self.step_duration)
            return self._blend(lift, landing, h, dh, v, dv)
        v, dv = swing_height_scalar(phi, self.phi_b, self.phi_e, self.step_duration)
        return self._blend(lift, landing, h, dh, v, dv)

    def _shaped(self, t: float, lift: Footstep, landing: Footstep):
        """The terrain swing's ``(h, dh, z, dz)`` at ``t`` [s] (rise, travel, lower:
        :meth:`~mpcwalk.gait.swing_clearance.SwingClearance.interpolants`), None when the
        swing keeps ``profile``."""
        if self.terrain_clearance is None:
            return None
        span = self.phi_e - self.phi_b
        s = (self.schedule.step_phase(t) - self.phi_b) / span
        return self.terrain_clearance.interpolants(lift, landing, s, span * self.step_duration)

    @staticmethod
    def _restarted(
        state: FootState,
        landing: Footstep,
        h: float,
        dh: float,
        h0: float,
        origin: np.ndarray,
        yaw0: float,
        height: float = 0.0,
        roll0: float = 0.0,
        pitch0: float = 0.0,
    ) -> FootState:
        """``state`` with its horizontal motion and its angles restarted at ``h0`` from
        ``origin``/``yaw0``/``roll0``/``pitch0``, its height offset by ``height`` [m] fading
        out with the rest of the way."""
        scale = 1.0 / (1.0 - h0)
        r, dr = max(h - h0, 0.0) * scale, dh * scale
        delta = landing.position[:2] - origin
        delta_yaw = float(wrap_angle(landing.yaw - yaw0))
        position = np.array(state.position)
        velocity = np.array(state.linear_velocity)
        position[:2] = origin + r * delta
        velocity[:2] = dr * delta
        if height:
            position[2] += height * (1.0 - r)
            velocity[2] -= height * dr
        delta_roll, delta_pitch = landing.roll - roll0, landing.pitch - pitch0
        return FootState(
            frozen_array(position),
            yaw0 + r * delta_yaw,
            frozen_array(velocity),
            dr * delta_yaw,
            False,
            roll0 + r * delta_roll,
            pitch0 + r * delta_pitch,
            dr * delta_roll,
            dr * delta_pitch,
        )

    def _blend(
        self, lift: Footstep, landing: Footstep, h: float, dh: float, v: float, dv: float
    ) -> FootState:
        delta = landing.position - lift.position
        delta_yaw = float(wrap_angle(landing.yaw - lift.yaw))
        lift_direction = np.array([0.0, 0.0, self.step_height])
        position = lift.position + h * delta + v * lift_direction
        velocity = dh * delta + dv * lift_direction
        delta_roll, delta_pitch = landing.roll - lift.roll, landing.pitch - lift.pitch
        return FootState(
            frozen_array(position),
            lift.yaw + h * delta_yaw,
            frozen_array(velocity),
            dh * delta_yaw,
            False,
            lift.roll + h * delta_roll,
            lift.pitch + h * delta_pitch,
            dh * delta_roll,
            dh * delta_pitch,
        )

    def torso_yaw(self, t):
        """Torso yaw (eq. 19) at time(s) ``t`` [s], in [rad].

        The yaw is continuous over the whole walk (not wrapped to [-pi, pi));
        apply :func:`~mpcwalk.footsteps.footstep.wrap_angle` if needed.

        Returns:
            A float for a scalar ``t``, else an array of the shape of ``t``.
        """
        return self._vectorised(t, self._torso_yaw)

    def torso_yaw_rate(self, t):
        """Time derivative of :meth:`torso_yaw` at time(s) ``t`` [s], in [rad/s]."""
        return self._vectorised(t, self._torso_yaw_rate)

    def _vectorised(self, t, function):
        if np.ndim(t) == 0:
            return function(self._check_time(t))
        times = np.asarray(t, dtype=float)
        flat = [function(self._check_time(x)) for x in times.ravel()]
        return np.array(flat).reshape(times.shape)

    def _torso_yaw(self, t: float, phase: Phase | None = None) -> float:
        k, h, _ = self._interpolants(t, phase)
        psi = self.torso_yaws
        if k < 0:
            return float(psi[0])
        if k >= len(psi) - 1:
            return float(psi[-1])
        return float(psi[k] + h * (psi[k + 1] - psi[k]))

    def _torso_yaw_rate(self, t: float) -> float:
        k, _, dh = self._interpolants(t)
        psi = self.torso_yaws
        if k < 0 or k >= len(psi) - 1:
            return 0.0
        return float(dh * (psi[k + 1] - psi[k]))
