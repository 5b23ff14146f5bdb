"""The balance stabilizer: what makes a position-controlled robot walk on a model that is wrong.

The proportional DCM feedback of the controller (:mod:`mpcwalk.control.dcm_feedback`) moves
the desired ZMP by ``k_p`` times the DCM error. This stabilizer adds the parts of the LIPM
walking controller of HRP-4 (Caron et al. 2019) and of the HRP-4C stabilizer (Kajita et al.
2010) that a biased model needs, each a small part of its own:

1. **integral action** on the DCM error (:class:`~mpcwalk.control.stabilizers.dcm_integrator.DcmIntegrator`),
   leaky and bounded: a constant ZMP bias (servos that sag, feed-forward torques computed
   with the wrong masses) no longer leaves a constant DCM error;
2. **ZMP distribution** between the feet (:class:`~mpcwalk.control.stabilizers.zmp_distribution.ZmpDistribution`):
   each foot's desired force and CoP in double support;
3. **foot damping** (:class:`~mpcwalk.control.stabilizers.foot_damping.FootDamping`): the ankle
   pitch and roll comply with the error between each foot's measured sole torque (its
   force/torque sensor) and its desired CoP;
4. **CoM offset estimate** (:class:`~mpcwalk.control.stabilizers.com_offset.ComOffsetEstimator`):
   the steady difference between the measured CoP and the planned ZMP, while
   the DCM error is small, is the offset of the robot's CoM from the model's; the IK's CoM
   target is moved by minus the estimate and the estimated CoM by plus it, so that the
   robot's CoM, not the model's, follows the plan;
5. **gravity's tilt**: on a ground sloping by ``theta`` (the estimated state's
   ``ground_tilt``, from the accelerometer), ``c'' = omega^2 (c - p) + g_xy`` makes the ZMP
   of a CoM at rest lie ``z_c tan(theta)`` downhill of it; the plan's CoM ``c'`` then stands
   for ``c - z_c tan(theta)``, a CoM offset known at once and added to the learnt one (it
   takes effect on the simulator's ground truth too, whose CoM is the robot's). Without it a
   4 deg tilt of the ground put `g1`'s ZMP 4.8 cm downhill, past its 3.5 cm half sole.

The controller (:class:`~mpcwalk.control.controller.WalkingController`, option ``balance``)
calls :meth:`BalanceStabilizer.measured_com_offset` before the DCM feedback,
:meth:`BalanceStabilizer.adjust_targets` before the IK, :meth:`BalanceStabilizer.zmp_shift`
for the desired ZMP, and :meth:`BalanceStabilizer.adjust_joint_targets` after the servo
feed-forward. Everything it reads comes in the typed
:class:`~mpcwalk.control.stabilizers.base.StabilizerInput` (the estimated state, its raw
force/torque readings, the references of the estimate's time); it never sees the controller.

The CoM offset estimate corrects a CoM the estimator computed with the model's masses. On
the simulator's ground truth (``source="oracle"``, for comparison) the CoM is the robot's:
the DCM feedback sees the offset itself and the estimate stays off (moving the IK's CoM
target while the measured CoM is not moved with it drags the generator's observer along:
on atlas-like the estimate then ran to its bound and the reference drifted 44 cm behind its
footsteps in 22 s).

The integral and the CoM offset estimate are kept in the heading frame of the plan (turned
by the torso yaw target): what they hold (a trunk heavier on one side, servos that sag, an
estimator's tilt) turns with the robot, and in the world frame a turning walk would drag a
stale bias round (paper M's turning walk on the estimator fell with world-frame states).

The CoM offset is learnt from the CoP error against the *planned* ZMP (the generator's,
without the DCM feedback): a compliant robot realises only part of the feedback's ZMP shift,
and against the desired ZMP that shortfall would read as a CoM offset the other way (the
estimate then pushed the CoM further off, on the small humanoid with a trunk CoM 1 cm to the
side). A CoM offset moves into the estimate, out of the DCM feedback and its integral.
"""

import dataclasses
import math

import numpy as np

from mpcwalk.control.gait_reference import GaitTargets
from mpcwalk.control.stabilizers.balance_options import BalanceOptions
from mpcwalk.control.stabilizers.base import Stabilizer, StabilizerInput
from mpcwalk.control.stabilizers.com_offset import ComOffsetEstimator, anchored_cop
from mpcwalk.control.stabilizers.dcm_integrator import DcmIntegrator
from mpcwalk.control.stabilizers.foot_damping import FootDamping
from mpcwalk.control.stabilizers.zmp_distribution import FootWrenchTargets, ZmpDistribution
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.models.com_state import ComState
from mpcwalk.robot.sensors import ForceTorqueReading

#: Generators whose closed loop includes the balance stabilizer by default (the QP
#: generators); the closed forms of the papers keep their own stabilizers unless asked.
BALANCED_GENERATORS = ("preview", "mpc", "mpc-steps", "mpc-hip", "static-qp")


class BalanceStabilizer(Stabilizer):
    """DCM integral action, ZMP distribution, foot damping and CoM offset estimate.

    Args:
        options: Gains and bounds (default :class:`BalanceOptions`); lengths left at None
            are set from the robot's sole on :meth:`reset`.

    Raises:
        ConfigurationError: ``options`` is not a BalanceOptions; on :meth:`reset`, a robot
            whose ankles the foot damping cannot find.
    """

    name = "balance"

    def __init__(self, options: BalanceOptions | None = None) -> None:
        options = BalanceOptions() if options is None else options
        if not isinstance(options, BalanceOptions):
            raise ConfigurationError(
                f"The balance stabilizer takes BalanceOptions, got {type(options).__name__}."
            )
        self.options = options
        self.integrator: DcmIntegrator | None = None
        self.offset_estimator: ComOffsetEstimator | None = None
        self.damping: FootDamping | None = None
        self.distribution: ZmpDistribution | None = None
        self.last_targets: FootWrenchTargets | None = None
        """Desired force and CoP of each foot of the last tick (None before a tick)."""
        self._shift = np.zeros(2)  # integral's ZMP shift of the last tick, world frame [m]
        self._yaw = 0.0  # heading of the plan [rad] (torso yaw target of the last tick)
        self._weight = 0.0  # robot's weight [N]
        self._min_force = 0.0  # [N]
        self._com_height = 0.0  # [m]
        self._tilt_offset = np.zeros(2)  # CoM offset of gravity's tilt, world frame [m]

    # ------------------------------------------------------------------ set-up
    def reset(self, inputs: StabilizerInput) -> None:
        """Build the parts for ``inputs.robot`` (its sole size and ankles); forget the
        integral, the foot rotations and the CoM offset."""
        robot = inputs.robot
        options = self.options.resolved(robot.sole_size)
        assert options.integral_limit is not None and options.com_offset_limit is not None
        assert options.com_offset_dcm_threshold is not None  # resolved() sets them
        self.integrator = DcmIntegrator(
            gain=options.integral_gain,
            leak_time=options.integral_leak_time,
            limit=options.integral_limit,
        )
        self.offset_estimator = None
        if options.com_offset_time_constant > 0.0 and options.com_offset_limit > 0.0:
            self.offset_estimator = ComOffsetEstimator(
                time_constant=options.com_offset_time_constant,
                limit=options.com_offset_limit,
                dcm_threshold=options.com_offset_dcm_threshold or np.inf,
            )
        self.damping = None
        if options.damping_gain > 0.0 and options.damping_max_offset > 0.0:
            self.damping = FootDamping(
                gain=options.damping_gain,
                time_constant=options.damping_time_constant,
                max_offset=options.damping_max_offset,
            )
            self.damping.calibrate(robot)
        self.distribution = ZmpDistribution(robot.sole_size, margin=0.1 * min(robot.sole_size))
        self.last_targets = None
        self._shift = np.zeros(2)
        self._yaw = float(inputs.targets.torso_yaw)
        self._weight = robot.total_mass * float(-robot.model.gravity.linear[2])
        self._min_force = 0.05 * self._weight  # feet pressing less are left out of the CoP
        self._com_height = float(robot.com_height)
        self._tilt_offset = np.zeros(2)

    # ------------------------------------------------------------------ the parts' outputs
    @property
    def com_offset(self) -> np.ndarray:
        """Offset of the robot's CoM from the plan's model, shape (2,), in [m]: the learnt
        estimate plus gravity's tilt's."""
        return self._learnt_offset() + self._tilt_offset

    def _learnt_offset(self) -> np.ndarray:
        if self.offset_estimator is None:
            return np.zeros(2)
        return self._to_world(self.offset_estimator.offset)

    def _observe_tilt(self, state: EstimatedState | ComState | None) -> None:
        """The CoM offset of gravity's tilt in ``state``: ``-z_c ground_tilt``."""
        if self.options.ground_tilt and isinstance(state, EstimatedState):
            self._tilt_offset = -self._com_height * np.asarray(state.ground_tilt, dtype=float)

    def _to_world(self, vector: np.ndarray) -> np.ndarray:
        """A heading-frame vector (2,) in the world frame."""
        c, s = math.cos(self._yaw), math.sin(self._yaw)
        x, y = float(vector[0]), float(vector[1])
        return np.array([c * x - s * y, s * x + c * y])

    def _to_heading(self, vector: np.ndarray) -> np.ndarray:
        """A world-frame vector (2,) in the heading frame."""
        c, s = math.cos(self._yaw), math.sin(self._yaw)
        x, y = float(vector[0]), float(vector[1])
        return np.array([c * x + s * y, -s * x + c * y])

    def measured_com_offset(self, state: EstimatedState | ComState | None) -> np.ndarray:
        """What to add to the CoM of ``state`` to get the robot's [m], shape (2,): the CoM
        offset estimate for a CoM computed with the model's masses (the estimator's, or a
        bare ComState), nothing for the simulator's ground truth (``source="oracle"``), whose
        CoM is the robot's already (see the module)."""
        self._observe_tilt(state)
        return self._tilt_offset if _is_oracle(state) else self.com_offset

    @property
    def integral_shift(self) -> np.ndarray:
        """ZMP shift of the integral action of the last tick, shape (2,), in [m]."""
        return self._shift.copy()

    def zmp_shift(self, dcm_error: np.ndarray, dt: float) -> np.ndarray:
        """Integral action: integrate the DCM error [m] over ``dt`` [s]; the ZMP shift [m],
        shape (2,), to add to the proportional feedback's desired ZMP."""
        if self.integrator is None:
            return np.zeros(2)
        self._shift = self._to_world(self.integrator.update(self._to_heading(dcm_error), dt))
        return self._shift.copy()

    # ------------------------------------------------------------------ stabilizer hooks
    def adjust_targets(self, inputs: StabilizerInput) -> GaitTargets:
        """Update the CoM offset estimate from the measured CoP (anchored to the planned
        feet); the IK's CoM target moved by minus the offset (the estimate and gravity's
        tilt's; the tilt's alone on the ground truth or without the estimate)."""
        state, estimator, targets = inputs.state, self.offset_estimator, inputs.targets
        self._yaw = float(targets.torso_yaw)
        self._observe_tilt(state)
        learnt = estimator is not None and not _is_oracle(state)  # the ground truth: no
        if estimator is not None and learnt and state is not None:
            contacts = (state.left_foot.in_contact, state.right_foot.in_contact)
            cop = anchored_cop(state.sensors.wrenches, contacts, targets.feet, self._min_force)
            planned = inputs.zmp_reference if inputs.zmp_planned is None else inputs.zmp_planned
            if cop is not None:
                error = self._to_heading(cop - planned)
                estimator.update(error, np.zeros(2), inputs.dcm_error, inputs.control_period)
        offset = self.com_offset if learnt else self._tilt_offset
        if not learnt and not (offset[0] or offset[1]):
            return targets
        com_xy = np.asarray(targets.com_xy) - offset  # (dataclasses.replace is slow)
        return GaitTargets(targets.feet, com_xy, targets.torso_yaw, targets.flywheel)

    def adjust_joint_targets(
        self, inputs: StabilizerInput, joint_targets: np.ndarray
    ) -> np.ndarray:
        """Servo targets plus the foot damping's ankle offsets (the rotations leak back to
        zero without an estimated state)."""
        if self.distribution is None:
            return joint_targets
        feet = inputs.targets.feet
        self.last_targets = self.distribution.distribute(inputs.zmp_reference, feet, self._weight)
        damping, state = self.damping, inputs.state
        if damping is None:
            return joint_targets
        local = np.zeros((2, 2))  # each foot's desired CoP in its (planned) sole frame
        for index, foot in enumerate((feet.left, feet.right)):
            c, s = math.cos(foot.yaw), math.sin(foot.yaw)
            dx, dy = self.last_targets.cops[index] - foot.position[:2]
            local[index] = (c * dx + s * dy, -s * dx + c * dy)
        lifted = (not feet.left.in_contact, not feet.right.in_contact)
        if state is None:  # no measurement: the rotations only leak
            zero = ForceTorqueReading(np.zeros(3), np.zeros(3))
            damping.update((zero, zero), local, (False, False), inputs.control_period, lifted)
        else:
            contacts = (
                state.left_foot.in_contact and feet.left.in_contact,
                state.right_foot.in_contact and feet.right.in_contact,
            )
            damping.update(state.sensors.wrenches, local, contacts, inputs.control_period, lifted)
        offsets = damping.joint_offsets()
        out = np.array(joint_targets, dtype=float, copy=True)
        out[damping.joint_indices.ravel()] += offsets.ravel()  # four distinct joints
        return out


def make_balance(
    option: BalanceOptions | dict | bool | None, generator: str
) -> BalanceStabilizer | None:
    """The balance stabilizer a controller's ``balance`` option asks for: its options (a
    :class:`BalanceOptions` or a table of its fields, as a walk specification gives them),
    True (the defaults), False (none), or None (the default of the generator called
    ``generator``: on for :data:`BALANCED_GENERATORS`).

    Raises:
        ConfigurationError: Anything else.
    """
    if option is None:
        option = generator in BALANCED_GENERATORS
    if option is False:
        return None
    if option is True:
        return BalanceStabilizer()
    if isinstance(option, BalanceOptions):
        return BalanceStabilizer(option)
    if isinstance(option, dict):  # a table of a walk specification
        names = {item.name for item in dataclasses.fields(BalanceOptions)}
        unknown = sorted(set(option) - names)
        if unknown:
            raise ConfigurationError(
                f"balance has no option {', '.join(map(repr, unknown))}; its options are "
                f"{', '.join(sorted(names))}."
            )
        return BalanceStabilizer(BalanceOptions(**option))
    raise ConfigurationError(
        "balance must be BalanceOptions, True, False or None (the generator's default), "
        f"got {option!r}."
    )


def _is_oracle(state: EstimatedState | ComState | None) -> bool:
    """Whether ``state`` is the simulator's ground truth (its CoM is the robot's)."""
    return isinstance(state, EstimatedState) and state.source == "oracle"
