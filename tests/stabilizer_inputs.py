"""Hand-built estimated states and stabilizer inputs: stabilizers tested without a controller,
an estimator or a simulator."""

import numpy as np
import pinocchio as pin

from mpcwalk.control.gait_reference import GaitTargets
from mpcwalk.control.stabilizers.base import StabilizerInput
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.swing_foot import FeetState, FootState, SwingFootTrajectory
from mpcwalk.robot.sensors import FootContact, ForceTorqueReading, ImuReading, SensorReadings

_ZERO3 = np.zeros(3)


def foot(position, in_contact: bool = True, yaw: float = 0.0) -> FootState:
    """A foot at rest at ``position`` [m]."""
    return FootState(np.array(position, dtype=float), yaw, _ZERO3, 0.0, in_contact)


def estimated_state(
    *,
    com=(0.0, 0.0, 0.0),
    com_velocity=(0.0, 0.0, 0.0),
    sole_positions=((0.0, 0.05, 0.0), (0.0, -0.05, 0.0)),
    sole_rotations=None,
    gyro=(0.0, 0.0, 0.0),
    base_rotation=None,
    q=None,
    wrenches=None,
    in_contact=(True, True),
    cop=(0.0, 0.0, 0.0),
    omega: float = 6.5,
    nb_joints: int = 0,
) -> EstimatedState:
    """The estimate of a robot standing still on both feet, with the given fields.

    ``wrenches`` are the left and right (force, torque) readings in the sole frames (zero by
    default); ``base_rotation`` (default identity) sets the roll, pitch and yaw; ``q`` (default
    the base at the origin with ``base_rotation``, joints at 0) the configuration.
    """
    rotation = np.eye(3) if base_rotation is None else np.asarray(base_rotation, dtype=float)
    roll, pitch, yaw = (float(a) for a in pin.rpy.matrixToRpy(rotation))
    if q is None:
        quaternion = pin.Quaternion(rotation).coeffs()  # x, y, z, w
        q = np.concatenate([np.zeros(3), quaternion, np.zeros(nb_joints)])
    q = np.asarray(q, dtype=float)
    if wrenches is None:
        wrenches = ((_ZERO3, _ZERO3), (_ZERO3, _ZERO3))
    readings = [ForceTorqueReading(np.array(f, float), np.array(t, float)) for f, t in wrenches]
    sensors = SensorReadings(
        time=0.0,
        imu=ImuReading(np.array(gyro, float), np.array([0.0, 0.0, 9.81])),
        joint_positions=q[7:].copy(),
        left_wrench=readings[0],
        right_wrench=readings[1],
    )
    rotations = np.array([np.eye(3), np.eye(3)]) if sole_rotations is None else sole_rotations
    rotations = np.array(rotations, dtype=float)
    positions = np.array(sole_positions, dtype=float)
    feet = [
        FootContact(
            rotations[i] @ readings[i].force,
            rotations[i] @ readings[i].torque,
            positions[i] if in_contact[i] else np.full(3, np.nan),
            bool(in_contact[i]),
        )
        for i in range(2)
    ]
    com, com_velocity = np.array(com, dtype=float), np.array(com_velocity, dtype=float)
    return EstimatedState(
        time=0.0,
        source="estimator",
        sensors=sensors,
        q=q,
        v=np.zeros(len(q) - 1),
        base_position=q[:3].copy(),
        base_rotation=rotation,
        base_linear_velocity=np.zeros(3),
        roll=roll,
        pitch=pitch,
        yaw=yaw,
        left_foot=feet[0],
        right_foot=feet[1],
        cop=np.array(cop, dtype=float),
        has_cop=any(in_contact),
        com=com,
        com_velocity=com_velocity,
        dcm=com[:2] + com_velocity[:2] / omega,
        joint_positions=q[7:].copy(),
        joint_velocities=np.zeros(len(q) - 7),
        sole_positions=positions,
        sole_rotations=rotations,
    )


def stabilizer_input(
    robot,
    schedule: ContactSchedule,
    *,
    t: float = 0.0,
    feet: FeetState | None = None,
    com_xy=None,
    torso_yaw: float = 0.0,
    q_ref=None,
    com_reference=None,
    zmp_reference=(0.0, 0.0),
    state: EstimatedState | None = None,
    dcm_error=(0.0, 0.0),
    control_period: float = 0.01,
) -> StabilizerInput:
    """A stabilizer input built by hand: the schedule's feet at ``t`` unless given, the robot
    at ``q0`` unless ``q_ref`` is given."""
    if feet is None:
        feet = SwingFootTrajectory(schedule, 0.04).foot_poses(t)
    q_ref = robot.q0 if q_ref is None else np.asarray(q_ref, dtype=float)
    com = robot.compute_com(q_ref) if com_reference is None else np.asarray(com_reference)
    return StabilizerInput(
        time=t,
        control_period=control_period,
        robot=robot,
        schedule=schedule,
        targets=GaitTargets(feet, np.array(com[:2] if com_xy is None else com_xy), torso_yaw),
        q_ref=q_ref,
        com_reference=com,
        zmp_reference=np.array(zmp_reference, dtype=float),
        state=state,
        dcm_error=np.array(dcm_error, dtype=float),
    )
