"""Torque control: the walking controller's tick, then the whole-body inverse dynamics.

A torque-controlled robot (``actuation = "torque"``, :mod:`mpcwalk.sim.actuation`) runs the
tick of :class:`~mpcwalk.control.controller.WalkingController` unchanged (generator, swing and
torso trajectories, DCM feedback, whole-body IK: the IK's ``q_ref`` stays the kinematic
reference), then turns it into joint torques with
:class:`~mpcwalk.ik.inverse_dynamics.InverseDynamicsQP` on the estimated state:

- the CoM acceleration is the generator's, minus ``omega^2`` times the DCM feedback's ZMP
  shift (the LIPM's ``c'' = omega^2 (c - p)`` with the desired ZMP ``p``: what the servo
  feed-forward realises with a base acceleration in position mode), with a PD on the
  estimated CoM towards the IK's CoM target;
- the swing soles follow the gait's poses and velocities, their accelerations the finite
  difference of the velocities;
- the torso follows the gait's yaw; the posture is the IK's ``q_ref`` and velocity;
- the load of each sole (:func:`contact_loads`) ramps from 0 to 1 over ``ramp_time`` after
  touch-down and back to 0 before lift-off, so that the torques do not jump at a switch.

The position servos' joint targets are still computed (and logged); the motors get the
torques of :attr:`~mpcwalk.control.control_output.ControlOutput.joint_torques`: the inverse
dynamics' own, or, with the joint torque loop (``torque_loop``,
:class:`~mpcwalk.control.torque_loop.TorqueLoop`), those divided by each motor's gain as the
joint torque sensors measure it.
"""

import dataclasses
import math
from typing import Any

import numpy as np
import pinocchio as pin

from mpcwalk.control.control_output import ControlOutput
from mpcwalk.control.controller import WalkingController
from mpcwalk.control.torque_loop import TorqueLoop
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps import Side
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.ik.dynamics_program import DEFAULT_DYNAMICS_SOLVER, check_dynamics_solver
from mpcwalk.ik.dynamics_targets import DynamicsTargets
from mpcwalk.ik.inverse_dynamics import InverseDynamicsQP
from mpcwalk.ik.sole_support import ROCKING_RATE
from mpcwalk.models.com_state import ComState


def contact_loads(schedule: ContactSchedule, t: float, ramp_time: float) -> tuple[float, float]:
    """Load of the left and right soles at ``t`` [s], in [0, 1]: 0 off the ground, rising
    linearly to 1 over ``ramp_time`` [s] after touch-down and falling to 0 over ``ramp_time``
    before lift-off (none at the schedule's start and end)."""
    phases = schedule.phases
    index = schedule.phase_at(t)
    loads = []
    for side in (Side.LEFT, Side.RIGHT):
        if side not in phases[index].feet:
            loads.append(0.0)
            continue
        first = last = index
        while first > 0 and side in phases[first - 1].feet:
            first -= 1
        while last < len(phases) - 1 and side in phases[last + 1].feet:
            last += 1
        touch_down = -math.inf if first == 0 else phases[first].start
        lift_off = math.inf if last == len(phases) - 1 else phases[last].end
        if ramp_time <= 0.0:
            loads.append(1.0)
            continue
        share = min(t - touch_down, lift_off - t) / ramp_time
        loads.append(float(min(max(share, 0.0), 1.0)))
    return loads[0], loads[1]


def state_delay(
    control_period: float, *, latency: float = 0.0, velocity_cutoff: float | None = None
) -> float:
    """Age [s] of the state the torques act on, on average over the tick: the sensors'
    ``latency`` [s], the control period (half for the zero-order hold of the torques, half
    for the finite difference of the encoders) and the lag ``1 / (2 pi f_c)`` of the joint
    velocities' first-order low-pass of cut-off ``velocity_cutoff`` [Hz] (None: the
    simulator's exact velocities).

    Raises:
        ConfigurationError: A non-positive period or cut-off, or a negative latency.
    """
    if not (math.isfinite(control_period) and control_period > 0.0):
        raise ConfigurationError(f"control_period must be > 0 [s], got {control_period!r}.")
    if not (math.isfinite(latency) and latency >= 0.0):
        raise ConfigurationError(f"latency must be >= 0 [s], got {latency!r}.")
    delay = float(latency) + float(control_period)
    if velocity_cutoff is not None:
        if not (math.isfinite(velocity_cutoff) and velocity_cutoff > 0.0):
            raise ConfigurationError(
                f"velocity_cutoff must be > 0 [Hz] (None: exact velocities), got "
                f"{velocity_cutoff!r}."
            )
        delay += 1.0 / (2.0 * math.pi * velocity_cutoff)
    return delay


def _yaw_rotation(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class TorqueController(WalkingController):
    """:class:`~mpcwalk.control.controller.WalkingController` whose output also carries the
    joint torques of the whole-body inverse dynamics.

    Args:
        robot: The robot.
        generator: Pattern generator (as :class:`WalkingController`).
        schedule: Footsteps and contact phases.
        inverse_dynamics: The inverse-dynamics QP (default: ``InverseDynamicsQP(robot)``
            on ``dynamics_solver``, with its posture gains capped for ``state_delay``).
        dynamics_solver: Back-end of the default inverse dynamics' QP, one of
            :func:`~mpcwalk.ik.dynamics_program.dynamics_solver_names` (``"daqp-direct"``,
            ``"quadprog"``, ``"proxqp"``...); a walk sets it with
            ``controller_options = {dynamics_solver = "NAME"}``. Not with
            ``inverse_dynamics``, which has its own.
        ramp_time: Duration [s] of the load ramp of a sole at touch-down and lift-off, >= 0.
        rocking_rate: Roll and pitch rate [rad/s] of a loaded sole above which the default
            inverse dynamics narrows the part of it the CoP may use
            (:class:`~mpcwalk.ik.sole_support.SoleSupport`; None: its default,
            :data:`~mpcwalk.ik.sole_support.ROCKING_RATE`, off; 0: never); a walk sets it
            with ``controller_options = {rocking_rate = R}``. Not with ``inverse_dynamics``.
        state_delay: Age [s] of the estimated state the torques act on
            (:func:`state_delay`; default: one control period, the simulator's exact state).
        torque_loop: Whether to divide the torques by each motor's gain as the joint torque
            sensors measure it (:class:`~mpcwalk.control.torque_loop.TorqueLoop`); a walk
            sets it with ``controller_options = {torque_loop = true}``. Without joint torque
            readings the gains stay 1.
        options: The other options of :class:`WalkingController`.

    Raises:
        ConfigurationError: A negative ramp time, an unknown ``dynamics_solver`` (the
            message lists the choices), a negative ``rocking_rate``, either given with
            ``inverse_dynamics``, or the options' own errors.
    """

    def __init__(
        self,
        robot,
        generator,
        schedule: ContactSchedule,
        *,
        inverse_dynamics: InverseDynamicsQP | None = None,
        dynamics_solver: str | None = None,
        ramp_time: float = 0.04,
        state_delay: float | None = None,
        rocking_rate: float | None = None,
        torque_loop: bool = False,
        **options: Any,
    ) -> None:
        super().__init__(robot, generator, schedule, **options)
        if not (math.isfinite(ramp_time) and ramp_time >= 0.0):
            raise ConfigurationError(f"ramp_time must be >= 0 [s], got {ramp_time!r}.")
        self.ramp_time = float(ramp_time)
        self.state_delay = self.control_period if state_delay is None else state_delay
        if inverse_dynamics is None:
            solver = check_dynamics_solver(dynamics_solver or DEFAULT_DYNAMICS_SOLVER)
            inverse_dynamics = InverseDynamicsQP(
                robot,
                solver=solver,
                state_delay=self.state_delay,
                control_period=self.control_period,
                rocking_rate=ROCKING_RATE if rocking_rate is None else rocking_rate,
            )
        elif dynamics_solver is not None or rocking_rate is not None:
            raise ConfigurationError(
                "dynamics_solver or rocking_rate given with inverse_dynamics: the inverse "
                "dynamics has its own (InverseDynamicsQP(robot, solver=..., "
                "rocking_rate=...)); give one of them."
            )
        self.inverse_dynamics = inverse_dynamics
        if not isinstance(torque_loop, bool):
            raise ConfigurationError(f"torque_loop must be true or false, got {torque_loop!r}.")
        self.torque_loop = (
            TorqueLoop(inverse_dynamics.torque_limit.copy(), control_period=self.control_period)
            if torque_loop
            else None
        )
        self.dynamics_failures = 0
        """Ticks whose inverse dynamics failed (the previous torques were held)."""

    def reset(self, q: np.ndarray | None = None) -> ControlOutput:
        output = super().reset(q)
        self.inverse_dynamics.reset()
        self.dynamics_failures = 0
        if self.torque_loop is not None:
            self.torque_loop.reset()
        q_start = output.q_ref
        torques = self.inverse_dynamics.static_torques(q_start)
        self._needed = torques  # the joint torques the robot needs (before the loop)
        self.last_output = dataclasses.replace(output, joint_torques=torques)
        return self.last_output

    def targets(self, output: ControlOutput, previous: ControlOutput) -> DynamicsTargets:
        """The inverse dynamics' references of the tick that produced ``output``."""
        dt = self.control_period
        reference = output.generator
        omega = self.generator.lipm.omega
        shift = output.zmp_command - reference.zmp
        acceleration_xy = reference.com_acceleration - omega**2 * shift
        height_rate = (output.com_target[2] - previous.com_target[2]) / dt
        feet, feet_before = (
            (output.feet.left, output.feet.right),
            (
                previous.feet.left,
                previous.feet.right,
            ),
        )
        poses, velocities, accelerations = [], [], []
        for foot, before in zip(feet, feet_before):
            poses.append(pin.SE3(foot.transform))
            velocity = np.concatenate([foot.linear_velocity, foot.angular_velocity])
            velocity_before = np.concatenate([before.linear_velocity, before.angular_velocity])
            velocities.append(velocity)
            accelerations.append((velocity - velocity_before) / dt)
        yaw_rate = math.remainder(output.torso_yaw - previous.torso_yaw, math.tau) / dt
        return DynamicsTargets(
            com=output.com_target,
            com_velocity=np.array([*reference.com_velocity, height_rate]),
            com_acceleration=np.array([*acceleration_xy, 0.0]),
            left_sole=poses[0],
            right_sole=poses[1],
            torso_rotation=_yaw_rotation(output.torso_yaw),
            posture=output.q_ref,
            contact_weights=contact_loads(self.schedule, output.time, self.ramp_time),
            left_sole_velocity=velocities[0],
            right_sole_velocity=velocities[1],
            left_sole_acceleration=accelerations[0],
            right_sole_acceleration=accelerations[1],
            torso_angular_velocity=np.array([0.0, 0.0, yaw_rate]),
            posture_velocity=output.ik.v,
        )

    def step(self, state: EstimatedState | ComState | None = None) -> ControlOutput:
        """One control tick (:meth:`WalkingController.step`) and its joint torques.

        Raises:
            ConfigurationError: ``state`` is not an EstimatedState: torque control acts on
                the estimated configuration and velocity.
        """
        if not isinstance(state, EstimatedState):
            raise ConfigurationError(
                "A torque-controlled robot needs its estimated state each tick (an "
                f"EstimatedState), got {type(state).__name__}."
            )
        previous = self.last_output
        output = super().step(state)
        assert previous is not None and previous.joint_torques is not None  # reset() set them
        targets = self.targets(output, previous)
        q, v = np.asarray(state.q), np.asarray(state.v)
        loop = self.torque_loop
        if loop is not None:
            loop.measure(state.sensors.time, state.sensors.joint_torques)
            # what the motors can give: their limits times their gains (never above rated)
            self.inverse_dynamics.torque_limit[:] = loop.limits * np.minimum(loop.gains, 1.0)
        if np.all(np.isfinite(q)) and np.all(np.isfinite(v)):
            result = self.inverse_dynamics.solve(q, v, targets)
            if not result.success and loop is not None and np.any(loop.gains < 1.0):
                # no solution within what the weak motors give: within their rated limits
                # (the motors clip the rest) rather than none
                self.inverse_dynamics.torque_limit[:] = loop.limits
                result = self.inverse_dynamics.solve(q, v, targets)
            torques = result.torques
        else:  # a faulty estimate: the torques of the last tick hold
            result, torques = None, self._needed
        if result is None or not result.success:
            self.dynamics_failures += 1
        self._needed = torques
        if loop is not None:
            torques = loop.command(output.time, torques)
        self.last_output = dataclasses.replace(output, joint_torques=torques, dynamics=result)
        return self.last_output
