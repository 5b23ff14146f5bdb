"""Hand-built sensor readings and stabilizer inputs: stabilizers tested without a controller
or a simulator."""

import numpy as np

from mpcwalk.control.gait_reference import GaitTargets
from mpcwalk.control.stabilizers.base import StabilizerInput
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.swing_foot import FeetState, FootState, SwingFootTrajectory
from mpcwalk.robot.sensors import FootContact, ImuReading, Measurements

_ZERO3 = np.zeros(3)


def foot(position, in_contact: bool = True, yaw: float = 0.0) -> FootState:
    """A foot at rest at ``position`` [m]."""
    return FootState(np.array(position, dtype=float), yaw, _ZERO3, 0.0, in_contact)


def measurements(
    *,
    com=(0.0, 0.0, 0.0),
    sole_positions=((0.0, 0.05, 0.0), (0.0, -0.05, 0.0)),
    sole_rotations=None,
    gyro=(0.0, 0.0, 0.0),
    quaternion=(1.0, 0.0, 0.0, 0.0),
    roll: float = 0.0,
    pitch: float = 0.0,
    yaw: float = 0.0,
    nb_joints: int = 0,
) -> Measurements:
    """Readings of a robot standing still on both feet, with the given fields."""
    contact = FootContact(_ZERO3, _ZERO3, np.full(3, np.nan), True, 4)
    imu = ImuReading(
        np.array(gyro, float),
        np.array([0.0, 0.0, 9.81]),
        np.array(quaternion, float),
        roll,
        pitch,
        yaw,
    )
    rotations = np.array([np.eye(3), np.eye(3)]) if sole_rotations is None else sole_rotations
    return Measurements(
        imu=imu,
        left_foot=contact,
        right_foot=contact,
        cop=np.zeros(3),
        has_cop=True,
        com=np.array(com, dtype=float),
        com_velocity=np.zeros(3),
        joint_positions=np.zeros(nb_joints),
        joint_velocities=np.zeros(nb_joints),
        sole_positions=np.array(sole_positions, dtype=float),
        sole_rotations=np.array(rotations, dtype=float),
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
    sensors: Measurements | None = None,
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
        measurements=sensors,
    )
