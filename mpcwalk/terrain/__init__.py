"""Terrain: stairs, slopes, platforms, stepping stones and rough patches.

Heights, normals and block edges for the footstep planner and the controller
(:class:`Terrain`), the solids the simulator builds (:meth:`Terrain.boxes`), terrain files
(:func:`read_terrain`) and the check that a terrain fits a robot (:func:`check_terrain`).
"""

from mpcwalk.terrain.features import (
    FEATURES,
    Feature,
    Platform,
    RoughPatch,
    Slope,
    Stairs,
    SteppingStones,
)
from mpcwalk.terrain.fit import MAX_STRADDLED_KINK_DEG, TerrainReach, check_terrain
from mpcwalk.terrain.surface import Box, Surface, sole_tilt
from mpcwalk.terrain.terrain import FLAT, SoleSupport, Terrain
from mpcwalk.terrain.terrain_file import (
    read_terrain,
    terrain_from_dict,
    terrain_to_dict,
    terrain_to_toml,
)

__all__ = [
    "FEATURES",
    "FLAT",
    "MAX_STRADDLED_KINK_DEG",
    "Box",
    "Feature",
    "Platform",
    "RoughPatch",
    "Slope",
    "SoleSupport",
    "Stairs",
    "SteppingStones",
    "Surface",
    "Terrain",
    "TerrainReach",
    "check_terrain",
    "read_terrain",
    "sole_tilt",
    "terrain_from_dict",
    "terrain_to_dict",
    "terrain_to_toml",
]
