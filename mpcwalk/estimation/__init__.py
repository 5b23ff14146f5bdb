"""State estimation from the robot's sensors: IMU, joint encoders, foot force/torque sensors.

:class:`Estimator` turns each tick's :class:`~mpcwalk.robot.sensors.SensorReadings` into an
:class:`EstimatedState` (base pose and velocity, CoM, its velocity and the DCM, contacts,
sole poses), composing :class:`AttitudeFilter` (IMU orientation), :class:`ContactDetector`
(contacts with hysteresis), :class:`JointVelocityFilter` (encoder velocities) and
:class:`BaseEstimator` (base position and velocity from the leg kinematics and the
accelerometer).
"""

from mpcwalk.estimation.attitude_filter import AttitudeFilter
from mpcwalk.estimation.base_estimator import BaseEstimator
from mpcwalk.estimation.contact_detector import ContactDetector
from mpcwalk.estimation.estimated_state import SOURCES, EstimatedState
from mpcwalk.estimation.estimator import Estimator
from mpcwalk.estimation.joint_velocity_filter import JointVelocityFilter

__all__ = [
    "SOURCES",
    "AttitudeFilter",
    "BaseEstimator",
    "ContactDetector",
    "EstimatedState",
    "Estimator",
    "JointVelocityFilter",
]
