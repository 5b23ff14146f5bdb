"""Paper A's comparison: its controllers, paths and steps, read from the ``config.toml``
beside this module (:func:`load_config`); the paths are the ``.mdat`` files of ``paths/``."""

from dataclasses import dataclass, fields
from pathlib import Path

from mpcwalk.experiments.paper_a.walks import TimedController
from mpcwalk.experiments.protocol import config_path, mode_name, read_config, unknown_keys
from mpcwalk.robot.package_data import package_data_dir

DEFAULT_CONFIG = config_path("mpcwalk.experiments.paper_a")

#: The folder of paper A's ``.mdat`` paths (``straight.mdat``, ``turning.mdat``, and the 3D
#: ``ramp.mdat`` with the terrain it crosses, ``ramp.toml``).
PATHS_DIR = package_data_dir("mpcwalk.experiments.paper_a") / "paths"


@dataclass(frozen=True)
class PaperAConfig:
    """What paper A's comparison runs.

    Attributes:
        specs: The controllers.
        paths: Path names (``PATHS_DIR/<name>.mdat``).
        robot: Robot name.
        nb_steps: Steps kept from each path (None: all).
        slow_nb_steps: Steps kept for controllers with T >= 3 s (None: as ``nb_steps``).
        mode: ``"full"`` or ``"quick"``.
    """

    specs: tuple[TimedController, ...]
    paths: tuple[str, ...] = ("straight", "turning", "ramp")
    robot: str = "atlas-like"
    nb_steps: int | None = None
    slow_nb_steps: int | None = None
    mode: str = "full"


def _spec(values: dict) -> TimedController:
    unknown_keys(values, [f.name for f in fields(TimedController)], "controllers")
    options = tuple((k, float(v)) for k, v in values.get("generator_options", {}).items())
    return TimedController(**{**values, "generator_options": options})


def load_config(path: str | Path = DEFAULT_CONFIG, *, quick: bool = False) -> PaperAConfig:
    """Read the comparison from TOML; ``quick`` applies its ``[quick]`` table (its
    ``controllers``: labels of the full list).

    Raises:
        ConfigurationError: An unknown key, or a quick controller that is not in the list.
    """
    from mpcwalk.exceptions import ConfigurationError

    data, small = read_config(path, quick=quick)
    keys = ("robot", "paths", "controllers", "nb_steps", "slow_nb_steps")
    unknown_keys(data, keys, "paper A")
    unknown_keys(small, keys, "quick")
    specs = tuple(_spec(values) for values in data.get("controllers", []))
    if "controllers" in small:
        labels = {spec.label: spec for spec in specs}
        missing = [label for label in small["controllers"] if label not in labels]
        if missing:
            raise ConfigurationError(
                f"[quick] controllers {missing} are not labels of [[controllers]]; the labels "
                f"are {list(labels)}."
            )
        specs = tuple(labels[label] for label in small["controllers"])
    values = {**data, **small}
    return PaperAConfig(
        specs=specs,
        paths=tuple(values.get("paths", ("straight", "turning", "ramp"))),
        robot=str(values.get("robot", "atlas-like")),
        nb_steps=values.get("nb_steps"),
        slow_nb_steps=values.get("slow_nb_steps"),
        mode=mode_name(quick),
    )


#: The controllers of the shipped comparison.
DEFAULT_SPECS: tuple[TimedController, ...] = load_config().specs


__all__ = ["DEFAULT_CONFIG", "DEFAULT_SPECS", "PATHS_DIR", "PaperAConfig", "load_config"]
