"""MuJoCo simulation: position-controlled robot, sensors, measured CoP, pushes, falls, video."""

from mpcwalk.robot.sensors import FootContact, ImuReading, Measurements
from mpcwalk.sim.contacts import ContactEstimator
from mpcwalk.sim.disturbances import BASE, TORSO, ExternalForce, PushFormatError, parse_push
from mpcwalk.sim.fall_detection import FallDetector, FallStatus
from mpcwalk.sim.measurements import SimState, quaternion_to_rpy
from mpcwalk.sim.rendering import (
    RenderingUnavailable,
    VideoDependencyMissing,
    VideoRecorder,
    gl_backend,
)
from mpcwalk.sim.simulation import SensorNoise, Simulation, SimulationUnstable, make_mj_data

__all__ = [
    "BASE",
    "TORSO",
    "ContactEstimator",
    "ExternalForce",
    "FallDetector",
    "FallStatus",
    "FootContact",
    "ImuReading",
    "Measurements",
    "PushFormatError",
    "RenderingUnavailable",
    "SensorNoise",
    "SimState",
    "Simulation",
    "SimulationUnstable",
    "VideoDependencyMissing",
    "VideoRecorder",
    "gl_backend",
    "make_mj_data",
    "parse_push",
    "quaternion_to_rpy",
]
