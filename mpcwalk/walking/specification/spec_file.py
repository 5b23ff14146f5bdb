"""A walk specification as a TOML file: :func:`spec_to_toml`, :func:`write_spec`,
:func:`read_spec`.

``mpcwalk walk`` writes ``spec.toml`` next to ``metrics.json``: every field of every part,
each with its unit and meaning in a comment, an unset field (its default decided when the
walk runs, e.g. the robot model's friction) as a commented line. A terrain is written inline
as the table ``[world.terrain]``, holding the tables of a terrain file
(:mod:`mpcwalk.terrain.terrain_file`: ``[[world.terrain.stairs]]``...), so that the file alone
walks the walk again. ``mpcwalk walk --spec FILE`` reads it back; fields left out of a
hand-written file take their defaults.
"""

import dataclasses
import json
import math
import re
import sys
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import SpecFileError
from mpcwalk.walking.specification.walk_spec import PARTS, WalkSpec

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

#: The file name of a walk's specification next to its results.
SPEC_FILE = "spec.toml"

#: What each field means, for the file's comments.
NOTES = {
    "name": "named controller (mpcwalk controllers), or custom",
    "generator": "pattern generator (mpcwalk generators)",
    "feedback": "close the loop on the estimated state",
    "stabilizers": "applied in order (mpcwalk stabilizers)",
    "arm_swing": "paper M's arm swing factor s (0: arms still)",
    "swing_profile": "cosine (paper M) or ctraj (paper A)",
    "generator_options": "keyword arguments of the generator",
    "controller_options": "keyword arguments of the walking controller",
    "command": "[vx m/s, vy m/s, vyaw rad/s]",
    "path": ".mdat path file instead of a command",
    "nb_steps": "steps (a command adds a closing step)",
    "duration": "[s] walking time instead of nb_steps",
    "step_duration": "[s] step duration T",
    "double_support_ratio": "share of a step in double support",
    "step_height": "[m] swing-foot height",
    "control_period": "[s] controller tick",
    "terrain_cadence": "on a terrain, steps lengthened to 75 % of the flat top speed",
    "noise_scale": "factor on the sensor model's noise and bias",
    "latency": "[s] sensing-to-actuation latency (unset: one control period)",
    "ideal": "exact sensors without latency",
    "state": "estimator (the sensors) or oracle (the simulator's ground truth)",
    "mass_scale": "factor on the simulated torso's mass",
    "com_offset": "[m] shift of the simulated torso's CoM (dx, dy)",
    "friction": "floor friction coefficient (unset: the robot model's)",
    "servo_strength": "factor on the servos' gains and torque limits",
    "friction_cone": "pyramidal or elliptic (unset: MuJoCo's pyramid)",
    "impratio": "MuJoCo's frictional-to-normal impedance ratio (unset: 1)",
    "actuation": "position (servos fed by the IK) or torque (motors fed by the inverse dynamics)",
    "ground_tilt": "[deg] slope of the ground",
    "ground_tilt_direction": "[deg] azimuth of the uphill direction (0: forward)",
    "ground_roughness": "[m] largest height of the ground's bumps",
    "terrain": "stairs, slopes, stones... along the heading (unset: the level floor)",
    "pushes": "[start s, duration s, fx N, fy N, fz N] on the torso",
    "sensor_nan": "[start s, end s] windows of NaN readings",
    "sensor_dropout": "[start s, end s] windows without readings",
    "yaw_reference": "also walk without the pushes, for the yaw deviation",
    "seed": "seed of the sensor noise and the ground's bumps",
    "progress": "progress bar",
    "video": "MP4 file to render into",
}

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _value(value: Any) -> str:
    """A TOML value."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise SpecFileError(f"a number of a walk specification is {value!r}, not finite")
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    if isinstance(value, dict):
        items = ", ".join(f"{_key(k)} = {_value(v)}" for k, v in value.items())
        return "{" + (f" {items} " if items else "") + "}"
    raise SpecFileError(f"a walk specification cannot hold {value!r}")


def _key(key: str) -> str:
    return key if _BARE_KEY.match(key) else json.dumps(key)


def spec_to_toml(spec: WalkSpec) -> str:
    """The text of a specification file (see the module docstring)."""
    values = spec.to_dict()
    lines = [
        "# A walk of mpcwalk. Walk it again: mpcwalk walk --spec FILE --out DIR",
        "# (options given beside --spec change those fields).",
        f"robot = {_value(values['robot'])}",
    ]
    for part, cls in PARTS.items():
        lines += ["", f"[{part}]"]
        tables: list[str] = []  # after the part's fields: a table ends them
        for f in dataclasses.fields(cls):
            value = values[part][f.name]
            note = NOTES.get(f.name, "")
            if value is None:
                lines.append(f"# {f.name} = (unset)  # {note}")
            elif f.name == "terrain":
                tables += _terrain_table(f"{part}.{f.name}", value)
            else:
                lines.append(f"{f.name} = {_value(value)}" + (f"  # {note}" if note else ""))
        lines += tables
    if values["labels"]:
        lines += ["", "[labels]"]
        lines += [f"{_key(k)} = {_value(v)}" for k, v in values["labels"].items()]
    return "\n".join(lines) + "\n"


def _terrain_table(name: str, tables: dict[str, Any]) -> list[str]:
    """The lines of a terrain (the tables of its file) as the table ``name``."""
    lines = ["", f"[{name}]  # the tables of a terrain file, laid along the heading"]
    lines += [f"width = {_value(tables['width'])}  # [m] across the heading"]
    for key, features in tables.items():
        for feature in features if key != "width" else ():
            lines += ["", f"[[{name}.{key}]]"]
            lines += [f"{field} = {_value(value)}" for field, value in feature.items()]
    return lines


def write_spec(spec: WalkSpec, path: str | Path) -> Path:
    """Write ``spec`` to ``path`` (see :func:`spec_to_toml`); returns the path."""
    path = Path(path)
    path.write_text(spec_to_toml(spec), encoding="utf-8")
    return path


def read_spec(path: str | Path) -> WalkSpec:
    """The specification in the TOML file ``path``.

    Raises:
        SpecFileError: No such file, not TOML, or a part, field or value the
            specification refuses (the message names the file and the field).
    """
    path = Path(path)
    if not path.is_file():
        raise SpecFileError(
            "no such file; give the spec.toml a walk wrote next to its metrics.json",
            path=str(path),
        )
    try:
        values = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as error:
        raise SpecFileError(f"not a TOML file: {error}", path=str(path)) from None
    from mpcwalk.exceptions import ConfigurationError, NotRegistered

    try:
        return WalkSpec.from_dict(values)
    except SpecFileError:
        raise
    except (ConfigurationError, NotRegistered) as error:
        raise SpecFileError(str(error), path=str(path)) from None


__all__ = ["SPEC_FILE", "read_spec", "spec_to_toml", "write_spec"]
