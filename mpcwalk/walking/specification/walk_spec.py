"""One walk, one specification: :class:`WalkSpec` and its run options :class:`RunSpec`.

A walk is a robot, a controller (:class:`ControllerSpec`), a plan (:class:`PlanSpec`), a
world (:class:`WorldSpec`), disturbances (:class:`DisturbanceSpec`) and run options
(:class:`RunSpec`): frozen, each part validated when it is made, written next to every
result as TOML (:mod:`mpcwalk.walking.specification.spec_file`) and read back: the same
specification gives the same walk. :func:`~mpcwalk.walking.runner.run_walk` runs one; a
sweep's case is one (:attr:`WalkSpec.case_id`, the hash of the specification).

The fields of the parts have distinct names, so a specification is also made and changed
field by field (:meth:`WalkSpec.build`, :meth:`WalkSpec.replace`)::

    spec = WalkSpec.build("bioloid-like", controller="mpc", command=(0.1, 0, 0), nb_steps=8)
    heavier = spec.replace(mass_scale=1.2, seed=3)
"""

import dataclasses
import hashlib
import json
from dataclasses import dataclass, field
from typing import Any

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.terrain import Terrain, terrain_to_dict
from mpcwalk.walking.specification.controller import ControllerSpec
from mpcwalk.walking.specification.disturbances import DisturbanceSpec
from mpcwalk.walking.specification.plan import PlanSpec
from mpcwalk.walking.specification.records import command_line, spec_columns
from mpcwalk.walking.specification.world import WorldSpec

#: The controller of a walk that names none.
DEFAULT_CONTROLLER = "mpc"


@dataclass(frozen=True)
class RunSpec:
    """How a walk is run, beyond what it is.

    Attributes:
        seed: Seed of the sensor noise and of the ground's bumps (same seed, same walk).
        progress: Show a progress bar (off: a library is quiet).
        video: MP4 file to render the walk into (offscreen), or None.

    Raises:
        ConfigurationError: A seed that is not an integer >= 0.
    """

    seed: int = 0
    progress: bool = False
    video: str | None = None

    def __post_init__(self) -> None:
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ConfigurationError(f"seed must be an integer >= 0, got {self.seed!r}.")
        if not isinstance(self.progress, bool):
            raise ConfigurationError(f"progress must be true or false, got {self.progress!r}.")
        if self.video is not None:
            object.__setattr__(self, "video", str(self.video))


#: The parts of a :class:`WalkSpec`, by attribute, and their classes.
PARTS: dict[str, type] = {
    "controller": ControllerSpec,
    "plan": PlanSpec,
    "world": WorldSpec,
    "disturbances": DisturbanceSpec,
    "run": RunSpec,
}

#: Field name -> the part that holds it (the controller's ``name`` is the controller's).
FIELDS: dict[str, str] = {
    f.name: part
    for part, cls in PARTS.items()
    for f in dataclasses.fields(cls)
    if not (part == "controller" and f.name == "name")
}


def _labels(value: Any) -> tuple[tuple[str, Any], ...]:
    items = value.items() if isinstance(value, dict) else value
    try:
        labels = tuple((str(name), item) for name, item in items)
    except (TypeError, ValueError):
        raise ConfigurationError(
            f"labels must be (name, value) pairs or a dict, got {value!r}."
        ) from None
    clash = [name for name, _ in labels if name in FIELDS or name in PARTS]
    if clash:
        raise ConfigurationError(f"Labels {clash} would hide fields of the walk specification.")
    return labels


@dataclass(frozen=True)
class WalkSpec:
    """A walk (see the module docstring).

    Attributes:
        robot: Robot name (``mpcwalk robots``) or the path of a preset file (.toml).
        controller: The controller.
        plan: Command or path, how long, timing.
        world: Sensors, state source, the simulated robot's departure from the model, ground.
        disturbances: Pushes and sensor faults.
        run: Seed, progress bar, video.
        labels: ``(name, value)`` pairs saying what a sweep made of the walk (columns of its
            table; they do not change the walk).
    """

    robot: str
    controller: ControllerSpec = field(
        default_factory=lambda: ControllerSpec.named(DEFAULT_CONTROLLER)
    )
    plan: PlanSpec = field(default_factory=PlanSpec)
    world: WorldSpec = field(default_factory=WorldSpec)
    disturbances: DisturbanceSpec = field(default_factory=DisturbanceSpec)
    run: RunSpec = field(default_factory=RunSpec)
    labels: tuple[tuple[str, Any], ...] = ()

    def __post_init__(self) -> None:
        if not isinstance(self.robot, str) or not self.robot:
            robot = self.robot
            if hasattr(robot, "__fspath__"):
                object.__setattr__(self, "robot", str(robot))
            else:
                raise ConfigurationError(
                    f"robot must be a robot name or a preset file, got {robot!r}; "
                    "mpcwalk robots lists the names."
                )
        for part, cls in PARTS.items():
            value = getattr(self, part)
            if not isinstance(value, cls):
                raise ConfigurationError(
                    f"WalkSpec.{part} must be a {cls.__name__}, got {type(value).__name__}; "
                    f"build one with {cls.__name__}(...) or WalkSpec.build(robot, field=...)."
                )
        object.__setattr__(self, "labels", _labels(self.labels))

    @classmethod
    def build(
        cls, robot: str, *, controller: "str | ControllerSpec | None" = None, **fields: Any
    ) -> "WalkSpec":
        """A specification from the robot, a controller (a name, a
        :class:`ControllerSpec`, or None: ``"mpc"``) and fields of any part by name
        (``command=``, ``noise_scale=``, ``pushes=``, ``seed=``, ``generator=``...). A field
        of the controller given beside a named controller changes it (``"custom"``).

        Raises:
            ConfigurationError: An unknown field (the message lists them), or a bad value.
        """
        return cls(robot, _controller(controller)).replace(**fields)

    def replace(self, **fields: Any) -> "WalkSpec":
        """A copy with ``fields`` changed, each by its name (see :data:`FIELDS`), or whole
        parts (``plan=PlanSpec(...)``), ``robot`` and ``labels``.

        Raises:
            ConfigurationError: An unknown field (the message lists them), or a bad value.
        """
        unknown = sorted(set(fields) - set(FIELDS) - set(PARTS) - {"robot", "labels"})
        if unknown:
            raise ConfigurationError(
                f"A walk specification has no field {', '.join(map(repr, unknown))}; its "
                f"fields are robot, labels, {', '.join(FIELDS)}."
            )
        whole = {k: v for k, v in fields.items() if k in PARTS or k in ("robot", "labels")}
        if isinstance(whole.get("controller"), str):
            whole["controller"] = ControllerSpec.named(whole["controller"])
        spec = dataclasses.replace(self, **whole)
        for part in PARTS:
            changes = {k: v for k, v in fields.items() if FIELDS.get(k) == part}
            if not changes:
                continue
            current = getattr(spec, part)
            if part == "controller":
                new = current.replace(**changes)
            else:
                if part == "world" and "ideal" in changes and "state" not in changes:
                    if current.state == ("oracle" if current.ideal else "estimator"):
                        changes["state"] = None  # the state source follows the sensors
                new = dataclasses.replace(current, **changes)
            spec = dataclasses.replace(spec, **{part: new})
        return spec

    def label(self, name: str, default: Any = None) -> Any:
        """The value of a label."""
        return dict(self.labels).get(name, default)

    def to_dict(self) -> dict[str, Any]:
        """The specification as nested plain values (tables per part, lists for tuples,
        None where a field is unset); :meth:`from_dict` reads it back."""
        values: dict[str, Any] = {"robot": self.robot}
        for part in PARTS:
            values[part] = _plain(dataclasses.asdict(getattr(self, part)))
        values["labels"] = {name: _plain(value) for name, value in self.labels}
        return values

    @classmethod
    def from_dict(cls, values: dict[str, Any]) -> "WalkSpec":
        """The specification of :meth:`to_dict`'s values (missing fields: their defaults).

        Raises:
            ConfigurationError: An unknown part or field (the message lists them), or a bad
                value.
        """
        if not isinstance(values, dict) or "robot" not in values:
            raise ConfigurationError(
                'A walk specification needs at least its robot (robot = "bioloid-like").'
            )
        unknown = sorted(set(values) - set(PARTS) - {"robot", "labels"})
        if unknown:
            raise ConfigurationError(
                f"A walk specification has no part {', '.join(map(repr, unknown))}; its parts "
                f"are robot, {', '.join(PARTS)}, labels."
            )
        parts: dict[str, Any] = {}
        for part, part_cls in PARTS.items():
            table = values.get(part, {})
            if not isinstance(table, dict):
                raise ConfigurationError(f"[{part}] must be a table of fields, got {table!r}.")
            names = [f.name for f in dataclasses.fields(part_cls)]
            extra = sorted(set(table) - set(names))
            if extra:
                raise ConfigurationError(
                    f"[{part}] has no field {', '.join(map(repr, extra))}; its fields are "
                    f"{', '.join(names)}."
                )
            kwargs = {k: v for k, v in table.items() if v is not None}
            if part == "controller":
                parts[part] = ControllerSpec.from_fields(kwargs)
            else:
                parts[part] = part_cls(**kwargs)
        return cls(values["robot"], labels=values.get("labels", {}), **parts)

    def to_columns(self) -> dict[str, Any]:
        """The walk as columns of a sweep's results table
        (:func:`~mpcwalk.walking.specification.records.spec_columns`)."""
        return spec_columns(self)

    def command_line(self, out: str = "walk") -> str:
        """The ``mpcwalk walk`` command that walks it again alone
        (:func:`~mpcwalk.walking.specification.records.command_line`)."""
        return command_line(self, out)

    @property
    def case_id(self) -> str:
        """Hash of the specification and its labels (16 hexadecimal digits): the same
        walk, the same id."""
        values = self.to_dict()
        if values["world"]["terrain"] is None:  # walks on the floor keep their ids
            del values["world"]["terrain"]
        if values["world"]["actuation"] == "position":  # position-servo walks keep theirs
            del values["world"]["actuation"]
        for contact in ("friction_cone", "impratio"):  # walks in MuJoCo's default contacts too
            if values["world"][contact] is None:
                del values["world"][contact]
        if not values["plan"]["terrain_cadence"]:  # walks at the plan's own cadence too
            del values["plan"]["terrain_cadence"]
        text = json.dumps(values, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


def _controller(value: "str | ControllerSpec | None") -> ControllerSpec:
    if value is None:
        return ControllerSpec.named(DEFAULT_CONTROLLER)
    if isinstance(value, str):
        return ControllerSpec.named(value)
    if isinstance(value, ControllerSpec):
        return value
    raise ConfigurationError(
        f"controller must be a controller name (mpcwalk controllers) or a ControllerSpec, "
        f"got {value!r}."
    )


def _plain(value: Any) -> Any:
    """Tuples as lists, numpy scalars as Python numbers, a terrain as the tables of its
    file, recursively."""
    if isinstance(value, Terrain):
        return terrain_to_dict(value)
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        return value.item()
    return value


__all__ = ["DEFAULT_CONTROLLER", "FIELDS", "PARTS", "RunSpec", "WalkSpec"]
