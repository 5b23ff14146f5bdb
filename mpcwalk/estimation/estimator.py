"""The floating-base estimator: the robot's state from its IMU, encoders and foot sensors.

One :meth:`Estimator.update` per control tick composes:

1. the joint velocities, filtered finite differences of the encoders
   (:class:`~mpcwalk.estimation.joint_velocity_filter.JointVelocityFilter`);
2. one Pinocchio pass on the robot with its base at the origin (``centerOfMass`` with the
   joint velocities, then ``updateFramePlacements``): the CoM, the soles and the IMU relative
   to the base, and their velocities due to the joints;
3. the IMU's orientation propagated with the gyroscope
   (:class:`~mpcwalk.estimation.attitude_filter.AttitudeFilter`), turned into the base's
   through the IMU's mounting (the frame ``imu`` of the robot description, moving with the
   joints between the base and the IMU's link: Talos's IMU sits upside down in its torso);
4. the feet's contacts (:class:`~mpcwalk.estimation.contact_detector.ContactDetector`);
5. the base position and velocity (:class:`~mpcwalk.estimation.base_estimator.BaseEstimator`):
   the accelerometer, less gravity as it is read in the world (item 8), fused with the leg
   kinematics of the feet in contact;
6. the tilt corrected with the accelerometer, from which the IMU's linear acceleration (the
   time derivative of its velocity as the legs give it) is removed first: a walking robot's
   accelerometer reads its sway as much as gravity;
7. the world quantities: the CoM and its velocity, the DCM, the sole poses, each foot's
   wrench and CoP rotated from its sole frame, the overall CoP (paper M eq. 31);
8. gravity's tilt in the world (``ground_tilt``): while the loaded soles set roll and pitch
   (the world is the soles' frame), a ground that slopes tilts gravity in that frame, and
   the accelerometer reads it (:mod:`mpcwalk.estimation.gravity_tilt`). With a terrain map
   the world is the map's, gravity's own: no tilt.

The estimator holds a :class:`~mpcwalk.robot.robot.Robot` (its Pinocchio model) and is fed
:class:`~mpcwalk.robot.sensors.SensorReadings` only: it never sees a simulator.
"""

import math

import numpy as np
import pinocchio as pin

from mpcwalk._checks import checked_number
from mpcwalk.estimation.attitude_filter import AttitudeFilter, tilt_from_accelerometer
from mpcwalk.estimation.base_estimator import BaseEstimator
from mpcwalk.estimation.contact_detector import ContactDetector
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.estimation.gravity_tilt import GravityTilt
from mpcwalk.estimation.joint_velocity_filter import JointVelocityFilter
from mpcwalk.estimation.kinematics import BaseKinematics, KinematicsPass, cross_rows, rpy_of
from mpcwalk.estimation.reset_checks import checked_reset_inputs
from mpcwalk.exceptions import ConfigurationError, NotReset
from mpcwalk.robot.robot import Robot
from mpcwalk.robot.sensors import SensorReadings
from mpcwalk.terrain import Terrain, sole_tilt

MIN_VELOCITY_NOISE = 0.02
"""Smallest default velocity noise of the leg kinematics [m/s] (the contacts' compliance and
the joints' backlash when the encoders are exact)."""


class Estimator:
    """State of a walking robot estimated from its sensors only.

    Args:
        robot: The robot (its Pinocchio model, sole and IMU frames, weight, CoM height).
        control_period: Nominal time between two readings [s]; the time between readings
            is taken from their time stamps, capped at 5 periods.
        attitude_gain: Accelerometer correction gain of the attitude filter [rad/s] (the
            tilt error decays with the time constant ``1 / attitude_gain``).
        attitude_integral_gain: Gyroscope bias integral gain of the attitude filter
            [rad/s^2].
        bias_window: Time [s] after :meth:`reset` during which the robot stands still and
            the heading part of the gyroscope's bias is averaged (0: none; a walk that starts
            moving at once must keep 0).
        foot_tilt_gain: Gain [rad/s] pulling roll and pitch towards those the leg
            kinematics give from the loaded feet, flat on the floor (``flat_ground``), while
            their CoP is away from the sole's edges: it bounds the tilt error an
            accelerometer bias leaves (b / g: 0.3 deg for 5 mg, 1 cm of CoM at 1 m); 0: the
            accelerometer alone.
        contact_on_fraction: Normal force (fraction of the weight) above which a foot comes
            into contact.
        contact_off_fraction: Normal force (fraction of the weight) below which a foot leaves
            contact.
        joint_velocity_cutoff: Cut-off frequency of the joint velocity low-pass [Hz].
        acceleration_noise: Process noise of the base Kalman filter [m/s^2].
        position_noise: Base position noise of one loaded foot's leg kinematics [m].
        velocity_noise: Base velocity noise of one loaded foot's leg kinematics [m/s]; None
            for the encoders' quantisation differentiated over one control period through
            a lever of twice the CoM height, ``2 h encoder_resolution / control_period``,
            and at least 0.02 m/s (0.24 m/s for the small humanoid's servo encoders, 0.02
            m/s for the large robots' 17-bit encoders: on these the legs are trusted more
            than the accelerometer, on those less).
        encoder_resolution: The joint encoders' quantisation step [rad], from the robot's
            data sheet (the sensor model's), for the default ``velocity_noise``.
        anchor_load_fraction: Load (fraction of the weight) from which a foot that touched
            down is anchored (0.5: a symmetric handover between the feet).
        flat_ground: The feet touch down at the height of the first stance (a flat floor);
            False takes their heights from the leg kinematics (stairs, uneven ground).
        terrain: The ground the robot's map holds (stairs, slopes, stones; None or a flat
            terrain: the floor): the feet are anchored at its height under them, and the
            loaded soles pull roll and pitch towards the tilt of the tops they stand on
            (its normals) instead of the vertical.
        tilt_time_constant: Time constant [s] of the low-pass on the specific force that
            follows gravity's tilt in the world after the start's average.
        tilt_deadband_deg: Gravity tilt [deg] read as a level floor (the tilt is ramped in
            from it to 1.25 times it; 0: none). Without feet setting the attitude
            (``foot_tilt_gain`` 0, ``flat_ground`` False) the world is gravity's and the tilt
            zero.

    Raises:
        ConfigurationError: A bad period or gain (each component checks its own).
    """

    def __init__(
        self,
        robot: Robot,
        *,
        control_period: float,
        attitude_gain: float = 0.3,
        attitude_integral_gain: float = 0.05,
        bias_window: float = 0.0,
        foot_tilt_gain: float = 3.0,
        contact_on_fraction: float = 0.08,
        contact_off_fraction: float = 0.03,
        joint_velocity_cutoff: float = 15.0,
        acceleration_noise: float = 2.0,
        position_noise: float = 0.002,
        velocity_noise: float | None = None,
        encoder_resolution: float = 0.0,
        anchor_load_fraction: float = 0.5,
        flat_ground: bool = True,
        terrain: Terrain | None = None,
        tilt_time_constant: float = 20.0,
        tilt_deadband_deg: float = 2.0,
    ) -> None:
        if not (math.isfinite(control_period) and control_period > 0.0):
            raise ConfigurationError(f"control_period must be > 0 s, got {control_period!r}.")
        self.robot = robot
        self.control_period = float(control_period)
        self.kinematics = BaseKinematics(robot)
        self.gravity = self.kinematics.gravity
        self.weight = robot.total_mass * self.gravity
        self.omega = math.sqrt(self.gravity / robot.com_height)
        foot_tilt_gain = checked_number("foot_tilt_gain", foot_tilt_gain, low=0.0, unit="rad/s")
        self.terrain = None if terrain is None or terrain.is_flat else terrain
        self.foot_tilt_gain = foot_tilt_gain if flat_ground or self.terrain else 0.0
        self.attitude = AttitudeFilter(
            gravity=self.gravity,
            gain=attitude_gain,
            integral_gain=attitude_integral_gain,
            bias_window=bias_window,
        )
        self.contacts = ContactDetector(
            self.weight, on_fraction=contact_on_fraction, off_fraction=contact_off_fraction
        )
        self.joint_velocities = JointVelocityFilter(
            robot.model.nq - 7, cutoff_frequency=joint_velocity_cutoff
        )
        if velocity_noise is None:
            encoder_resolution = checked_number(
                "encoder_resolution", encoder_resolution, low=0.0, unit="rad"
            )
            quantisation = 2.0 * robot.com_height * encoder_resolution / self.control_period
            velocity_noise = max(MIN_VELOCITY_NOISE, quantisation)
        self.base = BaseEstimator(
            acceleration_noise=acceleration_noise,
            position_noise=position_noise,
            velocity_noise=velocity_noise,
            anchor_load_fraction=anchor_load_fraction,
            flat_ground=flat_ground,
            ground=None if self.terrain is None else self.terrain.height,
        )
        self.gravity_tilt = GravityTilt(
            time_constant=tilt_time_constant, deadband_deg=tilt_deadband_deg
        )
        length, width = robot.sole_size
        self._half_sole = np.array([0.5 * length, 0.5 * width, 0.0])
        self._imu_velocity = np.zeros(3)
        self._time: float | None = None
        self._state: EstimatedState | None = None

    @property
    def state(self) -> EstimatedState:
        """The last estimate.

        Raises:
            NotReset: :meth:`reset` was not called.
        """
        if self._state is None:
            raise NotReset("Estimator.state was read before reset; call reset first.")
        return self._state

    def reset(self, readings: SensorReadings, q_initial: np.ndarray) -> EstimatedState:
        """Start estimating from the first readings and the configuration the walk starts from.

        The base position and heading come from ``q_initial`` (the planned start, known to
        the controller); so do roll and pitch while the soles set them (the world is the
        soles', a level floor's or a terrain map's: they start as planned, flat on their
        ground, whatever the accelerometer reads, a jolt or gravity tilted by a slope), else
        the accelerometer's when it reads gravity; the feet in contact are anchored where
        ``q_initial`` puts them.

        Args:
            readings: The first sensor readings.
            q_initial: The configuration the walk starts from, shape (nq,).

        Returns:
            The first estimate.

        Raises:
            ConfigurationError: Readings or configuration of the wrong size or not finite.
        """
        q_initial = checked_reset_inputs(self.robot.model, readings, q_initial)
        joints = np.asarray(readings.joint_positions, dtype=float)
        self.joint_velocities.reset(joints)
        pass_ = self.kinematics.compute(joints, self.joint_velocities.velocities)
        rotation = pin.Quaternion(q_initial[3:7]).normalized().matrix()
        roll, pitch, yaw = rpy_of(rotation)
        accelerometer = np.asarray(readings.imu.accelerometer, dtype=float)
        if self.foot_tilt_gain == 0.0 and self.attitude.accelerometer_weight(accelerometer) > 0.5:
            roll, pitch = tilt_from_accelerometer(pass_.imu_rotation @ accelerometer)
        rotation = pin.rpy.rpyToMatrix(roll, pitch, yaw)
        self.attitude.reset(rotation @ pass_.imu_rotation)
        in_contact = np.array(self.contacts.reset(self._normal_forces(readings)))
        planned = self.kinematics.compute(q_initial[7:], np.zeros(q_initial.shape[0] - 7))
        planned_rotation = pin.Quaternion(q_initial[3:7]).normalized().matrix()
        anchors = q_initial[0:3] + planned.foot_positions @ planned_rotation.T
        self.base.reset(q_initial[0:3], anchors, in_contact)
        self._time = float(readings.time)
        self._imu_velocity = np.zeros(3)
        self.gravity_tilt.reset()
        self._state = self.kinematics.estimated_state(
            readings,
            pass_,
            rotation,
            np.zeros(3),
            self.base.position,
            np.zeros(3),
            in_contact,
            self.omega,
            self.gravity_tilt.value,
        )
        return self._state

    def update(self, readings: SensorReadings) -> EstimatedState:
        """Estimate the state at the time of ``readings``.

        Args:
            readings: The sensor readings of this tick.

        Returns:
            The estimate (``source="estimator"``).

        Raises:
            NotReset: :meth:`reset` was not called.
        """
        if self._time is None:
            raise NotReset("Estimator.update was called before reset; call reset first.")
        dt = min(max(float(readings.time) - self._time, 0.0), 5.0 * self.control_period)
        self._time = float(readings.time)
        joints = np.asarray(readings.joint_positions, dtype=float)
        joint_velocities = self.joint_velocities.update(joints, dt)
        pass_ = self.kinematics.compute(joints, joint_velocities)
        gyro = np.asarray(readings.imu.gyro, dtype=float)
        accelerometer = np.asarray(readings.imu.accelerometer, dtype=float)
        imu_rotation = self.attitude.predict(gyro, dt)
        rotation = imu_rotation @ pass_.imu_rotation.T
        angular_velocity = (
            pass_.imu_rotation @ self.attitude.corrected_gyro(gyro) - pass_.imu_angular_velocity
        )
        acceleration = imu_rotation @ accelerometer
        acceleration += self.gravity_tilt.gravity(self.gravity)
        forces = self._normal_forces(readings)
        in_contact = np.array(self.contacts.update(forces))
        points = self._contact_points(readings, forces)
        levers = np.einsum("nij,nj->ni", pass_.foot_rotations, points)  # sole origin to CoP
        contact_velocities = (
            pass_.foot_velocities
            + cross_rows(angular_velocity, pass_.foot_positions + levers)
            + cross_rows(pass_.foot_angular_velocities, levers)
        )
        state = self.base.update(
            acceleration,
            dt,
            rotation,
            pass_.foot_positions,
            contact_velocities,
            in_contact,
            forces / self.weight,
        )
        if self.foot_tilt_gain > 0.0:
            imu_rotation = self._correct_with_feet(pass_, points, forces, dt)
            rotation = imu_rotation @ pass_.imu_rotation.T
        imu_velocity = state[1] + rotation @ (
            cross_rows(angular_velocity, pass_.imu_position) + pass_.imu_velocity
        )
        if dt > 0.0:  # the tilt corrected with the IMU's acceleration the legs imply
            imu_acceleration = (imu_velocity - self._imu_velocity) / dt
            imu_rotation = self.attitude.correct(accelerometer, dt, acceleration=imu_acceleration)
            rotation = imu_rotation @ pass_.imu_rotation.T
        self._imu_velocity = imu_velocity
        self._state = self.kinematics.estimated_state(
            readings,
            pass_,
            rotation,
            angular_velocity,
            state[0],
            state[1],
            in_contact,
            self.omega,
            self.gravity_tilt.value,
        )
        if dt > 0.0 and self.foot_tilt_gain > 0.0 and self.terrain is None:
            specific_force = imu_rotation @ accelerometer
            flat, loads = self._flat_weights(points, forces, with_loads=True)
            self.gravity_tilt.update(
                specific_force,
                imu_velocity,
                self._state.sole_rotations[:, :, 2],
                flat,
                float(loads.sum()),
                self.attitude.accelerometer_weight(specific_force) > 0.0,
                dt,
            )
        return self._state

    def _flat_weights(self, points: np.ndarray, forces: np.ndarray, *, with_loads=False):
        """Each foot's trust as flat on its ground: its load (share of the weight) times how
        far its CoP is from the sole's edges (a foot rolling on an edge is not flat); with
        the loads too when ``with_loads``."""
        edge = np.max(np.abs(points[:, :2]) / self._half_sole[:2], axis=1)
        loads = np.minimum(np.maximum(forces / self.weight, 0.0), 1.0)
        weights = loads * np.minimum(np.maximum((1.0 - edge) / 0.2, 0.0), 1.0)
        return (weights, loads) if with_loads else weights

    def _correct_with_feet(
        self, pass_: KinematicsPass, points: np.ndarray, forces: np.ndarray, dt: float
    ) -> np.ndarray:
        """Roll and pitch pulled towards the vertical of the loaded feet, flat on the floor:
        each foot weighted by its load and by how far its CoP is from the sole's edges (a
        foot rolling on an edge is not flat)."""
        weights = self._flat_weights(points, forces)
        total = float(weights.sum())
        if total < 0.3:
            return self.attitude.rotation
        if self.terrain is None:
            up_in_base = weights @ pass_.foot_rotations[:, :, 2] / total  # sole z axes, base
        else:  # the vertical seen from each sole on its tilted top
            up_in_base = weights @ self._verticals_in_base(pass_) / total
        up = pass_.imu_rotation.T @ up_in_base
        return self.attitude.correct_vertical(
            up / math.sqrt(float(up @ up)), dt, self.foot_tilt_gain * min(total, 1.0)
        )

    def _verticals_in_base(self, pass_: KinematicsPass) -> np.ndarray:
        """The world's vertical in the base frame as each sole sees it, resting on the top of
        the terrain under it (the sole's tilt on that top: the terrain's normal at the
        sole's estimated heading), shape (2, 3)."""
        base = self.attitude.rotation @ pass_.imu_rotation.T  # base orientation, world
        out = np.empty((2, 3))
        anchors = self.base.anchors
        for foot in range(2):
            rotation = pass_.foot_rotations[foot]  # sole in the base frame
            world = base @ rotation
            yaw = math.atan2(float(world[1, 0]), float(world[0, 0]))
            x, y = anchors[foot, :2] if np.all(np.isfinite(anchors[foot])) else (np.nan, np.nan)
            if not (math.isfinite(x) and math.isfinite(y)):
                out[foot] = rotation[:, 2]
                continue
            roll, pitch = sole_tilt(self.terrain.normal(x, y), yaw)  # type: ignore[union-attr]
            cr, sr, cp, sp = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch)
            # vertical in the sole frame: (Ry(pitch) Rx(roll))^T e_z
            vertical = np.array([-sp, sr * cp, cr * cp])
            out[foot] = rotation @ vertical
        return out

    def _contact_points(self, readings: SensorReadings, forces: np.ndarray) -> np.ndarray:
        """Each foot's CoP in its sole frame, shape (2, 3), in [m], kept inside the sole;
        the sole origin for a foot below the contact threshold."""
        points = np.zeros((2, 3))
        for foot, wrench in enumerate(readings.wrenches):
            if forces[foot] > self.contacts.off_force and forces[foot] > 0.0:
                torque = wrench.torque
                points[foot, 0] = -float(torque[1]) / forces[foot]
                points[foot, 1] = float(torque[0]) / forces[foot]
        np.minimum(np.maximum(points, -self._half_sole, out=points), self._half_sole, out=points)
        return points

    @staticmethod
    def _normal_forces(readings: SensorReadings) -> np.ndarray:
        return np.array(
            (float(readings.left_wrench.force[2]), float(readings.right_wrench.force[2]))
        )


__all__ = ["MIN_VELOCITY_NOISE", "Estimator"]
