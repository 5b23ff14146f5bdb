"""Whole-body IK on Pinocchio (tasks, QP per tick), the analytic leg IK of paper M and the
whole-body inverse dynamics (a QP per tick giving the joint torques)."""

from mpcwalk.ik.dynamics_targets import (
    DynamicsGains,
    DynamicsResult,
    DynamicsTargets,
    DynamicsWeights,
)
from mpcwalk.ik.inverse_dynamics import InverseDynamicsQP, torque_limits
from mpcwalk.ik.joint_bounds import DEFAULT_VELOCITY_LIMIT, JointBounds, solve_box_qp
from mpcwalk.ik.leg_ik import AnalyticLegIK, LegGeometry
from mpcwalk.ik.targets import IKResult, IKTargets, IKWeights, TaskErrors
from mpcwalk.ik.tasks import ComTask, FrameTask, PostureTask, Task, update_kinematics
from mpcwalk.ik.whole_body_ik import WholeBodyIK

__all__ = [
    "DEFAULT_VELOCITY_LIMIT",
    "AnalyticLegIK",
    "ComTask",
    "DynamicsGains",
    "DynamicsResult",
    "DynamicsTargets",
    "DynamicsWeights",
    "FrameTask",
    "IKResult",
    "IKTargets",
    "IKWeights",
    "InverseDynamicsQP",
    "JointBounds",
    "LegGeometry",
    "PostureTask",
    "Task",
    "TaskErrors",
    "WholeBodyIK",
    "solve_box_qp",
    "torque_limits",
    "update_kinematics",
]
