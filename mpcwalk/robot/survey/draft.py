"""A preset drafted from a description alone: what ``mpcwalk robots init`` writes.

:func:`draft_preset` reads a URDF, repairs what MuJoCo refuses, finds the legs, up and
forward (:mod:`~mpcwalk.robot.survey.legs`), the soles, the torso
(:mod:`~mpcwalk.robot.survey.upper_body`), solves the walking posture
(:mod:`~mpcwalk.robot.survey.posture`) and sizes the servos and the gait
(:mod:`~mpcwalk.robot.survey.rules`) into a :class:`~mpcwalk.robot.survey.parts.PresetDraft`;
:func:`~mpcwalk.robot.survey.writer.preset_toml` writes it as a preset whose every guessed
number carries, as a comment, where it came from.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.base_orientation import reorient_urdf_root
from mpcwalk.robot.joint_role_detection import detect_joint_roles
from mpcwalk.robot.survey import rules
from mpcwalk.robot.survey.legs import AXES, LegSurvey, body_of, find_legs
from mpcwalk.robot.survey.parts import PresetDraft, Servo, Sole
from mpcwalk.robot.survey.posture import Posture, solve_posture
from mpcwalk.robot.survey.upper_body import joint_loads, standing_torques, torso_frame
from mpcwalk.robot.urdf_repair import repair_inertias


def _sole_centre(sole: Sole) -> np.ndarray:
    return np.asarray(sole.offset, dtype=float)


def draft_preset(
    description: Path,
    *,
    name: str | None = None,
    reference: str = "",
    soles: tuple[Sole, Sole] | None = None,
    srdf: str | Path | None = None,
    timestep: float = 0.002,
) -> PresetDraft:
    """Draft the preset of the URDF humanoid ``description``.

    Args:
        description: URDF file.
        name: Robot name (default: the URDF's ``<robot name>``).
        reference: How the preset names the description (default: the file's path).
        soles: Sole of each foot (default: found from the foot's geometry).
        srdf: An SRDF file whose reference posture (``half_sitting``, ``standing``, else its
            first ``group_state``) gives the joints outside the legs (arms, head) and the
            legs' starting point.
        timestep: Physics time step of the preset [s].

    Raises:
        ConfigurationError: Not a URDF biped this draft can read (the message says what is
            missing and that a preset can be written by hand).
    """
    if description.suffix.lower() != ".urdf":
        raise ConfigurationError(
            f"robots init reads URDF files; got {description.name}. Write an MJCF robot's "
            "preset by hand (docs: Add a robot)."
        )
    text, repaired = repair_inertias(description.read_text())
    try:
        model = pin.buildModelFromXML(text, pin.JointModelFreeFlyer())
    except (RuntimeError, ValueError) as error:
        raise ConfigurationError(
            f"Pinocchio cannot read {description.name} ({error}); check it is a valid URDF."
        ) from error
    described = find_legs(model)
    if (described.forward, described.up) != ("x", "z"):
        # from here on in the loader's frame: the root re-expressed x forward, z up
        text = reorient_urdf_root(text, described.forward, described.up)
        model = pin.buildModelFromXML(text, pin.JointModelFreeFlyer())
    legs = find_legs(model)
    if soles is None:
        from mpcwalk.robot.survey.feet import soles_from_geometry

        soles = soles_from_geometry(description, model, legs)
    start, notes = None, []
    if srdf is not None:
        start, state = _reference_posture(model, Path(srdf))
        notes.append(f"the joints outside the legs take the SRDF's '{state}' posture")
    posture = solve_posture(
        model, legs, (_sole_centre(soles[0]), _sole_centre(soles[1])), q_start=start
    )
    up = AXES[legs.up]
    data = model.createData()
    pin.framesForwardKinematics(model, data, posture.q)
    hip = data.oMi[model.getJointId(legs.left.joints[0])].translation
    sole_world = data.oMf[model.getFrameId(legs.left.foot)].act(_sole_centre(soles[0]))
    leg_length = float((hip - sole_world) @ up)
    mass = float(sum(inertia.mass for inertia in model.inertias[1:]))
    servos = _servos(model, posture, legs, mass, leg_length, timestep)
    if repaired:
        notes.append(f"repaired the inertia of {len(repaired)} link(s): {', '.join(repaired)}")
    roles = detect_joint_roles(model, posture.q, (legs.left.foot, legs.right.foot))
    notes += list(roles.notes)
    return PresetDraft(
        base=(described.forward, described.up),
        roles=roles,
        imu=_imu_link(model, legs),
        name=name or str(model.name) or description.stem,
        description=reference or description.as_posix(),
        legs=legs,
        soles=soles,
        torso=torso_frame(model, posture.q, legs),
        posture=posture,
        leg_length=leg_length,
        mass=mass,
        servos=servos,
        gait=rules.gait_table(
            posture.com_height,
            leg_length,
            min(s.size[1] for s in soles),
            _half_stance(model, posture.q, legs, soles),
        ),
        repaired_links=tuple(repaired),
        notes=tuple(notes),
    )


def _half_stance(
    model: pin.Model, q: np.ndarray, legs: LegSurvey, soles: tuple[Sole, Sole]
) -> float:
    """Half the lateral distance [m] between the sole centres at ``q``."""
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    centres = [
        data.oMf[model.getFrameId(leg.foot)].act(_sole_centre(sole))
        for leg, sole in zip((legs.left, legs.right), soles)
    ]
    return 0.5 * abs(float(centres[0][1] - centres[1][1]))


def _imu_link(model: pin.Model, legs: LegSurvey) -> tuple[str, str]:
    """The IMU's link and why: a body fixed to the base named like an IMU, else the base
    (where most humanoids carry it)."""
    base = body_of(model, 1)
    for frame in model.frames:
        if (
            frame.parentJoint == 1
            and frame.type == pin.FrameType.BODY
            and "imu" in frame.name.lower()
        ):
            return str(frame.name), "a body fixed to the base, named as an IMU"
    return base, "the base, where most humanoids carry their IMU; name yours here"


def _reference_posture(model: pin.Model, srdf: Path) -> tuple[np.ndarray, str]:
    """The SRDF's reference configuration (base at the origin) and its name."""
    if not srdf.is_file():
        raise ConfigurationError(f"--srdf {srdf} is not a file; give the path of an SRDF file.")
    try:
        pin.loadReferenceConfigurations(model, str(srdf), False)
    except (RuntimeError, ValueError) as error:
        raise ConfigurationError(
            f"Pinocchio cannot read the SRDF {srdf.name} ({error})."
        ) from error
    states = {str(entry.key()): np.array(entry.data()) for entry in model.referenceConfigurations}
    if not states:
        raise ConfigurationError(f"The SRDF {srdf.name} has no <group_state> posture.")
    state = next((s for s in ("half_sitting", "standing") if s in states), next(iter(states)))
    q = states[state].astype(float)
    q[:3] = 0.0
    q[3:7] = (0.0, 0.0, 0.0, 1.0)
    return q, state


def _servos(
    model: pin.Model,
    posture: Posture,
    legs: LegSurvey,
    mass: float,
    leg_length: float,
    timestep: float,
) -> tuple[Servo, ...]:
    """The servo of every joint by :mod:`~mpcwalk.robot.survey.rules`."""
    leg_kp = rules.leg_stiffness(mass, leg_length)
    torques = standing_torques(model, posture.q, (legs.left.foot, legs.right.foot), legs.up)
    loads = joint_loads(model, posture.q)
    leg_joints = {*legs.left.joints, *legs.right.joints}
    servos = []
    for joint_id in range(2, model.njoints):
        joint = str(model.names[joint_id])
        if joint in leg_joints:
            kp, rule = leg_kp, f"leg: {rules.LEG_STIFFNESS:g} m g l"
        else:
            carried, reach = loads[joint]
            kp = rules.other_stiffness(carried, reach, leg_kp)
            rule = f"carries {carried:.2f} kg at {reach:.3f} m"
        limit = float(model.effortLimit[model.idx_vs[joint_id]])
        servos.append(
            Servo(
                joint=joint,
                kp=_round(kp),
                kv=_round(rules.damping(kp)),
                armature=_round(rules.armature(kp, timestep)),
                standing_torque=torques[joint],
                torque_limit=limit if math.isfinite(limit) else 0.0,
                rule=rule,
            )
        )
    return tuple(servos)


def _round(value: float, digits: int = 3) -> float:
    """``value`` to ``digits`` significant digits."""
    if value == 0.0:
        return 0.0
    return round(value, digits - 1 - int(math.floor(math.log10(abs(value)))))


__all__ = ["draft_preset"]
