"""The text of a drafted preset: TOML, every guessed number with a comment saying how."""

from __future__ import annotations

from typing import TYPE_CHECKING

from mpcwalk.robot.survey import rules
from mpcwalk.robot.survey.posture import HIP_HEIGHT_RATIO

if TYPE_CHECKING:
    from mpcwalk.robot.survey.parts import PresetDraft

#: Column of the comments.
_COLUMN = 36


def _line(text: str, comment: str = "") -> str:
    return f"{text:<{_COLUMN - 1}} # {comment}" if comment else text


def _number(value: float) -> str:
    return f"{value:.6g}" if abs(value) >= 1e-4 or value == 0.0 else f"{value:.3e}"


def _vector(values) -> str:
    return "[" + ", ".join(_number(float(v)) for v in values) + "]"


def preset_toml(draft: PresetDraft) -> str:
    """The preset of ``draft`` as the text of a TOML file."""
    legs, left_sole, right_sole = draft.legs, draft.soles[0], draft.soles[1]
    out = [
        f"# Preset of {draft.name}, drafted by `mpcwalk robots init` from its description.",
        "# Each number was found from the description; its comment says how. Change what you",
        "# know better, then run `mpcwalk robots check` on this file.",
    ]
    out += [f"# note: {note}" for note in draft.notes]
    out += [f"# LOOK: {warning}" for warning in draft.warnings]
    out += [
        f'name = "{draft.name}"',
        'format = "urdf"',
        f'description = "{draft.description}"',
        _line(f'torso_frame = "{draft.torso[0]}"', draft.torso[1]),
        _line(
            f"com_height = {draft.posture.com_height:.4f}",
            "[m] CoM above the soles in the walking posture",
        ),
        _line("timestep = 0.002", "[s] physics time step"),
        "",
        "[base]                             # axes of the description's root link",
        _line(
            f'forward = "{draft.base[0]}"',
            "the knees bend towards their larger range, the feet go back",
        ),
        _line(f'up = "{draft.base[1]}"', "from the feet to the hips, legs straight"),
        "",
        "[feet]                             # the two ends of the leg chains",
        _line(
            f'left = "{legs.left.foot}"', f"left of up x forward; leg {', '.join(legs.left.joints)}"
        ),
        _line(f'right = "{legs.right.foot}"', f"leg {', '.join(legs.right.joints)}"),
        _line(f"sole_offset = {_vector(left_sole.offset)}", f"[m] {left_sole.source}"),
        _line(f"sole_size = {_vector(left_sole.size)}", "[m] length, width"),
    ]
    if any(left_sole.rpy):
        out.append(
            _line(
                f"sole_rpy = {_vector(left_sole.rpy)}",
                "[rad] the foot link is turned from its sole",
            )
        )
    if any(abs(a - b) > 0.005 for a, b in zip(left_sole.offset, right_sole.offset)):
        out.append(f"# the right sole's centre differs: {_vector(right_sole.offset)} [m]")
    out += [
        "",
        "[imu]",
        _line(f'frame = "{draft.imu[0]}"', draft.imu[1]),
        "",
        "[joints]                           # roles from the axes and the chain order",
    ]
    out += [f'{key} = "{joint}"' for key, joint in draft.roles.names.items() if joint]
    if not draft.roles.has_arms:
        out.append(_line("arms = false", "no arm found: paper M walks without arm swing"))
    out += [
        "",
        f"[nominal_posture]                  # [rad] hips at {HIP_HEIGHT_RATIO:.0%} of their "
        "straight height, soles flat, CoM above the soles",
    ]
    out += [f"{joint} = {angle:.4f}" for joint, angle in draft.posture.angles.items()]
    out += ["", f"# Servos: mass m = {draft.mass:.2f} kg, leg l = {draft.leg_length:.3f} m."]
    for servo in draft.servos:
        share = (
            f", stands at {abs(servo.standing_torque) / servo.torque_limit:.0%} of "
            f"{servo.torque_limit:g} N m"
            if servo.torque_limit > 0
            else ", no torque limit"
        )
        out += [
            "[[actuators]]",
            f'joints = "{servo.joint}"',
            _line(f"kp = {_number(servo.kp)}", f"[N m/rad] {servo.rule}{share}"),
            _line(f"kv = {_number(servo.kv)}", f"[N m s/rad] {rules.DAMPING_TIME:g} s x kp"),
            _line(f"armature = {_number(servo.armature)}", "[kg m^2] kp (dt / 0.3)^2"),
        ]
    out += ["", "[gait]                             # from the leg l and the LIPM's T_c"]
    comments = {
        "step_duration": f"[s] {rules.STEP_TIME_CONSTANTS:g} T_c, at least 0.5 s",
        "double_support_ratio": "paper M",
        "step_height": f"[m] {rules.STEP_HEIGHT_SHARE:g} l",
        "y_sep": "[m] (sole width + 0.1 l) / 2, at most 0.95 of the half stance",
        "max_step_forward": "[m] 0.30 l",
        "max_step_backward": "[m] 0.15 l",
        "max_step_lateral": "[m] 0.12 l",
        "max_step_yaw": "[rad]",
        "max_step_yaw_inward": "[rad]",
        "mpc_sampling_period": "[s]",
        "mpc_horizon": "three steps",
    }
    for key, value in draft.gait.items():
        text = f"{key} = {value}" if isinstance(value, int) else f"{key} = {_number(value)}"
        out.append(_line(text, comments.get(key, "")))
    return "\n".join(out) + "\n"


__all__ = ["preset_toml"]
