"""mpcwalk: optimization-based walking of humanoid robots.

QP-based preview controllers over the CoM and the ZMP (Kajita preview control,
Wieber linear MPC) beside the closed-form gaits they reformulate (Maximo &
Ribeiro's ZMP walking engine, the static Atlas gait of the DARPA VRC), all
behind one pattern-generator protocol.
"""

from typing import Any

from mpcwalk.exceptions import (
    ConfigurationError,
    FootstepFileError,
    GeneratorNotFound,
    InfeasibleCommand,
    InfeasibleStep,
    MpcwalkError,
    NoSolutionFound,
    NotReset,
    SolverNotFound,
    StabilizerNotFound,
)
from mpcwalk.footsteps import (
    FootGeometry,
    Footstep,
    FootstepPlan,
    LegLimits,
    PathFollower,
    ReachabilityRectangle,
    Side,
    StepTiming,
    VelocityCommand,
    VelocityPlanner,
    plan_from_path,
    plan_from_velocity,
    read_mdat,
    write_mdat,
)
from mpcwalk.gait import ContactSchedule, SwingFootTrajectory, ctraj, jtraj
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.generators import (
    GENERATORS,
    ComState,
    GeneratorOutput,
    Horizon,
    PatternGenerator,
    Rollout,
    SolveInfo,
    generator_names,
    make_generator,
    rollout,
)
from mpcwalk.generators.analytic import AnalyticGenerator
from mpcwalk.generators.preview import PreviewGenerator
from mpcwalk.generators.static import StaticGenerator
from mpcwalk.models import LIPM, CartTable, SupportPolygon, foot_rectangle

__version__ = "0.1.0"

#: Imported on first use: the QP generators pull in qpsolvers and CasADi (~1 s); robots,
#: simulation and the walk load Pinocchio and MuJoCo.
_LAZY = {
    "MpcGenerator": "mpcwalk.generators.mpc",
    "StaticQPGenerator": "mpcwalk.generators.static_qp",
    "MpcParameters": "mpcwalk.qp",
    "WalkingQP": "mpcwalk.qp",
    "load_robot": "mpcwalk.robot",
    "robot_names": "mpcwalk.robot",
    "Robot": "mpcwalk.robot",
    "WholeBodyIK": "mpcwalk.ik",
    "IKTargets": "mpcwalk.ik",
    "Simulation": "mpcwalk.sim",
    "WalkingController": "mpcwalk.control.controller",
    "run_walk": "mpcwalk.walking.runner",
    "WalkSpec": "mpcwalk.walking.specification",
    "ControllerSpec": "mpcwalk.walking.specification",
    "PlanSpec": "mpcwalk.walking.specification",
    "WorldSpec": "mpcwalk.walking.specification",
    "DisturbanceSpec": "mpcwalk.walking.specification",
    "RunSpec": "mpcwalk.walking.specification",
    "read_spec": "mpcwalk.walking.specification",
    "write_spec": "mpcwalk.walking.specification",
    "ModelMismatch": "mpcwalk.sim.model_mismatch",
    "SensorModel": "mpcwalk.sim.sensing.model",
    "SensorReadings": "mpcwalk.robot.sensors",
    "Estimator": "mpcwalk.estimation.estimator",
    "EstimatedState": "mpcwalk.estimation.estimated_state",
    "WalkResult": "mpcwalk.walking.result",
    "WalkMetrics": "mpcwalk.walking.metrics",
    "WalkLog": "mpcwalk.walking.log",
    "FootstepReaiming": "mpcwalk.control.stabilizers.footstep_reaiming",
    "make_stabilizer": "mpcwalk.control.stabilizers",
    "STABILIZERS": "mpcwalk.control.stabilizers",
    "GyroStabilizer": "mpcwalk.control.stabilizers.gyro",
    "ArmSwing": "mpcwalk.control.arm_swing",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'mpcwalk' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY})


__all__ = [
    "GENERATORS",
    "LIPM",
    "STABILIZERS",
    "AnalyticGenerator",
    "ArmSwing",
    "CartTable",
    "ComState",
    "ConfigurationError",
    "ContactSchedule",
    "ControllerSpec",
    "DisturbanceSpec",
    "EstimatedState",
    "Estimator",
    "FootGeometry",
    "Footstep",
    "FootstepFileError",
    "FootstepPlan",
    "FootstepReaiming",
    "GeneratorNotFound",
    "GeneratorOutput",
    "GyroStabilizer",
    "Horizon",
    "IKTargets",
    "InfeasibleCommand",
    "InfeasibleStep",
    "LegLimits",
    "ModelMismatch",
    "MpcGenerator",
    "MpcParameters",
    "MpcwalkError",
    "NoSolutionFound",
    "NotReset",
    "PathFollower",
    "PatternGenerator",
    "PlanSpec",
    "PreviewGenerator",
    "ReachabilityRectangle",
    "Robot",
    "Rollout",
    "RunSpec",
    "SensorModel",
    "SensorReadings",
    "Side",
    "Simulation",
    "SolveInfo",
    "SolverNotFound",
    "StabilizerNotFound",
    "StaticGenerator",
    "StaticQPGenerator",
    "StepTiming",
    "SupportPolygon",
    "SwingFootTrajectory",
    "VelocityCommand",
    "VelocityPlanner",
    "WalkLog",
    "WalkMetrics",
    "WalkResult",
    "WalkSpec",
    "WalkingController",
    "WalkingQP",
    "WholeBodyIK",
    "WorldSpec",
    "ctraj",
    "foot_rectangle",
    "generator_names",
    "jtraj",
    "load_robot",
    "make_generator",
    "make_stabilizer",
    "plan_from_path",
    "plan_from_velocity",
    "read_mdat",
    "read_spec",
    "robot_names",
    "rollout",
    "run_walk",
    "support_margins",
    "write_mdat",
    "write_spec",
]
