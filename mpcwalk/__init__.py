"""mpcwalk: optimization-based walking of humanoid robots.

QP-based preview controllers over the CoM and the ZMP (Kajita preview control,
Wieber linear MPC) beside the closed-form gaits they reformulate (Maximo &
Ribeiro's ZMP walking engine, the static Atlas gait of the DARPA VRC), all
behind one pattern-generator protocol.
"""

from .exceptions import (
    ConfigurationError,
    FootstepFileError,
    GeneratorNotFound,
    InfeasibleCommand,
    InfeasibleStep,
    MpcwalkError,
    NoSolutionFound,
    NotReset,
    SolverNotFound,
)
from .footsteps import (
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
from .gait import ContactSchedule, SwingFootTrajectory, ctraj, jtraj
from .generators import (
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
from .generators.analytic import AnalyticGenerator
from .generators.preview import PreviewGenerator
from .generators.static import StaticGenerator
from .metrics import support_margins
from .models import LIPM, CartTable, SupportPolygon, foot_rectangle

__version__ = "0.1.0"

#: Imported on first use: the QP generators pull in qpsolvers and CasADi (~1 s).
_LAZY = {
    "MpcGenerator": ".generators.mpc",
    "StaticQPGenerator": ".generators.static_qp",
    "MpcParameters": ".qp",
    "WalkingQP": ".qp",
    # robots, simulation and the walk load Pinocchio models and MuJoCo
    "load_robot": ".robots",
    "robot_names": ".robots",
    "Robot": ".robots",
    "WholeBodyIK": ".ik",
    "IKTargets": ".ik",
    "Simulation": ".sim",
    "WalkingController": ".controller",
    "run_walk": ".walk",
    "WalkResult": ".walk",
    "PaperAStateMachine": ".paper_a",
    "make_stabilizer": ".stabilizers",
    "GyroStabilizer": ".stabilizers.gyro",
    "ArmSwing": ".gait.arm_swing",
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name], __name__), name)
    raise AttributeError(f"module 'mpcwalk' has no attribute {name!r}")

__all__ = [
    "ArmSwing", "GyroStabilizer", "IKTargets", "PaperAStateMachine", "Robot", "Simulation", "WalkResult", "WalkingController",
    "WholeBodyIK", "load_robot", "make_stabilizer", "robot_names", "run_walk",
    "AnalyticGenerator", "CartTable", "ComState", "ConfigurationError", "ContactSchedule",
    "FootGeometry", "Footstep", "FootstepFileError", "FootstepPlan", "GeneratorNotFound",
    "GeneratorOutput", "Horizon", "InfeasibleCommand", "InfeasibleStep", "LIPM", "LegLimits",
    "MpcGenerator", "MpcParameters", "MpcwalkError", "NoSolutionFound", "NotReset", "PathFollower", "PatternGenerator",
    "PreviewGenerator", "ReachabilityRectangle", "Rollout", "Side", "SolveInfo",
    "SolverNotFound", "StaticGenerator", "StaticQPGenerator", "StepTiming", "SupportPolygon", "SwingFootTrajectory",
    "VelocityCommand", "VelocityPlanner", "WalkingQP", "ctraj", "foot_rectangle", "generator_names", "jtraj",
    "make_generator", "plan_from_path", "plan_from_velocity", "read_mdat", "rollout",
    "support_margins", "write_mdat",
]
