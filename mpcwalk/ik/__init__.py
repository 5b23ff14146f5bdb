"""Whole-body IK on Pinocchio (tasks, QP per tick) and the analytic leg IK of paper M."""

from mpcwalk.ik.joint_bounds import DEFAULT_VELOCITY_LIMIT, JointBounds, solve_box_qp
from mpcwalk.ik.leg_ik import AnalyticLegIK, LegGeometry
from mpcwalk.ik.targets import IKResult, IKTargets, IKWeights, TaskErrors
from mpcwalk.ik.tasks import ComTask, FrameTask, PostureTask, Task, update_kinematics
from mpcwalk.ik.whole_body_ik import WholeBodyIK

__all__ = [
    "DEFAULT_VELOCITY_LIMIT",
    "AnalyticLegIK",
    "ComTask",
    "FrameTask",
    "IKResult",
    "IKTargets",
    "IKWeights",
    "JointBounds",
    "LegGeometry",
    "PostureTask",
    "Task",
    "TaskErrors",
    "WholeBodyIK",
    "solve_box_qp",
    "update_kinematics",
]
