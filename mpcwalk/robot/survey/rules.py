"""The numbers of a preset derived from the robot's own data, by documented rules.

Every rule is written next to the number it gives (``robots init`` copies it into the
preset's comments), so a user can read where a value came from and change it. Symbols:
``m`` the robot's mass [kg], ``g`` gravity, ``l`` the leg length (hip height above the soles
in the walking posture) [m], ``z_c`` the CoM height [m], ``T_c = sqrt(z_c / g)`` the LIPM's
time constant [s], ``dt`` the physics time step [s].

Servos (position actuators of MuJoCo):

- legs: ``kp = LEG_STIFFNESS * m g l`` [N m/rad]: a leg joint deflects by 1/LEG_STIFFNESS
  rad under the robot's whole weight at the leg's length (the shipped presets, tuned by
  hand, use 1.3 to 1.8 on ``g1``, 2.9 on ``talos``; at 2 ``talos`` stands tilted 6 deg);
- the other joints: ``kp = OTHER_STIFFNESS * m_s g r_s`` from the mass ``m_s`` the joint
  carries and the distance ``r_s`` of its CoM, at least :data:`MIN_STIFFNESS_SHARE` of the
  legs';
- ``kv = DAMPING_TIME * kp`` (a servo time constant of 30 ms, as the shipped presets);
- ``armature = kp (dt / STABLE_STEP)^2``: the servo's natural frequency times the time
  step stays under :data:`STABLE_STEP` rad, where MuJoCo's implicit integration of a stiff
  servo stays accurate.

Gait (the ``[gait]`` table):

- ``step_duration = STEP_TIME_CONSTANTS * T_c`` rounded to 50 ms, at least 0.5 s (paper M's
  robot walks at 0.5 s; ``g1``: 0.6 s);
- ``step_height = STEP_HEIGHT_SHARE * l``; reach per step forward / backward / outward
  ``0.30 / 0.15 / 0.12 l`` (``g1``: 0.20 / 0.10 / 0.08 m);
- ``y_sep = (sole width + 0.1 l) / 2``: soles never closer than 10 % of the leg, and at
  most 95 % of the walking posture's half stance (the planner's nominal stance must keep
  it);
- the MPC samples every 50 ms over three steps.
"""

from __future__ import annotations

import math

GRAVITY = 9.81  # [m/s^2]
LEG_STIFFNESS = 3.0
OTHER_STIFFNESS = 10.0
MIN_STIFFNESS_SHARE = 0.005
DAMPING_TIME = 0.03  # [s]
STABLE_STEP = 0.3  # [rad]
STEP_TIME_CONSTANTS = 2.3
MIN_STEP_DURATION = 0.5  # [s]
STEP_HEIGHT_SHARE = 0.09
MPC_SAMPLING_PERIOD = 0.05  # [s]
MPC_HORIZON_STEPS = 3.0


def leg_stiffness(mass: float, leg_length: float) -> float:
    """Stiffness of a leg joint's servo [N m/rad]."""
    return LEG_STIFFNESS * mass * GRAVITY * leg_length


def other_stiffness(carried_mass: float, reach: float, leg_kp: float) -> float:
    """Stiffness [N m/rad] of a joint that carries ``carried_mass`` [kg] whose CoM lies
    ``reach`` [m] from it."""
    return max(OTHER_STIFFNESS * carried_mass * GRAVITY * reach, MIN_STIFFNESS_SHARE * leg_kp)


def damping(kp: float) -> float:
    """Velocity gain [N m s/rad] of a servo of stiffness ``kp``."""
    return DAMPING_TIME * kp


def armature(kp: float, timestep: float) -> float:
    """Reflected rotor inertia [kg m^2] that keeps a servo of stiffness ``kp`` accurate at
    the time step ``timestep`` [s]."""
    return kp * (timestep / STABLE_STEP) ** 2


def step_duration(com_height: float) -> float:
    """Step duration [s] from the CoM height [m]."""
    time_constant = math.sqrt(com_height / GRAVITY)
    return max(MIN_STEP_DURATION, round(STEP_TIME_CONSTANTS * time_constant / 0.05) * 0.05)


def gait_table(
    com_height: float, leg_length: float, sole_width: float, half_stance: float
) -> dict[str, float]:
    """The ``[gait]`` table of a robot (values rounded for the preset); ``half_stance`` [m]
    is half the lateral distance of the sole centres in the walking posture."""
    period = step_duration(com_height)
    return {
        "step_duration": round(period, 2),
        "double_support_ratio": 0.2,
        "step_height": round(STEP_HEIGHT_SHARE * leg_length, 3),
        "y_sep": round(min(0.5 * (sole_width + 0.1 * leg_length), 0.95 * half_stance), 3),
        "max_step_forward": round(0.30 * leg_length, 3),
        "max_step_backward": round(0.15 * leg_length, 3),
        "max_step_lateral": round(0.12 * leg_length, 3),
        "max_step_yaw": 0.35,
        "max_step_yaw_inward": 0.2,
        "mpc_sampling_period": MPC_SAMPLING_PERIOD,
        "mpc_horizon": math.ceil(MPC_HORIZON_STEPS * period / MPC_SAMPLING_PERIOD),
    }


__all__ = [
    "armature",
    "damping",
    "gait_table",
    "leg_stiffness",
    "other_stiffness",
    "step_duration",
]
