"""How the simulated robot differs from the model the controller uses: :class:`ModelMismatch`.

A real robot's model is rarely better than 10 %: its trunk is heavier or lighter than the
CAD says, its CoM sits elsewhere, the floor is more slippery than assumed and the servos are
weaker or stiffer. A :class:`ModelMismatch` changes the simulator's own copy of the MuJoCo
model (:class:`~mpcwalk.sim.simulation.Simulation` copies ``robot.mj_model``), never the
robot's models that the controller, the IK and the estimator use.

The trunk is the body of ``robot.torso_frame`` in MuJoCo (``torso`` of ``bioloid-like`` and
``atlas-like``, ``torso_link`` of ``g1``, ``torso_2_link`` of ``talos``), or the root body
when that frame is not a body (:func:`trunk_body`).
"""

from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import mujoco

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import SimulationModelError

MASS_SCALE_RANGE = (0.1, 10.0)
"""Accepted factors on the trunk mass."""

MAX_COM_OFFSET = 0.5
"""Largest CoM shift [m] accepted on each axis."""

FRICTION_RANGE = (0.01, 10.0)
"""Accepted sliding friction coefficients."""

SERVO_STRENGTH_RANGE = (0.1, 10.0)
"""Accepted factors on the servo gains and torque limits."""

FRICTION_CONES = {
    "pyramidal": mujoco.mjtCone.mjCONE_PYRAMIDAL,
    "elliptic": mujoco.mjtCone.mjCONE_ELLIPTIC,
}
"""MuJoCo's friction cones by name."""

IMPRATIO_RANGE = (1.0, 100.0)
"""Accepted ratios of the frictional to the normal constraints' impedance (MuJoCo's
``impratio``)."""


_FIX = "choose a value in that range (ModelMismatch() is the robot as modelled)"


def _error(field: str, value: Any, expected: str | None = None) -> Callable[[str], Exception]:
    """The error of a bad ``field`` (``expected``: what the checks would say otherwise)."""
    return lambda said: SimulationModelError("ModelMismatch", field, value, expected or said, _FIX)


def _in_range(field: str, value: Any, bounds: tuple[float, float]) -> float:
    low, high = bounds
    return checked_number(field, value, low=low, high=high, error=_error(field, value))


@dataclass(frozen=True)
class ModelMismatch:
    """The simulated robot's departure from the model (the default: none).

    Attributes:
        mass_scale: Factor on the trunk's mass and inertia, in [0.1, 10].
        com_offset: Shift ``(dx, dy)`` [m] of the trunk's CoM, in the trunk's frame (x
            forward, y left when upright), each within +-0.5 m.
        friction: Sliding friction coefficient of the floor and the soles (the contacts
            take the larger of the two geoms', so both are set), in [0.01, 10]; None keeps
            the model's.
        servo_strength: Factor on the position servos' stiffness, damping and torque
            limits, and on the torque motors' gain and limits (a joint gives that share of
            the torque it is asked), in [0.1, 10].
        friction_cone: The contacts' friction cone, ``"pyramidal"`` or ``"elliptic"`` (None
            keeps the model's: MuJoCo's default pyramid). With the default ``impratio`` of 1
            MuJoCo's friction is soft: a loaded contact creeps under any tangential force
            (a support sole slid 6 cm down a 5 deg ramp in a 12 s stance); an elliptic cone
            with ``impratio`` 10 holds it (docs/concepts/terrain.md).
        impratio: MuJoCo's ratio of the frictional to the normal constraints' impedance, in
            [1, 100]; above 1 the friction is stiffer (MuJoCo advises it with the elliptic
            cone). None keeps the model's.

    Raises:
        SimulationModelError: A value out of its range (the message gives the range).
    """

    mass_scale: float = 1.0
    com_offset: tuple[float, float] = (0.0, 0.0)
    friction: float | None = None
    servo_strength: float = 1.0
    friction_cone: str | None = None
    impratio: float | None = None

    def __post_init__(self) -> None:
        set_field = object.__setattr__
        set_field(self, "mass_scale", _in_range("mass_scale", self.mass_scale, MASS_SCALE_RANGE))
        expected = f"two numbers (dx, dy) [m] each within +-{MAX_COM_OFFSET:g} m"
        error = _error("com_offset", self.com_offset, expected)
        try:
            offset = tuple(self.com_offset)
        except TypeError:
            raise error(expected) from None
        if len(offset) != 2:
            raise error(expected)
        dx, dy = (
            checked_number(
                "com_offset", value, low=-MAX_COM_OFFSET, high=MAX_COM_OFFSET, error=error
            )
            for value in offset
        )
        set_field(self, "com_offset", (dx, dy))
        if self.friction is not None:
            set_field(self, "friction", _in_range("friction", self.friction, FRICTION_RANGE))
        set_field(
            self,
            "servo_strength",
            _in_range("servo_strength", self.servo_strength, SERVO_STRENGTH_RANGE),
        )
        if self.friction_cone is not None and self.friction_cone not in FRICTION_CONES:
            expected = f"one of {', '.join(FRICTION_CONES)}"
            raise _error("friction_cone", self.friction_cone, expected)(expected)
        if self.impratio is not None:
            set_field(self, "impratio", _in_range("impratio", self.impratio, IMPRATIO_RANGE))

    @property
    def is_nominal(self) -> bool:
        """Whether the simulated robot is the model (no mismatch)."""
        return self == ModelMismatch()

    def to_dict(self) -> dict[str, Any]:
        """The mismatch for the ``config`` block of ``metrics.json`` (JSON types)."""
        values = asdict(self)
        values["com_offset"] = list(self.com_offset)
        return values

    @classmethod
    def from_dict(cls, values: dict[str, Any]) -> "ModelMismatch":
        """The mismatch of :meth:`to_dict`'s output (a sweep's stored case)."""
        values = dict(values)
        if "com_offset" in values:
            values["com_offset"] = tuple(values["com_offset"])
        return cls(**values)

    def apply(self, model: mujoco.MjModel, *, trunk: int) -> None:
        """Perturb ``model`` in place (the simulator's copy, never ``robot.mj_model``).

        Args:
            model: The MuJoCo model to change.
            trunk: Body index of the trunk (:func:`trunk_body`).
        """
        if self.is_nominal:
            return
        if self.friction_cone is not None:
            model.opt.cone = FRICTION_CONES[self.friction_cone]
        if self.impratio is not None:
            model.opt.impratio = self.impratio
        model.body_mass[trunk] *= self.mass_scale
        model.body_inertia[trunk] *= self.mass_scale
        model.body_ipos[trunk, :2] += self.com_offset
        if self.friction is not None:
            colliding = (model.geom_contype != 0) | (model.geom_conaffinity != 0)
            model.geom_friction[colliding, 0] = self.friction
        servos = (model.actuator_gaintype == mujoco.mjtGain.mjGAIN_FIXED) & (
            model.actuator_biastype == mujoco.mjtBias.mjBIAS_AFFINE
        )
        model.actuator_gainprm[servos, 0] *= self.servo_strength  # kp
        model.actuator_biasprm[servos, 1:3] *= self.servo_strength  # -kp, -kv
        model.actuator_forcerange[servos] *= self.servo_strength
        motors = (model.actuator_gaintype == mujoco.mjtGain.mjGAIN_FIXED) & (
            model.actuator_biastype == mujoco.mjtBias.mjBIAS_NONE
        )
        model.actuator_gainprm[motors, 0] *= self.servo_strength  # torque per command
        model.actuator_forcerange[motors] *= self.servo_strength
        mujoco.mj_setConst(model, mujoco.MjData(model))  # subtree masses and the like


def trunk_body(model: mujoco.MjModel, torso_frame: str) -> int:
    """MuJoCo body index of the trunk: the body named ``torso_frame``, else the root body
    (the body of the floating base)."""
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, torso_frame)
    return int(body) if body >= 0 else int(model.jnt_bodyid[0])


__all__ = ["FRICTION_CONES", "IMPRATIO_RANGE", "ModelMismatch", "trunk_body"]
