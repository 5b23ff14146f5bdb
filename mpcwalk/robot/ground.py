"""The ground under a simulated walk: flat, tilted, or rough (:class:`Ground`).

Every robot's scene is built with a height field (a MuJoCo ``hfield``) lying on its floor,
switched off (no contact, hidden): :func:`add_ground_field`, called where the scene is built.
A :class:`Ground` changes the simulator's own copy of the compiled model
(:meth:`Ground.apply`), never the robot's models, as a
:class:`~mpcwalk.sim.model_mismatch.ModelMismatch` does:

- **roughness**: the height field is switched on with random bumps: heights drawn uniformly
  in ``[0, roughness]`` on a grid of :data:`BUMP_SPACING` and interpolated linearly between
  (a field of :data:`FIELD_HALF_SIZE` around the start, the flat floor beyond); the ground
  under the initial stance stays flat, the bumps rise over one bump spacing around it. The
  seed draws the bumps (same seed, same ground).
- **tilt**: a ground sloping up by ``tilt`` degrees towards the azimuth ``tilt_direction``
  (0: the robot's initial forward direction, 90: its left) is simulated by tilting gravity
  by the same angle: MuJoCo's world frame is then the slope's (its z axis the slope's
  normal), which is physically the same as turning the floor and the robot standing on it,
  without moving the robot's start off the floor. The IMU reads the tilted gravity; the
  footsteps, the ground truth and the metrics are in the slope's frame.
"""

import math
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError

if TYPE_CHECKING:
    from mpcwalk.robot.robot import Robot

FIELD_NAME = "ground_bumps"
"""Name of the height field asset and of its geom in every robot's scene."""

FIELD_HALF_SIZE = 5.0
"""Half side [m] of the square height field, centred on the start."""

FIELD_SPACING = 0.025
"""Distance [m] between the height field's grid points."""

FIELD_MAX_HEIGHT = 0.05
"""Largest bump height [m] the field holds (the largest ``roughness``)."""

BUMP_SPACING = 0.05
"""Distance [m] between the random heights of a rough ground."""

MAX_TILT_DEG = 20.0
"""Steepest slope [deg] accepted."""

DORMANT_AFFINITY = 1 << 30
"""Contact affinity of the height field while it is off: a bit no robot geom sets."""


def add_ground_field(spec: mujoco.MjSpec) -> None:
    """Add the height field, off, to a scene (where the floor is built)."""
    nb = int(round(2.0 * FIELD_HALF_SIZE / FIELD_SPACING)) + 1
    spec.add_hfield(
        name=FIELD_NAME,
        size=[FIELD_HALF_SIZE, FIELD_HALF_SIZE, FIELD_MAX_HEIGHT, 0.01],
        nrow=nb,
        ncol=nb,
        userdata=[0.0] * (nb * nb),  # level: rough grounds write their bumps at run time
    )
    spec.worldbody.add_geom(
        name=FIELD_NAME,
        type=mujoco.mjtGeom.mjGEOM_HFIELD,
        hfieldname=FIELD_NAME,
        contype=0,
        # off: a bit no robot geom has (0 would leave the field out of the collision
        # structures MuJoCo compiles, and switching it on later would have no effect)
        conaffinity=DORMANT_AFFINITY,
        group=3,  # hidden by the default visual options
        rgba=[0.35, 0.32, 0.28, 1.0],
        friction=[1.0, 0.005, 0.0001],
    )


def _number(name: str, value: Any, low: float, high: float, unit: str) -> float:
    return checked_number(f"Ground.{name}", value, low=low, high=high, unit=unit)


@dataclass(frozen=True)
class Ground:
    """The ground of a simulated walk (the default: flat and level).

    Attributes:
        tilt: Slope [deg], in [-20, 20] (negative: sloping down towards ``tilt_direction``).
        tilt_direction: Azimuth [deg] of the uphill direction in the world frame (0: the
            robot's initial forward direction, 90: its left).
        roughness: Largest bump height [m], in [0, 0.05] (0: flat).
        seed: Seed of the bumps.

    Raises:
        ConfigurationError: A value out of its range.
    """

    tilt: float = 0.0
    tilt_direction: float = 0.0
    roughness: float = 0.0
    seed: int = 0

    def __post_init__(self) -> None:
        set_field = object.__setattr__
        set_field(self, "tilt", _number("tilt", self.tilt, -MAX_TILT_DEG, MAX_TILT_DEG, "deg"))
        set_field(
            self,
            "tilt_direction",
            _number("tilt_direction", self.tilt_direction, -360.0, 360.0, "deg"),
        )
        set_field(
            self, "roughness", _number("roughness", self.roughness, 0.0, FIELD_MAX_HEIGHT, "m")
        )
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ConfigurationError(f"Ground.seed must be an integer >= 0, got {self.seed!r}.")

    @property
    def is_flat(self) -> bool:
        """Whether the ground is the level floor (no tilt, no bumps)."""
        return self.tilt == 0.0 and self.roughness == 0.0

    def to_dict(self) -> dict[str, float]:
        """The ground for the ``config`` block of ``metrics.json`` (degrees and metres)."""
        values = asdict(self)
        return {
            "ground_tilt_deg": values["tilt"],
            "ground_tilt_direction_deg": values["tilt_direction"],
            "ground_roughness_m": values["roughness"],
        }

    def changes(self) -> dict[str, float]:
        """The entries of :meth:`to_dict` that differ from the level floor."""
        values = self.to_dict()
        if self.tilt == 0.0:
            del values["ground_tilt_deg"], values["ground_tilt_direction_deg"]
        if self.roughness == 0.0:
            del values["ground_roughness_m"]
        return values

    def gravity(self, magnitude: float = 9.81) -> np.ndarray:
        """Gravity [m/s^2] in the slope's frame."""
        tilt, azimuth = math.radians(self.tilt), math.radians(self.tilt_direction)
        downhill = -math.sin(tilt) * np.array([math.cos(azimuth), math.sin(azimuth)])
        return magnitude * np.array([downhill[0], downhill[1], -math.cos(tilt)])

    def heights(self, clear_radius: float) -> np.ndarray:
        """Heights [m] of the height field's grid, shape (rows along y, columns along x):
        the bumps, zero within ``clear_radius`` [m] of the start."""
        nb = int(round(2.0 * FIELD_HALF_SIZE / FIELD_SPACING)) + 1
        grid = np.linspace(-FIELD_HALF_SIZE, FIELD_HALF_SIZE, nb)
        if self.roughness == 0.0:
            return np.zeros((nb, nb))
        nb_coarse = int(round(2.0 * FIELD_HALF_SIZE / BUMP_SPACING)) + 1
        coarse = np.linspace(-FIELD_HALF_SIZE, FIELD_HALF_SIZE, nb_coarse)
        rng = np.random.default_rng(self.seed)
        values = rng.uniform(0.0, self.roughness, (nb_coarse, nb_coarse))
        # bilinear: along x (columns) on every coarse row, then along y (rows)
        along_x = np.array([np.interp(grid, coarse, row) for row in values])
        heights = np.array([np.interp(grid, coarse, column) for column in along_x.T]).T
        x, y = np.meshgrid(grid, grid)
        taper = np.clip((np.hypot(x, y) - clear_radius) / BUMP_SPACING, 0.0, 1.0)
        return heights * taper

    def apply(self, model: mujoco.MjModel, robot: "Robot | None" = None) -> None:
        """Build this ground into ``model`` in place (the simulator's copy).

        Args:
            model: The compiled MuJoCo model of a robot's scene.
            robot: The robot, whose initial stance stays on flat ground (None: a bump-free
                disc of 0.3 m).

        Raises:
            ConfigurationError: A rough ground on a model without the height field.
        """
        if self.tilt != 0.0:
            model.opt.gravity[:] = self.gravity(float(np.linalg.norm(model.opt.gravity)))
        if self.roughness == 0.0:
            return
        geom = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, FIELD_NAME)
        field = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_HFIELD, FIELD_NAME)
        if geom < 0 or field < 0:
            raise ConfigurationError(
                f"A rough ground needs the height field '{FIELD_NAME}' of the robot's scene; "
                "load the robot with mpcwalk.robot.load_robot."
            )
        heights = self.heights(0.3 if robot is None else clear_radius(robot))
        start, size = int(model.hfield_adr[field]), heights.size
        model.hfield_data[start : start + size] = (heights / model.hfield_size[field, 2]).ravel()
        model.geom_conaffinity[geom] = 1  # the soles collide with it, as with the floor
        model.geom_group[geom] = 0  # visible


def clear_radius(robot: "Robot") -> float:
    """Radius [m] around the start that stays flat: the initial stance's soles."""
    half_diagonal = 0.5 * math.hypot(*robot.sole_size)
    feet = robot.initial_feet()
    return max(float(np.hypot(*foot.position[:2])) for foot in feet) + half_diagonal


__all__ = ["Ground", "add_ground_field", "clear_radius"]
