"""The per-tick log of a simulated walk (:class:`WalkLog`) and its recorder."""

from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from mpcwalk._checks import frozen_array
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.contact_schedule import ContactSchedule

if TYPE_CHECKING:
    from mpcwalk.robot.robot import Robot

#: Shapes of the empty series of a log with no tick (nj joints, nu actuators filled in).
_EMPTY_SHAPES = {
    "com": (0, 3),
    "com_velocity": (0, 3),
    "com_reference": (0, 2),
    "zmp_reference": (0, 2),
    "zmp_command": (0, 2),
    "com_target": (0, 3),
    "dcm_error": (0, 2),
    "cop": (0, 3),
    "contact": (0, 2),
    "foot_wrenches": (0, 2, 6),
    "sole_positions": (0, 2, 3),
    "sole_yaws": (0, 2),
    "feet_reference": (0, 2, 3),
    "base_rpy": (0, 3),
    "base_position": (0, 3),
    "estimate_time": (0,),
    "estimated_com": (0, 3),
    "estimated_com_velocity": (0, 3),
    "estimated_base_rpy": (0, 3),
    "estimated_contact": (0, 2),
    "estimated_sole_positions": (0, 2, 3),
}

#: CSV columns of a foot's wrench, after the side (``left_force_x``...).
_WRENCH_COLUMNS = tuple(f"{part}_{axis}" for part in ("force", "torque") for axis in "xyz")


@dataclass(frozen=True)
class WalkLog:
    """Per-tick log of a simulated walk (n ticks, world frame, SI units).

    "Measured" is the simulator's ground truth (what a motion-capture system would measure),
    for the metrics; "estimated" is what the controller received (the estimator's state, or
    the ground truth itself behind ``state="oracle"``).

    Attributes:
        time: End of each tick [s], shape (n,).
        com: Measured CoM [m], (n, 3). com_velocity: [m/s], (n, 3).
        com_reference: Generator CoM [m], (n, 2). zmp_reference: Generator ZMP [m], (n, 2).
        zmp_command: Desired ZMP with the DCM feedback [m], (n, 2).
        com_target: IK CoM target [m], (n, 3). dcm_error: [m], (n, 2).
        cop: Measured CoP (paper M eq. 31) [m], (n, 3), NaN without contact.
        contact: Measured contact of the left and right soles, (n, 2) bool.
        foot_wrenches: Measured contact wrench of each foot, world frame: force [N], then
            moment about its sole origin (``sole_positions``) [N m], (n, 2, 6).
        sole_positions: Measured soles [m], (n, 2, 3). sole_yaws: [rad], (n, 2).
        feet_reference: Sole references of the gait [m], (n, 2, 3).
        base_rpy: Base roll, pitch, yaw [rad], (n, 3).
        base_position: Base (floating joint) position [m], (n, 3).
        estimate_time: Time of the sensor readings the state given to the controller at the
            next tick was estimated from [s], (n,) (``time`` minus the latency).
        estimated_com: Its CoM [m], (n, 3). estimated_com_velocity: [m/s], (n, 3).
        estimated_base_rpy: Its base roll, pitch, yaw [rad], (n, 3).
        estimated_contact: Its contacts of the left and right soles, (n, 2) bool.
        estimated_sole_positions: Its soles [m], (n, 2, 3).
        joint_positions: Measured joints [rad], (n, nj). joint_targets: Servo targets, (n, nj).
        actuator_force: Actuator torques [N m] in ``joint_names`` order, (n, nj) (NaN for a
            joint no actuator drives).
        ik_error: Largest CoM/sole position error of the IK [m], (n,).
        generator_failed: Generator reported a failed solve, (n,) bool.
        generator_tick, ik_tick, controller_tick, mujoco_step, estimator_tick: Wall times
            [s], (n,) (the estimator's: 0 on the ground truth).
        joint_names: Joint names (``robot.joint_names``).
        torque_limit: Torque limit of each joint's actuator [N m] (inf: none), (nj,).
    """

    time: np.ndarray
    com: np.ndarray
    com_velocity: np.ndarray
    com_reference: np.ndarray
    zmp_reference: np.ndarray
    zmp_command: np.ndarray
    com_target: np.ndarray
    dcm_error: np.ndarray
    cop: np.ndarray
    contact: np.ndarray
    foot_wrenches: np.ndarray
    sole_positions: np.ndarray
    sole_yaws: np.ndarray
    feet_reference: np.ndarray
    base_rpy: np.ndarray
    base_position: np.ndarray
    estimate_time: np.ndarray
    estimated_com: np.ndarray
    estimated_com_velocity: np.ndarray
    estimated_base_rpy: np.ndarray
    estimated_contact: np.ndarray
    estimated_sole_positions: np.ndarray
    joint_positions: np.ndarray
    joint_targets: np.ndarray
    actuator_force: np.ndarray
    ik_error: np.ndarray
    generator_failed: np.ndarray
    generator_tick: np.ndarray
    ik_tick: np.ndarray
    controller_tick: np.ndarray
    mujoco_step: np.ndarray
    estimator_tick: np.ndarray
    joint_names: tuple[str, ...]
    torque_limit: np.ndarray

    @staticmethod
    def recorder(robot: "Robot", schedule: ContactSchedule) -> "WalkLogRecorder":
        """An empty recorder for a walk of ``robot``."""
        return WalkLogRecorder(robot)

    def __len__(self) -> int:
        return len(self.time)

    @classmethod
    def load(cls, path: str | Path) -> "WalkLog":
        """Read a log written by :meth:`save` as ``.npz`` (a log written before the base
        position or the foot wrenches were recorded gets NaN there).

        Raises:
            ConfigurationError: Not a walk log.
        """
        try:
            with np.load(path) as data:
                arrays = {name: data[name] for name in data.files}
        except (OSError, ValueError) as error:
            raise ConfigurationError(f"Cannot read the walk log {path}: {error}.") from None
        for name, shape in (("base_position", (3,)), ("foot_wrenches", (2, 6))):
            if name not in arrays and "time" in arrays:
                arrays[name] = np.full((len(arrays["time"]), *shape), np.nan)
        missing = sorted({f.name for f in fields(cls)} - set(arrays))
        if missing:
            raise ConfigurationError(
                f"{path} is not a walk log of this version of mpcwalk: no {', '.join(missing)}."
            )
        arrays["joint_names"] = tuple(str(name) for name in arrays["joint_names"])
        for value in arrays.values():
            if isinstance(value, np.ndarray):
                value.setflags(write=False)
        return cls(**{f.name: arrays[f.name] for f in fields(cls)})

    def save(self, path: str | Path) -> Path:
        """Write the log as ``.npz`` (every field) or ``.csv`` (the scalar and planar series,
        one row per tick, with a header). Returns the path.

        Raises:
            ConfigurationError: Another suffix.
        """
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".csv":
            columns = self.csv_columns()
            data = np.column_stack(list(columns.values()))
            np.savetxt(path, data, delimiter=",", header=",".join(columns), comments="", fmt="%.6g")
            return path
        if path.suffix != ".npz":
            raise ConfigurationError(
                f"A walk log is written as .npz or .csv, got '{path.name}'; use e.g. walk_log.npz."
            )
        arrays: dict[str, Any] = {f.name: np.asarray(getattr(self, f.name)) for f in fields(self)}
        np.savez_compressed(path, **arrays)
        return path

    def csv_columns(self) -> dict[str, np.ndarray]:
        """Named columns of the CSV form of the log."""
        columns = {"time": self.time, "estimate_time": self.estimate_time}
        for name, axes in (
            ("com", "xyz"),
            ("com_velocity", "xyz"),
            ("com_reference", "xy"),
            ("zmp_reference", "xy"),
            ("zmp_command", "xy"),
            ("cop", "xy"),
            ("dcm_error", "xy"),
            ("base_rpy", ("roll", "pitch", "yaw")),
            ("estimated_com", "xyz"),
            ("estimated_com_velocity", "xyz"),
            ("estimated_base_rpy", ("roll", "pitch", "yaw")),
        ):
            values = getattr(self, name)
            for i, axis in enumerate(axes):
                columns[f"{name}_{axis}"] = values[:, i]
        for j, side in enumerate(("left", "right")):
            columns[f"{side}_contact"] = self.contact[:, j].astype(float)
            columns[f"{side}_estimated_contact"] = self.estimated_contact[:, j].astype(float)
            for i, axis in enumerate("xyz"):
                columns[f"{side}_sole_{axis}"] = self.sole_positions[:, j, i]
            columns[f"{side}_sole_yaw"] = self.sole_yaws[:, j]
            for i, name in enumerate(_WRENCH_COLUMNS):
                columns[f"{side}_{name}"] = self.foot_wrenches[:, j, i]
        for name in (
            "ik_error",
            "generator_tick",
            "ik_tick",
            "controller_tick",
            "mujoco_step",
            "estimator_tick",
        ):
            columns[name] = getattr(self, name)
        columns["generator_failed"] = self.generator_failed.astype(float)
        return columns


class WalkLogRecorder:
    """Accumulates the ticks of a walk, then :meth:`freeze` makes the :class:`WalkLog`."""

    def __init__(self, robot: "Robot") -> None:
        self.robot = robot
        self._actuator_of = _actuator_of_joints(robot)
        self.rows: dict[str, list] = {
            f.name: [] for f in fields(WalkLog) if f.name not in ("joint_names", "torque_limit")
        }

    def append(
        self,
        output,
        state,
        estimate,
        actuator_force,
        *,
        mujoco_step: float,
        controller_tick: float,
        estimator_tick: float = 0.0,
    ) -> None:
        """Record one tick: controller output, simulation state after the tick (its ground
        truth ``state.oracle``), the state estimated for the next tick, wall times [s]."""
        rows, m = self.rows, state.oracle
        rows["time"].append(state.time)
        rows["com"].append(m.com)
        rows["com_velocity"].append(m.com_velocity)
        rows["com_reference"].append(output.generator.com)
        rows["zmp_reference"].append(output.generator.zmp)
        rows["zmp_command"].append(output.zmp_command)
        rows["com_target"].append(output.com_target)
        rows["dcm_error"].append(output.dcm_error)
        rows["cop"].append(m.cop)
        rows["contact"].append((m.left_foot.in_contact, m.right_foot.in_contact))
        feet = (m.left_foot, m.right_foot)
        rows["foot_wrenches"].append([np.concatenate((f.force, f.torque)) for f in feet])
        rows["sole_positions"].append(m.sole_positions)
        rows["sole_yaws"].append(m.sole_yaws)
        rows["feet_reference"].append((output.feet.left.position, output.feet.right.position))
        rows["base_rpy"].append((m.roll, m.pitch, m.yaw))
        rows["base_position"].append(m.base_position)
        rows["estimate_time"].append(estimate.time)
        rows["estimated_com"].append(estimate.com)
        rows["estimated_com_velocity"].append(estimate.com_velocity)
        rows["estimated_base_rpy"].append((estimate.roll, estimate.pitch, estimate.yaw))
        rows["estimated_contact"].append(
            (estimate.left_foot.in_contact, estimate.right_foot.in_contact)
        )
        rows["estimated_sole_positions"].append(estimate.sole_positions)
        rows["joint_positions"].append(m.joint_positions)
        rows["joint_targets"].append(output.joint_targets)
        forces = np.full(len(self._actuator_of), np.nan)
        driven = self._actuator_of >= 0
        forces[driven] = np.asarray(actuator_force)[self._actuator_of[driven]]
        rows["actuator_force"].append(forces)
        rows["ik_error"].append(output.ik.task_errors.position_max)
        rows["generator_failed"].append(output.generator_failed)
        rows["generator_tick"].append(output.generator_tick)
        rows["ik_tick"].append(output.ik_tick)
        rows["controller_tick"].append(controller_tick)
        rows["mujoco_step"].append(mujoco_step)
        rows["estimator_tick"].append(estimator_tick)

    def freeze(self) -> WalkLog:
        """The log so far."""
        model = self.robot.mj_model
        actuator_limit = np.where(
            model.actuator_forcelimited.astype(bool),
            np.abs(model.actuator_forcerange).max(axis=1),
            np.inf,
        )
        driven = self._actuator_of >= 0
        limit = np.full(len(self._actuator_of), np.inf)
        limit[driven] = actuator_limit[self._actuator_of[driven]]
        nj = len(self.robot.joint_names)
        empty = {
            **_EMPTY_SHAPES,
            "joint_positions": (0, nj),
            "joint_targets": (0, nj),
            "actuator_force": (0, nj),
        }
        arrays = {}
        # a tick appended in part (an interrupt inside append) is dropped from every series
        complete = min((len(values) for values in self.rows.values()), default=0)
        for name, values in self.rows.items():
            values = values[:complete]
            dtype = bool if name in ("contact", "estimated_contact", "generator_failed") else float
            arrays[name] = frozen_array(
                values if values else np.zeros(empty.get(name, (0,))), dtype=dtype
            )
        return WalkLog(
            **arrays, joint_names=tuple(self.robot.joint_names), torque_limit=frozen_array(limit)
        )


def _actuator_of_joints(robot: "Robot") -> np.ndarray:
    """Index of the actuator driving each of ``robot.joint_names`` (-1: none; the first one
    when several do)."""
    model = robot.mj_model
    index_of = {name: i for i, name in enumerate(robot.joint_names)}
    actuator_of = np.full(len(robot.joint_names), -1, dtype=int)
    for actuator in reversed(range(model.nu)):
        joint = int(model.actuator_trnid[actuator, 0])
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, joint)
        if name in index_of:
            actuator_of[index_of[name]] = actuator
    return actuator_of
