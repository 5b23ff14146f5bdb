"""Terrain files (TOML): one array of tables per kind of feature.

Distances are along the robot's initial heading, from its start; every field is in metres
but for angles (degrees), counts and seeds::

    width = 3.0        # [m] across the heading (optional)

    [[stairs]]
    start = 0.6        # [m] to the first riser
    rise = 0.15        # [m] per step; negative goes down
    run = 0.30         # [m] tread depth
    count = 5

    [[slope]]
    start = 4.5
    length = 1.5       # [m] horizontal
    angle = 10.0       # [deg] up; negative down

    [[platform]]       # a block on the level: start, length, height [m]
    [[stones]]         # stepping stones: start, count, length, gap, width, height, depth
    [[rough]]          # blocks of random known heights: start, length, width, block, height, seed

:func:`read_terrain` reads one, :func:`terrain_to_toml` writes one back (the same terrain).
"""

import dataclasses
import sys
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import TerrainError
from mpcwalk.terrain.features import FEATURES
from mpcwalk.terrain.terrain import Terrain

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib


def terrain_from_dict(data: dict[str, Any], *, source: str = "<terrain>") -> Terrain:
    """Terrain from the tables of a terrain file.

    Raises:
        TerrainError: An unknown table or field, a value out of range, overlapping features.
    """
    features = []
    width = data.get("width", 3.0)
    for key, tables in data.items():
        if key == "width":
            continue
        cls = FEATURES.get(key)
        if cls is None:
            raise TerrainError(
                f"{source}: unknown table [[{key}]]; a terrain file holds "
                f"{', '.join(f'[[{name}]]' for name in FEATURES)} and 'width'."
            )
        if not isinstance(tables, list):
            raise TerrainError(f"{source}: '{key}' must be an array of tables, write [[{key}]].")
        names = [f.name for f in dataclasses.fields(cls)]
        for index, table in enumerate(tables):
            unknown = sorted(set(table) - set(names))
            if unknown:
                raise TerrainError(
                    f"{source}: [[{key}]] number {index + 1} has unknown field(s) "
                    f"{', '.join(unknown)}; its fields are {', '.join(names)}."
                )
            if "start" not in table:
                raise TerrainError(
                    f"{source}: [[{key}]] number {index + 1} needs 'start', its distance [m] "
                    "from the robot's start along its heading."
                )
            try:
                features.append(cls(**table))
            except TerrainError as error:
                raise TerrainError(f"{source}: [[{key}]] number {index + 1}: {error}") from None
    try:
        return Terrain(features, width=width)
    except TerrainError as error:
        raise TerrainError(f"{source}: {error}") from None


def read_terrain(path: str | Path) -> Terrain:
    """Terrain of a TOML file (see the module's documentation).

    Raises:
        TerrainError: The file is missing, not TOML, or holds what a terrain cannot.
    """
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as error:
        raise TerrainError(
            f"Cannot read the terrain file {path}: {error.strerror or error}."
        ) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise TerrainError(f"{path} is not valid TOML: {error}.") from None
    return terrain_from_dict(data, source=str(path))


def terrain_to_dict(terrain: Terrain) -> dict[str, Any]:
    """The tables of a terrain file holding ``terrain``."""
    out: dict[str, Any] = {"width": terrain.width}
    for feature in terrain.features:
        out.setdefault(feature.key, []).append(feature.to_dict())
    return out


def terrain_to_toml(terrain: Terrain) -> str:
    """A terrain file holding ``terrain`` (read back by :func:`read_terrain` as the same)."""
    lines = [f"width = {terrain.width!r}  # [m]"]
    for feature in terrain.features:
        lines += ["", f"[[{feature.key}]]"]
        lines += [f"{name} = {value!r}" for name, value in feature.to_dict().items()]
    return "\n".join(lines) + "\n"


__all__ = ["read_terrain", "terrain_from_dict", "terrain_to_dict", "terrain_to_toml"]
