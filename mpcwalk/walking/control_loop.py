"""The control loop of a simulated walk: sensors, estimator, controller, simulation, log.

Each tick (DESIGN.md, section 1) the controller receives the state estimated from the
sensor readings (:attr:`~mpcwalk.sim.sim_state.SimState.sensors`: noisy, biased,
quantised, delayed by the latency), or the simulator's ground truth
(:attr:`~mpcwalk.sim.sim_state.SimState.oracle`) when the loop has no estimator (the
explicit ``state="oracle"``); the simulator's ground truth goes to the log and the fall
detector only.
"""

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from mpcwalk.control.controller import WalkingController
from mpcwalk.control.faults import FaultMonitor
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.estimation.estimator import Estimator
from mpcwalk.exceptions import ControllerStopped, SimulationUnstable
from mpcwalk.robot.robot import Robot
from mpcwalk.sim import FallDetector, FallStatus, Simulation
from mpcwalk.sim.sensing.faults import SensorFaults, readings_are_finite
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.metrics import WalkMetrics, sanity_warnings


@dataclass(frozen=True)
class LoopOutcome:
    """What :meth:`ControlLoop.run` returns.

    Attributes:
        log: The per-tick log.
        fall: Verdict of the fall detector at the end (or a diverged simulation).
        wall_time: Wall time of the loop [s].
        stop_reason: Why the controller stopped the walk ("" when it did not).
        interrupted: The loop was interrupted (SIGINT); the log is the partial walk's.
    """

    log: WalkLog
    fall: FallStatus
    wall_time: float
    stop_reason: str = ""
    interrupted: bool = False


class ControlLoop:
    """Runs a controller on a simulated robot until its schedule ends or the robot falls.

    Args:
        robot: The robot (the controller's model; the simulation may perturb its own copy).
        controller: The walking controller, not yet reset.
        simulation: The simulation, with its sensor model and model mismatch.
        estimator: The state estimator; None gives the controller the ground truth.
        detector: The fall detector.
        sensor_faults: Faults injected into the sensor stream (None: none).
    """

    def __init__(
        self,
        robot: Robot,
        controller: WalkingController,
        simulation: Simulation,
        estimator: Estimator | None,
        detector: FallDetector,
        sensor_faults: SensorFaults | None = None,
    ) -> None:
        self.robot = robot
        self.sensor_faults = sensor_faults
        self._last_estimate: EstimatedState | None = None
        self.controller = controller
        self.simulation = simulation
        self.estimator = estimator
        self.detector = detector

    def _estimate(self, state, *, first: bool = False):
        """The state the controller receives after ``state``: readings checked at the
        boundary; a bad or missing one is a sensor fault (the estimator is not updated with
        it, the controller keeps the last estimate and counts the tick as a fallback)."""
        if self.estimator is None:
            return state.oracle
        if first:
            self._last_estimate = self.estimator.reset(state.sensors, self.robot.q0)
            return self._last_estimate
        readings = state.sensors
        if self.sensor_faults is not None:
            readings = self.sensor_faults.apply(readings)
        if not readings_are_finite(readings):
            self.controller.faults.note_sensor_fault()
            return self._last_estimate
        self._last_estimate = self.estimator.update(readings)
        return self._last_estimate

    def run(
        self,
        *,
        video: str | Path | None = None,
        progress: bool = False,
        label: str = "walk",
        observer: Callable[[float, np.ndarray], None] | None = None,
    ) -> LoopOutcome:
        """Reset the simulation at ``robot.q0``, the estimator with its first readings and
        the planned start configuration, the controller; then tick.

        Args:
            video: MP4 file to render the walk into, or None.
            progress: Show a progress bar over the ticks.
            label: Label of the progress bar.
        """
        from tqdm import tqdm

        robot, controller, simulation = self.robot, self.controller, self.simulation
        recorder = None
        if video is not None:
            from mpcwalk.sim import VideoRecorder

            recorder = VideoRecorder(video, simulation.model)
        state = simulation.reset(robot.q0)
        estimate = self._estimate(state, first=True)
        controller.reset(robot.q0)
        log = WalkLog.recorder(robot, controller.schedule)
        fall = FallStatus(False, "", 0.0)
        stop_reason, interrupted = "", False
        nb_ticks = int(math.ceil(controller.schedule.duration / controller.control_period - 1e-9))
        bar = tqdm(total=nb_ticks, desc=label, unit="tick", disable=not progress, leave=False)
        start = time.perf_counter()
        try:
            if recorder is not None:
                recorder.capture(simulation.data, 0.0)
            while not controller.done:
                tick_start = time.perf_counter()
                output = controller.step(estimate)
                sim_start = time.perf_counter()
                try:
                    if output.joint_torques is not None:  # torque motors
                        state = simulation.step(torques=output.joint_torques)
                    else:
                        state = simulation.step(output.joint_targets)
                except SimulationUnstable as error:
                    fall = FallStatus(True, f"simulation diverged ({error})", simulation.time)
                    break
                estimator_start = time.perf_counter()
                estimate = self._estimate(state)
                end = time.perf_counter()
                log.append(
                    output,
                    state,
                    estimate,
                    simulation.data.actuator_force,
                    mujoco_step=estimator_start - sim_start,
                    controller_tick=sim_start - tick_start,
                    estimator_tick=end - estimator_start,
                )
                if recorder is not None:
                    recorder.capture(simulation.data, state.time)
                if observer is not None:  # e.g. a live view: the time and MuJoCo's qpos
                    observer(state.time, simulation.data.qpos)
                bar.update(1)
                fall = self.detector.check(state)
                if fall.fell:
                    break
        except ControllerStopped as stop:  # faults beyond the controller's bound
            stop_reason = stop.reason
        except KeyboardInterrupt:  # the partial walk is still measured and written
            interrupted = True
        finally:
            wall_time = time.perf_counter() - start
            bar.close()
            if recorder is not None:
                recorder.close()
        return LoopOutcome(log.freeze(), fall, wall_time, stop_reason, interrupted)


def with_outcome(metrics: WalkMetrics, outcome: LoopOutcome, faults: FaultMonitor) -> WalkMetrics:
    """``metrics`` with the walk's outcome, its fault counts and its sanity warnings."""
    if outcome.interrupted:
        verdict = "interrupted"
    elif outcome.stop_reason:
        verdict = "stopped"
    else:
        verdict = "fell" if outcome.fall.fell else "walked"
    metrics = replace(
        metrics,
        outcome=verdict,
        stop_reason=outcome.stop_reason,
        interrupted=outcome.interrupted,
        sensor_faults=faults.sensor_faults,
        ik_failures=faults.ik_failures,
        fallback_ticks=faults.fallback_ticks,
    )
    warnings = sanity_warnings(metrics) if verdict == "walked" else ()
    return replace(metrics, warnings=warnings)
