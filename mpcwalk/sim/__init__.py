"""MuJoCo simulation: position-controlled robot, sensors, measured CoP, pushes, falls, video."""

from mpcwalk.sim.contacts import ContactEstimator
from mpcwalk.sim.disturbances import BASE, TORSO, ExternalForce, PushFormatError, parse_push
from mpcwalk.sim.fall_detection import FallDetector, FallStatus
from mpcwalk.sim.measurements import (
    FootContact,
    ImuReading,
    Measurements,
    SimState,
    quaternion_to_rpy,
)
from mpcwalk.sim.rendering import (
    RenderingUnavailable,
    VideoDependencyMissing,
    VideoRecorder,
    gl_backend,
)
from mpcwalk.sim.simulation import SensorNoise, Simulation, SimulationUnstable

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
    "parse_push",
    "quaternion_to_rpy",
]
