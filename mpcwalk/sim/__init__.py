"""MuJoCo simulation: position-controlled robot, sensors with noise and latency, perturbed
worlds, ground truth, pushes, falls, video."""

from mpcwalk.robot.sensors import FootContact, ForceTorqueReading, ImuReading, SensorReadings
from mpcwalk.sim.contacts import ContactEstimator
from mpcwalk.sim.disturbances import BASE, TORSO, ExternalForce, parse_push
from mpcwalk.sim.fall_detection import FallDetector, FallStatus
from mpcwalk.sim.ground_truth import GroundTruth
from mpcwalk.sim.measurements import SimState, quaternion_to_rpy
from mpcwalk.sim.perturbation import Perturbation, trunk_body
from mpcwalk.sim.rendering import VideoRecorder, gl_backend
from mpcwalk.sim.sensor_model import SensorModel
from mpcwalk.sim.sensor_simulator import SensorSimulator
from mpcwalk.sim.simulation import Simulation, make_mj_data

__all__ = [
    "BASE",
    "TORSO",
    "ContactEstimator",
    "ExternalForce",
    "FallDetector",
    "FallStatus",
    "FootContact",
    "ForceTorqueReading",
    "GroundTruth",
    "ImuReading",
    "Perturbation",
    "SensorModel",
    "SensorReadings",
    "SensorSimulator",
    "SimState",
    "Simulation",
    "VideoRecorder",
    "gl_backend",
    "make_mj_data",
    "parse_push",
    "quaternion_to_rpy",
    "trunk_body",
]
