"""Whole-body IK on Pinocchio (tasks, QP per tick) and the analytic leg IK of paper M."""

from .joint_bounds import DEFAULT_VELOCITY_LIMIT, JointBounds, solve_box_qp
from .leg_ik import AnalyticLegIK, LegGeometry, LegUnreachable
from .targets import IKResult, IKTargets, TaskErrors
from .tasks import ComTask, FrameTask, PostureTask, Task, update_kinematics
from .whole_body_ik import IKWeights, WholeBodyIK

__all__ = [
    "AnalyticLegIK",
    "ComTask",
    "DEFAULT_VELOCITY_LIMIT",
    "FrameTask",
    "IKResult",
    "IKTargets",
    "IKWeights",
    "JointBounds",
    "LegGeometry",
    "LegUnreachable",
    "PostureTask",
    "Task",
    "TaskErrors",
    "WholeBodyIK",
    "solve_box_qp",
    "update_kinematics",
]
