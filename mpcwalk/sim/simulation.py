"""MuJoCo simulation of one robot: position servos or torque motors, sensors, contacts, CoP,
pushes.

Each control period the simulation reports its ground truth and what the robot senses: the
readings of its IMU, joint encoders and foot force/torque sensors with the noise, bias,
quantisation and latency of a :class:`~mpcwalk.sim.sensing.model.SensorModel` (the robot's own
by default). A :class:`~mpcwalk.sim.model_mismatch.ModelMismatch` makes the simulated robot
differ from the model the controller uses.
"""

import copy
import math
from collections.abc import Iterable

import mujoco
import numpy as np

from mpcwalk.exceptions import ConfigurationError, SimulationUnstable
from mpcwalk.ik.inverse_dynamics import torque_limits
from mpcwalk.robot.ground import Ground
from mpcwalk.robot.robot import Robot
from mpcwalk.sim.actuation import actuated_model, check_actuation
from mpcwalk.sim.contacts import ContactWrenches
from mpcwalk.sim.ground_truth import GroundTruth
from mpcwalk.sim.model_mismatch import ModelMismatch, trunk_body
from mpcwalk.sim.pushes import ExternalForce, resolve_body
from mpcwalk.sim.sensing.model import SensorModel
from mpcwalk.sim.sensing.simulator import SensorSimulator
from mpcwalk.sim.sim_state import SimState
from mpcwalk.terrain import Terrain

_UNSTABLE_WARNINGS = (
    mujoco.mjtWarning.mjWARN_BADQACC,
    mujoco.mjtWarning.mjWARN_BADQPOS,
    mujoco.mjtWarning.mjWARN_BADQVEL,
)
_UNSTABLE_INDEX = np.array([int(w) for w in _UNSTABLE_WARNINGS])


def _ctrl_joint_index(robot: Robot) -> np.ndarray | None:
    """The joint (``robot.joint_names`` order) each actuator's ``ctrl`` holds, so that
    ``ctrl = joint_angles[index]`` is ``robot.q_to_ctrl`` of those angles; None when an
    actuator holds something else than a joint slot of the configuration."""
    probe = robot.q_to_ctrl(np.arange(1.0, robot.model.nq + 1.0))  # q[i] = i + 1
    if probe.size == 0 or not np.all(probe >= 8.0):  # the joints start at q[7]
        return None
    return probe.astype(int) - 8


def make_mj_data(robot: Robot, q: np.ndarray | None = None) -> mujoco.MjData:
    """MuJoCo data of ``robot.mj_model`` at ``q`` (default ``robot.q0``), at rest, the
    actuators holding ``q``, forwarded."""
    q = robot.q0 if q is None else q
    mj_data = mujoco.MjData(robot.mj_model)
    mj_data.qpos[:] = robot.q_to_qpos(q)
    mj_data.ctrl[:] = robot.q_to_ctrl(q)
    mujoco.mj_forward(robot.mj_model, mj_data)
    return mj_data


class Simulation:
    """One robot on a floor or a terrain in MuJoCo, driven by position servos or torque motors.

    The simulation owns a copy of ``robot.mj_model`` (changing its time step or its mismatch
    leaves the robot's model alone), or of its scene with the terrain's blocks
    (:func:`~mpcwalk.robot.terrain_scene.terrain_model`). Each :meth:`step` holds the joint
    targets during one control period of ``control_period / timestep`` physics steps and
    applies the external forces active at each physics step; the state it returns carries the
    ground truth, the sensor readings (delayed by the latency) and the oracle.

    Args:
        robot: The robot (from :func:`mpcwalk.robot.load_robot`).
        timestep: Physics time step [s]; None keeps the robot's.
        control_period: Duration of one :meth:`step` [s], a multiple of ``timestep``.
        seed: Seed of the sensor noise and biases (same seed, same readings; None: fresh
            entropy).
        pushes: External forces applied during their windows.
        sensors: Sensor model (noise, bias, quantisation, latency in control periods);
            None for the robot's (:meth:`SensorModel.for_robot`), ``SensorModel.ideal()``
            for exact, immediate readings.
        model_mismatch: How the simulated robot differs from ``robot`` (trunk mass and CoM,
            friction, servo strength); None for no difference.
        ground: Tilt and bumps of the ground (:class:`~mpcwalk.robot.ground.Ground`); None
            for the level floor.
        terrain: Stairs, slopes, stones... laid along the robot's initial heading
            (:class:`~mpcwalk.terrain.Terrain`); None for the level floor.
        contact_threshold: Vertical force [N] above which a foot is in contact in the ground
            truth; None for 1 % of the simulated robot's weight.
        actuation: ``"position"`` (the robot's position servos, fed joint angles) or
            ``"torque"`` (torque motors, fed joint torques: :mod:`mpcwalk.sim.actuation`).

    Raises:
        ConfigurationError: Non-positive periods, or a control period that is not a
            multiple of the time step.
    """

    def __init__(
        self,
        robot: Robot,
        *,
        timestep: float | None = None,
        control_period: float = 0.01,
        seed: int | None = None,
        pushes: Iterable[ExternalForce] = (),
        sensors: SensorModel | None = None,
        model_mismatch: ModelMismatch | None = None,
        contact_threshold: float | None = None,
        ground: Ground | None = None,
        terrain: Terrain | None = None,
        actuation: str = "position",
    ) -> None:
        self.robot = robot
        self.terrain = None if terrain is None or terrain.is_flat else terrain
        self.actuation = check_actuation(actuation)
        self.model: mujoco.MjModel = copy.copy(actuated_model(robot, self.terrain, actuation))
        if timestep is not None:
            if not (math.isfinite(timestep) and timestep > 0.0):
                raise ConfigurationError(f"timestep must be > 0 s, got {timestep!r}.")
            self.model.opt.timestep = float(timestep)
        self.timestep = float(self.model.opt.timestep)
        if not (math.isfinite(control_period) and control_period > 0.0):
            raise ConfigurationError(f"control_period must be > 0 s, got {control_period!r}.")
        nb_substeps = round(control_period / self.timestep)
        if nb_substeps < 1 or abs(nb_substeps * self.timestep - control_period) > 1e-9:
            raise ConfigurationError(
                f"control_period = {control_period:g} s is not a multiple of the physics time "
                f"step {self.timestep:g} s; choose e.g. {max(nb_substeps, 1) * self.timestep:g} s."
            )
        self.control_period = float(control_period)
        self.nb_substeps = int(nb_substeps)
        self.model_mismatch = ModelMismatch() if model_mismatch is None else model_mismatch
        self.trunk_body = trunk_body(self.model, robot.torso_frame)
        self.ground = Ground() if ground is None else ground
        if self.terrain is not None and self.ground.roughness > 0.0:
            raise ConfigurationError(
                "A terrain and a rough ground do not go together (the bumps' height field lies "
                "at z = 0, under the terrain's blocks); lay a RoughPatch in the terrain instead."
            )
        self.ground.apply(self.model, robot)  # before the friction reaches every contact
        self.model_mismatch.apply(self.model, trunk=self.trunk_body)
        self.data = mujoco.MjData(self.model)
        self.sensor_model = SensorModel.for_robot(robot) if sensors is None else sensors
        self.sensors = SensorSimulator(
            self.sensor_model,
            period=self.control_period,
            nb_joints=len(robot.joint_names),
            seed=seed,
            torque_limits=torque_limits(robot) if self.actuation == "torque" else None,
        )
        mass = float(self.model.body_mass.sum())
        weight = mass * float(np.linalg.norm(self.model.opt.gravity))
        self.ground_truth = GroundTruth(
            robot,
            self.model,
            contact_threshold=0.01 * weight if contact_threshold is None else contact_threshold,
            joint_torques=self.actuation == "torque",
        )
        self.contacts: ContactWrenches = self.ground_truth.contacts
        self.root_body = self.ground_truth.root_body
        self._pushes: list[tuple[ExternalForce, int]] = []
        for push in pushes:
            self.add_push(push)
        self._substep = 0
        self._state: SimState | None = None
        self._ctrl_joints = _ctrl_joint_index(robot)
        self.reset()

    @property
    def time(self) -> float:
        """Simulated time [s] since the last :meth:`reset` (after settling)."""
        return self._substep * self.timestep

    @property
    def pushes(self) -> tuple[ExternalForce, ...]:
        """External forces of this simulation."""
        return tuple(force for force, _ in self._pushes)

    def add_push(self, push: ExternalForce) -> None:
        """Add an external force; raises ConfigurationError if its body does not exist."""
        body_id = resolve_body(self.model, push.body, self.robot.torso_frame)
        self._pushes.append((push, body_id))

    def reset(
        self,
        q: np.ndarray | None = None,
        *,
        v: np.ndarray | None = None,
        settle: float = 0.0,
    ) -> SimState:
        """Put the robot at ``q`` (Pinocchio configuration, default ``robot.q0``) at rest.

        Args:
            q: Configuration; the actuators hold its joint angles (torque motors: its static
                torques on both feet).
            v: Velocity (Pinocchio convention); None for zero.
            settle: Simulate this long [s] holding ``q`` first (the robot sinks into its
                contacts); the clock then restarts at 0.

        Returns:
            The state at time 0.
        """
        q = self.robot.q0 if q is None else np.asarray(q, dtype=float)
        if q.shape != (self.robot.model.nq,) or not np.all(np.isfinite(q)):
            raise ConfigurationError(
                f"reset expects a finite configuration of size nq = {self.robot.model.nq}, got "
                f"shape {q.shape}."
            )
        mujoco.mj_resetData(self.model, self.data)
        self.data.qpos[:] = self.robot.q_to_qpos(q)
        if v is not None:
            self.data.qvel[:] = self.robot.v_to_qvel(q, np.asarray(v, dtype=float))
        self.data.ctrl[:] = self._holding_ctrl(q)
        nb_settle = round(settle / self.timestep)
        if nb_settle > 0:
            mujoco.mj_step(self.model, self.data, nb_settle)
            self._check_stable(-settle)
        self.data.time = 0.0
        self._substep = 0
        # At rest. Servos holding q give no torque until the robot moves: the instantaneous
        # readings. Motors hold it with its static torques, but its contacts carry no load
        # yet: the instantaneous accelerometer would read a base that drops and pitches
        # (atlas-like: 4 deg of tilt, which the estimator took for gravity's).
        self.ground_truth.imu_mean = (
            self.ground_truth.imu_at_rest(self.model, self.data)
            if self.actuation == "torque" and nb_settle == 0
            else None
        )
        self._state = self._compute_state(first=True)
        return self._state

    def _holding_ctrl(self, q: np.ndarray) -> np.ndarray:
        """Controls that hold ``q``: its joint angles, or its static torques on both feet."""
        if self.actuation == "position":
            return self.robot.q_to_ctrl(q)
        from mpcwalk.control.servo_feedforward import ServoFeedforward

        torques = ServoFeedforward(self.robot).compute_torques(q, (0.5, 0.5))
        return self._torque_ctrl(torques)

    def _torque_ctrl(self, torques: np.ndarray) -> np.ndarray:
        torques = np.asarray(torques, dtype=float)
        nb_joints = len(self.robot.joint_names)
        if torques.shape != (nb_joints,) or not np.all(np.isfinite(torques)):
            raise ConfigurationError(
                f"Joint torques must be {nb_joints} finite numbers (robot.joint_names order), "
                f"got shape {torques.shape}; check the inverse dynamics' output."
            )
        q = self.robot.q0.copy()  # the torques ride on the configuration's joint slots
        q[7:] = torques
        return self.robot.q_to_ctrl(q)

    def step(
        self, joint_targets: np.ndarray | None = None, *, torques: np.ndarray | None = None
    ) -> SimState:
        """Simulate one control period holding the joint targets (position servos) or the
        joint torques (torque motors).

        Args:
            joint_targets: Joint angles [rad] in Pinocchio order (``robot.joint_names``,
                size nq - 7), or a full configuration (size nq) whose joint angles are used;
                None keeps the previous targets. Position servos only.
            torques: Joint torques [N m] in ``robot.joint_names`` order; None keeps the
                previous ones. Torque motors only.

        Returns:
            The state at the end of the period.

        Raises:
            ConfigurationError: Targets or torques of the wrong size or not finite, or given
                to actuators that do not take them.
            SimulationUnstable: MuJoCo's integration diverged (MuJoCo has then reset its
                data; call :meth:`reset` before stepping again).
        """
        torque = self.actuation == "torque"
        if (joint_targets is not None and torque) or (torques is not None and not torque):
            raise ConfigurationError(
                f"This simulation's joints are driven by {self.actuation} actuators: give "
                f"{'torques=' if torque else 'joint_targets'} to step(), not "
                f"{'joint_targets' if torque else 'torques='}."
            )
        if joint_targets is not None:
            self.data.ctrl[:] = self._ctrl_of(joint_targets)
        if torques is not None:
            self.data.ctrl[:] = self._torque_ctrl(torques)
        imu_sum = np.zeros(6)  # the IMU reports its readings averaged over the period
        imu_now = self.ground_truth.imu_now
        for _ in range(self.nb_substeps):
            if self._pushes:
                self.data.xfrc_applied[:] = 0.0
                active = [(f, body) for f, body in self._pushes if f.is_active(self.time)]
                if any(force.point is not None for force, _ in active):
                    mujoco.mj_kinematics(self.model, self.data)  # body poses of this state
                    mujoco.mj_comPos(self.model, self.data)
                for force, body_id in active:
                    force.apply(self.data, body_id)
            mujoco.mj_step(self.model, self.data)
            imu_sum += imu_now(self.data)
            self._substep += 1
        self.ground_truth.imu_mean = imu_sum / self.nb_substeps
        self._check_stable(self.time)
        self._state = None
        return self.state()

    def state(self) -> SimState:
        """Snapshot of the current state (computed once per control period)."""
        if self._state is None:
            self._state = self._compute_state()
        return self._state

    def _ctrl_of(self, joint_targets: np.ndarray) -> np.ndarray:
        targets = np.asarray(joint_targets, dtype=float)
        nq = self.robot.model.nq
        if targets.shape == (nq,):
            joints = targets[7:]
        elif targets.shape == (nq - 7,):
            joints = targets
        else:
            raise ConfigurationError(
                f"Joint targets must have {nq - 7} joint angles (robot.joint_names order) or "
                f"be a configuration of size {nq}; got shape {targets.shape}."
            )
        if not np.isfinite(joints).all():
            raise ConfigurationError(
                "Joint targets must be finite, got NaN or infinite angles for "
                f"{[n for n, a in zip(self.robot.joint_names, joints) if not np.isfinite(a)]}; "
                "check the IK output."
            )
        if self._ctrl_joints is not None:  # one gather, as q_to_ctrl of the same angles
            return joints[self._ctrl_joints]
        return self.robot.q_to_ctrl(np.concatenate([self.robot.q0[:7], joints]))

    def _check_stable(self, time: float) -> None:
        if self.data.warning.number[_UNSTABLE_INDEX].any():
            raise SimulationUnstable(time, self.timestep)

    def _compute_state(self, *, first: bool = False) -> SimState:
        """Ground truth at the current positions; the sensors take their readings (the
        first of a walk restarts them)."""
        oracle = self.ground_truth.read(self.model, self.data, self.time)
        sensors = (self.sensors.reset if first else self.sensors.read)(oracle.sensors)
        return SimState(
            time=self.time,
            q=oracle.q,
            v=oracle.v,
            base_position=oracle.base_position,
            base_rotation=oracle.base_rotation,
            sole_positions=oracle.sole_positions,
            sole_rotations=oracle.sole_rotations,
            sensors=sensors,
            oracle=oracle,
        )
