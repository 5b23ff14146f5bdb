"""The simulated robot's true state and exact sensor readings, read from MuJoCo.

:class:`GroundTruth` reads, at the current MuJoCo state, what a perfect robot would know:
the configuration and velocity, the base pose, the contacts of both soles and their CoP
(:class:`~mpcwalk.sim.contacts.ContactWrenches`), the CoM, its velocity and the DCM, the
sole poses, and the exact readings of the robot's sensors (IMU gyroscope and accelerometer
in the IMU frame, the joint angles, each foot's contact wrench in its sole frame about the
sole origin). It returns them as an
:class:`~mpcwalk.estimation.estimated_state.EstimatedState` with ``source="oracle"``: the
type the estimator gives the controller, so that the controller can run on the truth behind
an explicit switch (``state="oracle"``), for comparison.
"""

import mujoco
import numpy as np

from mpcwalk._checks import freeze, frozen_array
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.models.lipm import LIPM
from mpcwalk.robot.robot import Robot
from mpcwalk.robot.sensors import FootContact, ForceTorqueReading, ImuReading, SensorReadings
from mpcwalk.sim.contacts import ContactWrenches
from mpcwalk.sim.sim_state import quaternion_to_rpy


def _sensor_slice(model: mujoco.MjModel, name: str) -> slice:
    """Where sensor ``name`` lies in ``data.sensordata``."""
    sensor = model.sensor(name)
    return slice(int(sensor.adr[0]), int(sensor.adr[0] + sensor.dim[0]))


class GroundTruth:
    """Reads the true state of a simulated robot and the exact readings of its sensors.

    Args:
        robot: The robot (its joint order, sole frames and CoM height).
        model: The simulator's MuJoCo model (perhaps perturbed) with the loader's sensors.
        contact_threshold: Vertical force [N] above which a foot is in contact.
        joint_torques: Whether the robot has joint torque sensors (torque motors): its
            readings then carry the torque each actuator applies to its joint.
    """

    def __init__(
        self,
        robot: Robot,
        model: mujoco.MjModel,
        *,
        contact_threshold: float,
        joint_torques: bool = False,
    ) -> None:
        self.robot = robot
        self._joint_dofs = robot.joint_dofs if joint_torques else None
        self.contacts = ContactWrenches(
            model, robot.foot_frames, contact_threshold=contact_threshold
        )
        self.root_body = int(model.jnt_bodyid[0])
        self._gyro = _sensor_slice(model, "imu_gyro")
        self._accelerometer = _sensor_slice(model, "imu_accelerometer")
        self._imu_site = int(model.sensor("imu_accelerometer").objid[0])
        adjacent = self._gyro.stop == self._accelerometer.start
        self._imu = slice(self._gyro.start, self._accelerometer.stop) if adjacent else None
        self._sites = list(self.contacts.site_ids)
        self._omega = LIPM(com_height=robot.com_height).omega  # [1/s] of the DCM
        gravity = model.opt.gravity  # a tilted ground tilts gravity (set before this)
        self._tilt = frozen_array(np.array(gravity[:2]) / float(gravity[2]))  # g_xy / g_z
        self.imu_mean: np.ndarray | None = None
        """Gyroscope and accelerometer readings averaged over the last control period,
        shape (6,), or None for the instantaneous ones. A MEMS IMU read at the control rate
        reports its samples low-pass filtered (the BMI088's digital filter: 32 Hz bandwidth
        at 100 Hz output rate, data sheet BST-BMI088-DS001), never an instantaneous value:
        point samples would alias the servos' vibrations into biased readings."""

    def imu_now(self, data: mujoco.MjData) -> np.ndarray:
        """The instantaneous gyroscope [rad/s] and accelerometer [m/s^2] readings of the
        last MuJoCo step, shape (6,) (a view into ``data`` when the two sensors are adjacent:
        copy it to keep it)."""
        if self._imu is not None:
            return data.sensordata[self._imu]
        return np.concatenate((data.sensordata[self._gyro], data.sensordata[self._accelerometer]))

    def imu_at_rest(self, model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
        """The gyroscope [rad/s] and accelerometer [m/s^2] readings of the robot at rest at
        ``data``'s positions, shape (6,): no rotation, gravity's specific force in the IMU
        frame."""
        mujoco.mj_kinematics(model, data)
        rotation = data.site_xmat[self._imu_site].reshape(3, 3)
        return np.concatenate((np.zeros(3), rotation.T @ -model.opt.gravity))

    def read(self, model: mujoco.MjModel, data: mujoco.MjData, time: float) -> EstimatedState:
        """The truth at the current ``data`` (forwarded here: positions, contact forces,
        sensors, subtree velocities).

        Args:
            model: The simulator's MuJoCo model.
            data: Its data, at the state to read.
            time: The simulation time [s].

        Returns:
            The true state, ``source="oracle"``, its ``sensors`` the exact readings.
        """
        mujoco.mj_forward(model, data)
        mujoco.mj_subtreeVel(model, data)
        robot, root = self.robot, self.root_body
        q = freeze(robot.qpos_to_q(data.qpos))
        v = freeze(robot.qvel_to_v(data.qpos, data.qvel))
        left, right, cop, has_cop = self.contacts.measure(model, data)
        sole_positions = freeze(data.site_xpos[self._sites])  # fancy indexing: a copy
        sole_rotations = freeze(data.site_xmat[self._sites].reshape(2, 3, 3))
        sensors = self._exact_readings(data, time, q, (left, right), sole_rotations)
        com = frozen_array(data.subtree_com[root])
        com_velocity = frozen_array(data.subtree_linvel[root])
        roll, pitch, yaw = quaternion_to_rpy(data.qpos[3:7])
        return EstimatedState(
            time=float(time),
            source="oracle",
            sensors=sensors,
            q=q,
            v=v,
            base_position=frozen_array(data.xpos[root]),
            base_rotation=frozen_array(data.xmat[root], (3, 3)),
            base_linear_velocity=frozen_array(data.qvel[0:3]),
            roll=roll,
            pitch=pitch,
            yaw=yaw,
            left_foot=left,
            right_foot=right,
            cop=cop,
            has_cop=has_cop,
            com=com,
            com_velocity=com_velocity,
            dcm=freeze(com[:2] + com_velocity[:2] / self._omega),  # LIPM.dcm
            joint_positions=q[7:],
            joint_velocities=v[6:],
            sole_positions=sole_positions,
            sole_rotations=sole_rotations,
            ground_tilt=self._tilt,
        )

    def _exact_readings(
        self,
        data: mujoco.MjData,
        time: float,
        q: np.ndarray,
        feet: tuple[FootContact, FootContact],
        sole_rotations: np.ndarray,
    ) -> SensorReadings:
        """What ideal sensors read: MuJoCo's IMU sensors (IMU frame), the joint angles, each
        foot's contact wrench rotated into its sole frame (torque about the sole origin), and
        the actuators' joint torques where the robot senses them."""
        imu = self.imu_now(data) if self.imu_mean is None else self.imu_mean
        left, right = (
            ForceTorqueReading(
                force=freeze(rotation.T @ foot.force), torque=freeze(rotation.T @ foot.torque)
            )
            for foot, rotation in zip(feet, sole_rotations)
        )
        return SensorReadings(
            time=float(time),
            imu=ImuReading(gyro=frozen_array(imu[:3]), accelerometer=frozen_array(imu[3:])),
            joint_positions=q[7:] if not q.flags.writeable else frozen_array(q[7:]),
            left_wrench=left,
            right_wrench=right,
            joint_torques=(
                None
                if self._joint_dofs is None
                else freeze(data.qfrc_actuator[self._joint_dofs])  # fancy indexing: a copy
            ),
        )
