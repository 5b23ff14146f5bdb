"""MuJoCo simulation: position-controlled robot, sensors with noise and latency
(:mod:`~mpcwalk.sim.sensing`), the simulated robot's mismatch with the controller's model
(:mod:`~mpcwalk.sim.model_mismatch`), ground truth, pushes (:mod:`~mpcwalk.sim.pushes`),
falls, video."""

from mpcwalk.robot.sensors import FootContact, ForceTorqueReading, ImuReading, SensorReadings
from mpcwalk.sim.contacts import ContactWrenches
from mpcwalk.sim.fall_detection import FallDetector, FallStatus
from mpcwalk.sim.ground_truth import GroundTruth
from mpcwalk.sim.model_mismatch import ModelMismatch, trunk_body
from mpcwalk.sim.pushes import BASE, TORSO, ExternalForce, parse_push
from mpcwalk.sim.rendering import VideoRecorder, gl_backend
from mpcwalk.sim.sensing.model import SensorModel
from mpcwalk.sim.sensing.simulator import SensorSimulator
from mpcwalk.sim.sim_state import SimState, quaternion_to_rpy
from mpcwalk.sim.simulation import Simulation, make_mj_data

__all__ = [
    "BASE",
    "TORSO",
    "ContactWrenches",
    "ExternalForce",
    "FallDetector",
    "FallStatus",
    "FootContact",
    "ForceTorqueReading",
    "GroundTruth",
    "ImuReading",
    "ModelMismatch",
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
