"""WalkingController: one control tick from footsteps to joint targets. One tick composes:

1. the pattern generator advances by one control period and returns the CoM reference of
   the next tick (closed loop: from the measured CoM, see below);
2. the swing-foot and torso-yaw trajectories (paper M eq. 19-23,
   :class:`~mpcwalk.control.gait_reference.GaitReference`) give the feet and torso targets;
3. the whole-body IK moves the reference configuration ``q_ref`` one step towards them (the
   robot is position controlled, the IK is its kinematic model);
4. the arm swing (paper M eq. 24-25, :class:`~mpcwalk.control.arm_swing.ArmSwing`), a joint
   stage after the IK, sets the shoulder pitch angles of ``q_ref``;
5. the servo feed-forward (:class:`~mpcwalk.control.servo_feedforward.ServoFeedforward`)
   adds the offsets ``tau / kp`` that make compliant position servos carry the reference
   motion, with the contact wrench at the desired ZMP.

The controller knows the robot through its estimated state, never a simulator's ground truth.
Stabilizers (:mod:`mpcwalk.control.stabilizers`) correct the targets of step 3 and the servo
targets of step 5 from a typed input. In closed loop the estimated CoM reaches the generator
through an observer and the desired ZMP of step 5 is the generator's plus the DCM feedback
(:mod:`mpcwalk.control.dcm_feedback`); the heading hold (:mod:`mpcwalk.control.heading_hold`)
turns the footsteps to come by the measured heading error (and shifts them, holding position).
"""

import time
from typing import Any

import numpy as np

from mpcwalk.control.arm_swing import arm_swing_for
from mpcwalk.control.control_output import ControlOutput
from mpcwalk.control.dcm_feedback import DcmFeedback, measured_com_state, support_weights
from mpcwalk.control.faults import FaultMonitor, ik_step, step_generator
from mpcwalk.control.gait_reference import GaitReference, GaitTargets
from mpcwalk.control.heading_hold import HeadingHold
from mpcwalk.control.servo_feedforward import ServoFeedforward
from mpcwalk.control.stabilizers.balance import make_balance
from mpcwalk.control.stabilizers.balance_options import BalanceOptions
from mpcwalk.control.stabilizers.base import Stabilizer, StabilizerInput
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.exceptions import ConfigurationError, NotReset
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.swing_foot import FeetState, SwingFootTrajectory
from mpcwalk.generators.pattern_generator import PatternGenerator
from mpcwalk.ik.targets import IKResult
from mpcwalk.ik.whole_body_ik import WholeBodyIK
from mpcwalk.models.com_state import ComState
from mpcwalk.robot.robot import Robot
from mpcwalk.terrain import Terrain


class WalkingController:
    """Generator + swing-foot/torso trajectories + whole-body IK + servo feed-forward.

    Args:
        robot: The robot (:func:`mpcwalk.robot.load_robot`).
        generator: Pattern generator whose LIPM has the robot's CoM height and whose control
            period is ``control_period``; :meth:`for_robot` builds one by name.
        schedule: Footsteps and contact phases of the walk.
        ik: Whole-body IK of ``robot`` (default: ``WholeBodyIK(robot, upright_pelvis=...)``).
        swing_profile: ``"cosine"`` (paper M) or ``"ctraj"`` (paper A), see
            :class:`~mpcwalk.gait.swing_foot.SwingFootTrajectory`.
        step_height: Swing-foot height [m]; None: the robot's ``gait.step_height`` (its
            preset's ``[gait]`` table, else paper M's 0.04 m).
        feedback: Close the loop on the estimated CoM when an estimate is given (False:
            the open loop of paper M's configuration; no balance stabilizer).
        observer_gain: Share in [0, 1] of the measured CoM error given to the generator
            (default: the generator's :attr:`~PatternGenerator.observer_gain`; see
            :mod:`mpcwalk.control.dcm_feedback` for what it costs).
        dcm_gain: ZMP shift per metre of DCM error, >= 0 (> 1 makes the error decay).
        zmp_margin: The desired ZMP with the DCM feedback is kept this far [m] inside the
            planned support polygon (default: a tenth of the sole width).
        servo_feedforward: Add the feed-forward offsets of compliant position servos.
        control_period: Duration of one tick [s].
        stabilizer: A :class:`~mpcwalk.control.stabilizers.base.Stabilizer` correcting the IK
            targets and the servo targets from the estimated state, or None (applied after
            the balance stabilizer).
        balance: The balance stabilizer's :class:`BalanceOptions`, True (its defaults),
            False (off), or None: on for the QP generators (``BALANCED_GENERATORS`` of
            :mod:`mpcwalk.control.stabilizers.balance`), off for the closed forms. Always off
            when ``feedback`` is False.
        arm_swing: Paper M's arm movement factor s (eq. 24-25; 0.8 in the paper): after the
            IK, the shoulder pitch joints swing each hand with the opposite foot. 0 keeps the
            arms in their nominal posture; a robot without shoulder pitch joints walks
            without it and :attr:`notes` says so.
        heading_hold: Hold the plan's heading (None: :meth:`HeadingHold.maybe`).
        terrain: The ground the robot's map holds: the swing feet clear it (None: the floor).
        hold_position: The heading hold holds the footholds' positions too (``position``).
        upright_pelvis: The default IK keeps the pelvis upright with the torso frame (paper
            M's rigid trunk on a robot with a waist; :class:`WholeBodyIK`).

    The controller follows a new schedule (moved footsteps) from the tick its generator gives it.

    Raises:
        ConfigurationError: A CoM height or control period that does not match, a gain out
            of range, or a schedule that is not a ContactSchedule.
    """

    def __init__(
        self,
        robot: Robot,
        generator: PatternGenerator,
        schedule: ContactSchedule,
        *,
        ik: WholeBodyIK | None = None,
        step_height: float | None = None,
        feedback: bool = True,
        observer_gain: float | None = None,
        dcm_gain: float = 3.0,
        servo_feedforward: bool = True,
        zmp_margin: float | None = None,
        control_period: float = 0.01,
        stabilizer: Stabilizer | None = None,
        swing_profile: str = "cosine",
        arm_swing: float = 0.0,
        balance: BalanceOptions | bool | None = None,
        heading_hold: bool | None = None,
        terrain: Terrain | None = None,
        upright_pelvis: bool = False,
        hold_position: bool = False,
    ) -> None:
        if not (np.isfinite(control_period) and control_period > 0.0):
            raise ConfigurationError(
                f"control_period must be a positive number of seconds, got {control_period!r}."
            )
        if abs(generator.control_period - control_period) > 1e-12:
            raise ConfigurationError(
                f"The generator ticks every {generator.control_period:g} s but the controller "
                f"every {control_period:g} s; build the generator with "
                f"control_period={control_period:g}."
            )
        if abs(generator.lipm.com_height - robot.com_height) > 1e-6:  # [m]
            raise ConfigurationError(
                f"The generator's LIPM has a CoM height of {generator.lipm.com_height:g} m but "
                f"robot '{robot.name}' walks with {robot.com_height:g} m; build the generator "
                "with lipm=LIPM(com_height=robot.com_height) (WalkingController.for_robot does)."
            )
        self.robot = robot
        self.generator = generator
        height = robot.gait.step_height if step_height is None else step_height
        self.reference = GaitReference(
            schedule, height, swing_profile, robot.com_height, terrain=terrain
        )
        self.ik = ik if ik is not None else WholeBodyIK(robot, upright_pelvis=upright_pelvis)
        self.feedback = bool(feedback)
        self.dcm_feedback = DcmFeedback(
            schedule,
            generator.lipm.omega,
            dcm_gain=dcm_gain,
            observer_gain=generator.observer_gain if observer_gain is None else observer_gain,
            zmp_margin=0.1 * min(schedule.foot.length, schedule.foot.width)
            if zmp_margin is None
            else zmp_margin,
        )
        self.feedforward = ServoFeedforward(robot) if servo_feedforward else None
        self.control_period = float(control_period)
        self.stabilizer = stabilizer
        self.balance = make_balance(balance, generator.name) if self.feedback else None
        self.arm_swing, self.notes = arm_swing_for(robot, arm_swing)  # notes: what it left out
        self.heading_hold = HeadingHold.maybe(
            schedule, heading_hold, feedback, generator, stabilizer, position=hold_position
        )
        self.faults = FaultMonitor()  # the tick's boundary checks (mpcwalk.control.faults)
        self.q_ref: np.ndarray | None = None
        self.last_output: ControlOutput | None = None

    @classmethod
    def for_robot(
        cls,
        robot: Robot,
        generator: str,
        schedule: ContactSchedule,
        *,
        control_period: float = 0.01,
        generator_options: dict[str, Any] | None = None,
        **options: Any,
    ) -> "WalkingController":
        """Controller with the generator called ``generator`` on the robot's LIPM.

        ``generator_options`` go to the generator, over what the generator takes from the
        robot (:meth:`PatternGenerator.robot_options`), ``options`` to the controller.
        """
        from mpcwalk.generators import generator_class

        pattern_class: type[PatternGenerator] = generator_class(generator)
        options_ = generator_options or {}
        pattern = pattern_class.for_robot(robot, control_period=control_period, **options_)
        return cls(robot, pattern, schedule, control_period=control_period, **options)

    @property
    def nb_generator_failures(self) -> int:
        """Ticks whose generator reported a failed solve (or raised NoSolutionFound)."""
        return self.faults.generator_failures

    @property
    def time(self) -> float:
        """Time of the last references [s]."""
        return self.generator.time

    @property
    def done(self) -> bool:
        """Whether the schedule is over."""
        return self.generator.done

    @property
    def schedule(self) -> ContactSchedule:
        """Footsteps and contact phases followed now."""
        return self.reference.schedule

    @property
    def trajectory(self) -> SwingFootTrajectory:
        """Swing-foot and torso-yaw trajectories followed now."""
        return self.reference.trajectory

    # ------------------------------------------------------------------ helpers
    @property
    def _stabilizers(self) -> tuple[Stabilizer, ...]:
        """The balance stabilizer and the stabilizer, in the order they are applied."""
        return tuple(s for s in (self.balance, self.stabilizer) if s is not None)

    def _stabilizer_input(
        self,
        t: float,
        targets: GaitTargets,
        state: EstimatedState | None,
        dcm_error: np.ndarray | None = None,
    ) -> StabilizerInput:
        """What the stabilizer sees now: the references of the last output are those of the
        estimate's time, ``q_ref`` the controller's current one."""
        previous = self.last_output
        assert previous is not None and self.q_ref is not None  # set by reset()
        dcm_error = np.zeros(2) if dcm_error is None else dcm_error
        return StabilizerInput(
            time=t,
            control_period=self.control_period,
            robot=self.robot,
            schedule=self.schedule,
            targets=targets,
            q_ref=self.q_ref,
            com_reference=previous.com_target,
            zmp_reference=previous.zmp_command,
            zmp_planned=previous.generator.zmp,
            state=state,
            dcm_error=dcm_error,
        )

    def _joint_targets(
        self,
        q: np.ndarray,
        v: np.ndarray,
        previous_v: np.ndarray,
        zmp: np.ndarray,
        zmp_shift: np.ndarray,
        feet: FeetState,
    ) -> np.ndarray:
        """Joint angles of the reference ``q`` (reached with velocity ``v``) plus the servo
        feed-forward of the reference motion, its wrench's CoP at the desired ``zmp``."""
        if self.feedforward is None:
            return q[7:].copy()
        acceleration = (v - previous_v) / self.control_period
        if zmp_shift.any():  # DCM feedback: accelerate the whole body away from the shift
            acceleration[0:3] += self.dcm_feedback.base_acceleration(q, zmp_shift)
        weights = support_weights(zmp, feet)
        return q[7:] + self.feedforward.compute_offsets(q, weights, v, acceleration)

    def follow_schedule(self, schedule: ContactSchedule) -> None:
        """Follow ``schedule`` from now on (moved footsteps): the swing foot lands on them from
        where it is (no jump), and the DCM feedback uses its polygons."""
        if schedule is not self.schedule:
            last, swing, now = self.last_output, None, None
            if last is not None and last.feet.swing_side is not None:
                swing = (last.time, last.feet.swing_side)
                if self.time - last.time > 1.5 * self.control_period:  # the clock jumped
                    now = self.time
            late = getattr(self.generator, "late_adjustment", False)  # quintic re-plan
            self.reference.follow(schedule, swing, now, smooth=late)
            self.dcm_feedback.set_schedule(schedule)

    # ------------------------------------------------------------------ protocol
    def reset(self, q: np.ndarray | None = None) -> ControlOutput:
        """Start the walk from configuration ``q`` (default ``robot.q0``), at rest.

        The generator starts from the CoM of the robot at ``q``, at rest.

        Returns:
            The references at time 0 (``q_ref = q``, static feed-forward).
        """
        q = self.robot.q0 if q is None else np.asarray(q, dtype=float)
        if q.shape != (self.robot.model.nq,) or not np.all(np.isfinite(q)):
            nq = self.robot.model.nq
            msg = f"reset expects a finite configuration of size nq = {nq}, got shape {q.shape}."
            raise ConfigurationError(msg)
        self.q_ref = q.copy()
        self.faults = FaultMonitor(self.faults.max_fault_ticks)
        self.heading_hold = self.heading_hold and self.heading_hold.restarted()
        self.reference.restart()
        self.dcm_feedback.set_schedule(self.schedule)
        com = self.robot.compute_com(q)
        output = self.generator.reset(self.schedule, ComState(com[:2], np.zeros(2), np.zeros(2)))
        gait = self.reference.targets(output.time, output.com)
        feet, yaw = gait.feet, gait.torso_yaw
        targets = self.reference.ik_targets(gait, output.time)
        nv = self.robot.model.nv
        ik = IKResult(q.copy(), np.zeros(nv), self.ik.errors(q, targets), 0.0, True, "reset", 0, 0)
        joint_targets = self._joint_targets(q, ik.v, ik.v, output.zmp, np.zeros(2), feet)
        self.last_output = ControlOutput(
            time=output.time,
            q_ref=q.copy(),
            joint_targets=joint_targets,
            com_target=targets.com.copy(),
            zmp_command=output.zmp.copy(),
            dcm_error=np.zeros(2),
            generator=output,
            feet=feet,
            torso_yaw=yaw,
            ik=ik,
            generator_tick=0.0,
            ik_tick=0.0,
        )
        inputs = self._stabilizer_input(output.time, gait, None)
        for stabilizer in self._stabilizers:
            stabilizer.reset(inputs)
        return self.last_output

    def step(self, state: EstimatedState | ComState | None = None) -> ControlOutput:
        """One control tick: the references one control period later and the joint targets.

        Args:
            state: The robot's estimated state (:class:`~mpcwalk.estimation.estimated_state.
                EstimatedState`), a bare ComState, or None (kinematic robot, open loop).

        Raises:
            NotReset: :meth:`reset` was not called.
            ConfigurationError: ``state`` is none of these.
        """
        if self.q_ref is None or self.last_output is None:
            raise NotReset("WalkingController.step() was called before reset(q).")
        previous = self.last_output
        state = self.faults.measurement(state)  # non-finite: the last good estimate
        com_state = measured_com_state(state)  # raises on anything else than these types
        measured = com_state if self.feedback else None
        estimate = state if isinstance(state, EstimatedState) else None
        balance = self.balance
        generator_input, dcm_error = None, np.zeros(2)
        if measured is not None:
            offset = None if balance is None else balance.measured_com_offset(state)
            generator_input, dcm_error = self.dcm_feedback.observe(
                measured, estimate, previous, self.time, offset
            )
        turned = self.heading_hold and self.heading_hold.update(self.time, self.schedule, estimate)
        if turned:
            self.generator.schedule = turned
            self.follow_schedule(turned)
        start = time.perf_counter()
        output, failed = step_generator(self.generator, generator_input, dcm_error)
        generator_tick = time.perf_counter() - start
        self.faults.generator(failed)
        if output.schedule is not None and output.schedule is not self.schedule:
            self.follow_schedule(output.schedule)
        gait = self.reference.targets(output.time, output.com, output.flywheel)
        for stabilizer in self._stabilizers:  # the balance stabilizer first
            inputs = self._stabilizer_input(output.time, gait, estimate, dcm_error)
            gait = stabilizer.adjust_targets(inputs)
        feet, yaw = gait.feet, gait.torso_yaw
        targets = self.reference.ik_targets(gait, output.time)
        start = time.perf_counter()
        ik = ik_step(self.ik, self.q_ref, targets, self.control_period, previous.ik)
        ik_tick = time.perf_counter() - start
        q_next = self.faults.ik(ik.q_next, self.q_ref)  # non-finite: the reference holds
        if self.arm_swing is not None:  # a joint stage of its own after the IK
            q_next = self.arm_swing.apply(q_next, gait.com_xy, feet, yaw)
        self.q_ref = q_next
        shift = None
        if balance is not None and measured is not None:  # the balance's integral action
            shift = balance.zmp_shift(dcm_error, self.control_period)
        zmp_command = self.dcm_feedback.desired_zmp(output.time, output.zmp, dcm_error, shift)
        zmp_shift = zmp_command - output.zmp
        v_previous = previous.ik.v
        joint_targets = self._joint_targets(q_next, ik.v, v_previous, zmp_command, zmp_shift, feet)
        inputs = self._stabilizer_input(output.time, gait, estimate, dcm_error)
        for stabilizer in self._stabilizers:
            joint_targets = stabilizer.adjust_joint_targets(inputs, joint_targets)
        joint_targets = self.faults.joint_targets(joint_targets, previous.joint_targets)
        self.faults.end_tick(output.time)  # ControllerStopped after too many in a row
        self.last_output = ControlOutput(
            time=output.time,
            q_ref=q_next.copy(),
            joint_targets=joint_targets,
            com_target=targets.com.copy(),
            zmp_command=zmp_command,
            dcm_error=dcm_error,
            generator=output,
            feet=feet,
            torso_yaw=yaw,
            ik=ik,
            generator_tick=generator_tick,
            ik_tick=ik_tick,
            generator_failed=failed,
            com_offset=np.zeros(2) if balance is None else balance.com_offset,
            zmp_integral=np.zeros(2) if shift is None else np.array(shift),
        )
        return self.last_output
