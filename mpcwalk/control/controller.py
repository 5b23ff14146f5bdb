"""WalkingController: one control tick from footsteps to joint targets.

One tick composes the parts of the walking pipeline (DESIGN.md, section 1):

1. the pattern generator advances by one control period and returns the CoM reference of
   the next tick;
2. the swing-foot and torso-yaw trajectories of the gait core (paper M eq. 19-23) give the
   feet poses and the torso yaw at that time;
3. the whole-body IK moves the controller's own reference configuration ``q_ref`` one step
   towards these targets (CoM at the robot's CoM height, soles flat, torso upright at the
   yaw, posture): the robot is position controlled, the IK is its kinematic model;
4. the servo feed-forward (:class:`~mpcwalk.control.servo_feedforward.ServoFeedforward`) adds to the joint
   angles the offsets ``tau / kp`` that make compliant position servos carry the reference
   motion, with the contact wrench at the desired ZMP.

Closed loop (``feedback=True`` and a measurement), see :mod:`mpcwalk.control.dcm_feedback`: the
measured CoM, anchored to the measured feet, goes to the generator through an observer
(``observer_gain`` times its error; closed forms ignore it), and the desired ZMP of step 4 is
the generator's plus ``dcm_gain`` times the error of the divergent component of motion.
The kinematic reference stays the generator's, so that the servos keep pulling the robot
towards it.
"""

import time
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from mpcwalk.control.dcm_feedback import DcmFeedback
from mpcwalk.control.servo_feedforward import ServoFeedforward
from mpcwalk.exceptions import ConfigurationError, NoSolutionFound, NotReset
from mpcwalk.gait.arm_swing import ArmSwing
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.swing_foot import FeetState, SwingFootTrajectory
from mpcwalk.generators.pattern_generator import (
    ComState,
    GeneratorOutput,
    PatternGenerator,
    SolveInfo,
)
from mpcwalk.ik.targets import IKResult, IKTargets
from mpcwalk.ik.whole_body_ik import WholeBodyIK
from mpcwalk.models.cart_table import CartTable

DEFAULT_STEP_HEIGHT = 0.04
"""Swing-foot height [m] when neither the caller nor the robot's ``[gait]`` preset gives one
(paper M, Table 1)."""

_HEIGHT_TOLERANCE = 1e-6  # [m] generator CoM height vs robot CoM height


@dataclass(frozen=True)
class ControlOutput:
    """What one control tick produced.

    Attributes:
        time: Time of the references [s] (one control period after the measurement).
        q_ref: Reference configuration (IK) after this tick, shape (nq,).
        joint_targets: Position-servo targets, shape (nq - 7,), in [rad]
            (``robot.joint_names`` order): ``q_ref[7:]`` plus the servo feed-forward.
        com_target: CoM target of the IK, shape (3,), in [m].
        zmp_command: Desired ZMP realised by the feed-forward (the generator's ZMP plus the
            DCM feedback), shape (2,), in [m].
        dcm_error: Measured minus reference DCM, shape (2,), in [m] (zero in open loop).
        generator: CoM/ZMP reference of the pattern generator.
        feet: Feet poses and velocities at ``time``.
        torso_yaw: Torso yaw target [rad].
        ik: Result of the IK step (task errors: those of the previous ``q_ref``).
        generator_tick: Wall time of the generator step [s].
        ik_tick: Wall time of the IK step [s].
        generator_failed: The generator reported a failed solve this tick (its fallback, or
            the controller's, was used).
    """

    time: float
    q_ref: np.ndarray
    joint_targets: np.ndarray
    com_target: np.ndarray
    zmp_command: np.ndarray
    dcm_error: np.ndarray
    generator: GeneratorOutput
    feet: FeetState
    torso_yaw: float
    ik: IKResult
    generator_tick: float
    ik_tick: float
    generator_failed: bool = False


def as_com_state(measurement) -> ComState | None:
    """CoM state of a measurement: a SimState, Measurements, ComState, or None.

    Raises:
        ConfigurationError: Anything else.
    """
    if measurement is None or isinstance(measurement, ComState):
        return measurement
    measurements = getattr(measurement, "measurements", measurement)
    com_state = getattr(measurements, "com_state", None)
    if com_state is None:
        raise ConfigurationError(
            f"A measurement must be a SimState, Measurements or ComState, got "
            f"{type(measurement).__name__}."
        )
    return com_state()


class WalkingController:
    """Generator + swing-foot/torso trajectories + whole-body IK + servo feed-forward.

    Args:
        robot: The robot (:func:`mpcwalk.robot.loading.load_robot`).
        generator: Pattern generator whose LIPM has the robot's CoM height and whose control
            period is ``control_period``; :meth:`for_robot` builds one by name.
        schedule: Footsteps and contact phases of the walk.
        ik: Whole-body IK of ``robot`` (default: ``WholeBodyIK(robot)``).
        swing_profile: ``"cosine"`` (paper M) or ``"ctraj"`` (paper A's quintic Cartesian
            lift and lower), see :class:`~mpcwalk.gait.swing_foot.SwingFootTrajectory`.
        step_height: Swing-foot height [m]; None: the preset's ``[gait] step_height``, else
            :data:`DEFAULT_STEP_HEIGHT`.
        feedback: Close the loop on the measured CoM when a measurement is given.
        observer_gain: Share in [0, 1] of the measured CoM error given to the generator
            (default: the generator's :attr:`~PatternGenerator.observer_gain`; see
            :mod:`mpcwalk.control.dcm_feedback` for what it costs).
        dcm_gain: ZMP shift per metre of DCM error, >= 0 (> 1 makes the error decay).
        zmp_margin: The desired ZMP with the DCM feedback is kept this far [m] inside the
            planned support polygon (default: a tenth of the sole width).
        servo_feedforward: Add the feed-forward offsets of compliant position servos.
        control_period: Duration of one tick [s].
        stabilizer: A :class:`~mpcwalk.control.stabilizers.Stabilizer` correcting the IK targets and
            the servo targets from the measurement, or None.
        arm_swing: Paper M's arm movement factor s (eq. 24-25; 0.8 in the paper): the
            shoulder pitch joints swing each hand with the opposite foot. 0 keeps the arms in
            their nominal posture.

    A footstep-adaptive generator may move the future footsteps: when its output carries a
    new schedule (:attr:`GeneratorOutput.schedule`), the controller follows it from that
    tick on (swing-foot landing, support polygons of the DCM feedback).

    Raises:
        ConfigurationError: A CoM height or control period that does not match, a gain out
            of range, or a schedule that is not a ContactSchedule.
    """

    def __init__(
        self,
        robot,
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
        stabilizer=None,
        swing_profile: str = "cosine",
        arm_swing: float = 0.0,
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
        if abs(generator.lipm.com_height - robot.com_height) > _HEIGHT_TOLERANCE:
            raise ConfigurationError(
                f"The generator's LIPM has a CoM height of {generator.lipm.com_height:g} m but "
                f"robot '{robot.name}' walks with {robot.com_height:g} m; build the generator "
                "with lipm=LIPM(com_height=robot.com_height) (WalkingController.for_robot does)."
            )
        if not isinstance(schedule, ContactSchedule):
            raise ConfigurationError(
                f"schedule must be a ContactSchedule, got {type(schedule).__name__}."
            )
        if step_height is None:
            step_height = robot.preset.gait.get("step_height", DEFAULT_STEP_HEIGHT)
        self.robot = robot
        self.generator = generator
        self.schedule = schedule
        self.ik = ik if ik is not None else WholeBodyIK(robot)
        self.trajectory = SwingFootTrajectory(schedule, step_height, swing_profile)
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
        self.arm_swing = ArmSwing(robot, arm_swing) if arm_swing else None
        self._initial_schedule = schedule
        self.omega = float(generator.lipm.omega)
        self.cart_table = CartTable(generator.lipm, self.control_period)
        self.nb_generator_failures = 0
        """Ticks whose generator reported a failed solve (or raised NoSolutionFound)."""
        self.q_ref: np.ndarray | None = None
        self.last_output: ControlOutput | None = None

    @classmethod
    def for_robot(
        cls,
        robot,
        generator: str,
        schedule: ContactSchedule,
        *,
        control_period: float = 0.01,
        generator_options: dict | None = None,
        **options,
    ) -> "WalkingController":
        """Controller with the generator called ``generator`` on the robot's LIPM.

        ``generator_options`` go to the generator, over what the generator takes from the
        robot (:meth:`PatternGenerator.robot_options`), ``options`` to the controller.
        """
        from mpcwalk.generators import generator_class
        from mpcwalk.models.lipm import LIPM

        cls_ = generator_class(generator)
        pattern = cls_(
            lipm=LIPM(com_height=robot.com_height),
            control_period=control_period,
            **{**cls_.robot_options(robot), **(generator_options or {})},
        )
        return cls(robot, pattern, schedule, control_period=control_period, **options)

    @property
    def time(self) -> float:
        """Time of the last references [s]."""
        return self.generator.time

    @property
    def done(self) -> bool:
        """Whether the schedule is over."""
        return self.generator.done

    # ------------------------------------------------------------------ helpers
    def _targets(self, com_xy: np.ndarray, t: float, feet: FeetState, yaw: float) -> IKTargets:
        ground = float(np.mean([foot.position[2] for foot in self.schedule.stance(t).values()]))
        c, s = np.cos(yaw), np.sin(yaw)
        torso = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        com = np.array([com_xy[0], com_xy[1], ground + self.robot.com_height])
        return IKTargets(com, feet.left.transform, feet.right.transform, torso)

    @staticmethod
    def support_weights(zmp: np.ndarray, feet: FeetState) -> tuple[float, float]:
        """Share of the weight on the left and right feet: all on the support foot in single
        support, else by the position of ``zmp`` along the segment between the feet."""
        if not feet.left.in_contact:
            return 0.0, 1.0
        if not feet.right.in_contact:
            return 1.0, 0.0
        left, right = feet.left.position[:2], feet.right.position[:2]
        axis = left - right
        share = float(np.clip(np.dot(zmp - right, axis) / np.dot(axis, axis), 0.0, 1.0))
        return share, 1.0 - share

    def _step_generator(self, measured: ComState | None) -> tuple[GeneratorOutput, bool]:
        """Generator step that never raises NoSolutionFound: (output, failed)."""
        try:
            output = self.generator.step(measured)
        except NoSolutionFound as error:
            # The generator gave up after its own fallback ticks: continue the last reference
            # with zero jerk for this tick and move the generator's clock.
            previous = self.last_output.generator
            state = np.vstack([previous.com, previous.com_velocity, previous.com_acceleration])
            state = self.cart_table.integrate(state, np.zeros(2), self.control_period)
            self.generator.tick += 1
            zmp = state[0] - state[2] / self.omega**2
            info = SolveInfo(
                False, getattr(error, "solver", ""), "controller fallback", fallback=True
            )
            output = GeneratorOutput(
                self.generator.time,
                state[0],
                state[1],
                state[2],
                zmp,
                self.generator.lipm.com_height,
                None,
                info,
            )
            return output, True
        return output, output.solve is not None and not output.solve.success

    def _joint_targets(
        self,
        ik: IKResult,
        previous_v: np.ndarray,
        zmp: np.ndarray,
        zmp_shift: np.ndarray,
        feet: FeetState,
    ) -> np.ndarray:
        """IK joint angles plus the servo feed-forward of the reference motion."""
        joint_targets = ik.q_next[7:].copy()
        if self.feedforward is None:
            return joint_targets
        acceleration = (ik.v - previous_v) / self.control_period
        if np.any(zmp_shift):  # DCM feedback: accelerate the whole body away from the shift
            rotation = pin.Quaternion(ik.q_next[3:7]).normalized().matrix()
            shift = -(self.omega**2) * np.array([zmp_shift[0], zmp_shift[1], 0.0])
            acceleration[0:3] += rotation.T @ shift
        weights = self.support_weights(zmp, feet)
        return joint_targets + self.feedforward.compute_offsets(
            ik.q_next, weights, ik.v, acceleration
        )

    def follow_schedule(self, schedule: ContactSchedule) -> None:
        """Follow ``schedule`` from now on (a footstep-adaptive generator moved footsteps):
        the swing foot lands on its footsteps, from where it is now (no jump), and the DCM
        feedback uses its polygons."""
        if schedule is not self.schedule:
            self._use_schedule(schedule, continue_swing=True)

    def _use_schedule(self, schedule: ContactSchedule, continue_swing: bool) -> None:
        previous = self.trajectory
        self.schedule = schedule
        self.trajectory = SwingFootTrajectory(schedule, previous.step_height, previous.profile)
        self.dcm_feedback.set_schedule(schedule)
        if continue_swing and self.last_output is not None:  # the swing goes on from its pose
            t = self.last_output.time
            side = self.last_output.feet.swing_side
            if side is not None:
                self.trajectory.restart_swing(t, previous.foot_poses(t)[side])

    # ------------------------------------------------------------------ protocol
    def reset(self, q: np.ndarray | None = None) -> ControlOutput:
        """Start the walk from configuration ``q`` (default ``robot.q0``), at rest.

        The generator starts from the CoM of the robot at ``q``, at rest.

        Returns:
            The references at time 0 (``q_ref = q``, static feed-forward).
        """
        q = self.robot.q0 if q is None else np.asarray(q, dtype=float)
        if q.shape != (self.robot.model.nq,) or not np.all(np.isfinite(q)):
            raise ConfigurationError(
                f"reset expects a finite configuration of size nq = {self.robot.model.nq}, got "
                f"shape {q.shape}."
            )
        self.q_ref = q.copy()
        self.nb_generator_failures = 0
        self._use_schedule(self._initial_schedule, continue_swing=False)
        if self.stabilizer is not None:
            self.stabilizer.reset(self)
        com = self.robot.compute_com(q)
        output = self.generator.reset(self.schedule, ComState(com[:2], np.zeros(2), np.zeros(2)))
        feet = self.trajectory.foot_poses(output.time)
        yaw = float(self.trajectory.torso_yaw(output.time))
        targets = self._targets(output.com, output.time, feet, yaw)
        nv = self.robot.model.nv
        ik = IKResult(q.copy(), np.zeros(nv), self.ik.errors(q, targets), 0.0, True, "reset", 0, 0)
        joint_targets = self._joint_targets(ik, np.zeros(nv), output.zmp, np.zeros(2), feet)
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
        return self.last_output

    def step(self, measurement=None) -> ControlOutput:
        """One control tick.

        Args:
            measurement: The robot's state at the current time (a SimState; Measurements or
                a ComState lack the sole poses, so the CoM is not anchored to the feet), or
                None (kinematic robot, open loop).

        Returns:
            The references one control period later and the joint targets.

        Raises:
            NotReset: :meth:`reset` was not called.
        """
        if self.q_ref is None or self.last_output is None:
            raise NotReset("WalkingController.step() was called before reset(q).")
        previous = self.last_output
        measured = as_com_state(measurement) if self.feedback else None
        dcm_error = np.zeros(2)
        generator_input = None
        if measured is not None:
            weights = self.support_weights(previous.zmp_command, previous.feet)
            measured = self.dcm_feedback.anchor(measured, measurement, self.time, weights)
            generator_input, dcm_error = self.dcm_feedback.compare(measured, previous.generator)
            self.generator.observe_dcm_error(dcm_error)
        start = time.perf_counter()
        output, failed = self._step_generator(generator_input)
        generator_tick = time.perf_counter() - start
        self.nb_generator_failures += int(failed)
        if output.schedule is not None and output.schedule is not self.schedule:
            self.follow_schedule(output.schedule)
        feet = self.trajectory.foot_poses(output.time)
        yaw = float(self.trajectory.torso_yaw(output.time))
        com_xy = output.com
        if self.stabilizer is not None:
            feet, com_xy, yaw = self.stabilizer.adjust_targets(
                self, output.time, feet, com_xy, yaw, measurement
            )
        targets = self._targets(com_xy, output.time, feet, yaw)
        start = time.perf_counter()
        ik = self.ik.solve(self.q_ref, targets, self.control_period)
        ik_tick = time.perf_counter() - start
        if self.arm_swing is not None:
            ik.q_next[7 + self.arm_swing.joint_indices] = self.arm_swing.joint_angles(
                com_xy, feet.left.position, feet.right.position, yaw
            )
        self.q_ref = ik.q_next
        zmp_command = self.dcm_feedback.desired_zmp(output.time, output.zmp, dcm_error)
        zmp_shift = zmp_command - output.zmp
        joint_targets = self._joint_targets(ik, previous.ik.v, zmp_command, zmp_shift, feet)
        if self.stabilizer is not None:
            joint_targets = self.stabilizer.adjust_joint_targets(
                self, output.time, joint_targets, feet, measurement
            )
        self.last_output = ControlOutput(
            time=output.time,
            q_ref=ik.q_next.copy(),
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
        )
        return self.last_output
