"""MuJoCo simulation: position-controlled robot, sensors, measured CoP, pushes, falls, video."""

from .contacts import ContactEstimator
from .disturbances import BASE, TORSO, ExternalForce, PushFormatError, parse_push
from .fall_detection import FallDetector, FallStatus
from .measurements import FootContact, ImuReading, Measurements, SimState, quaternion_to_rpy
from .rendering import RenderingUnavailable, VideoDependencyMissing, VideoRecorder, gl_backend
from .simulation import SensorNoise, Simulation, SimulationUnstable

__all__ = [
    "BASE",
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
    "TORSO",
    "VideoDependencyMissing",
    "VideoRecorder",
    "gl_backend",
    "parse_push",
    "quaternion_to_rpy",
]
