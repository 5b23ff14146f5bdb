"""The soles of a humanoid for its drafted preset, measured on its feet's geometry.

The preset's sole (``sole_offset``, ``sole_size``) is where the loader puts each foot's
contact box, in the foot link's axes, so it must lie under the foot as drawn:
:func:`~mpcwalk.robot.footprint.sole_from_geometry` measures the lowest face of the foot's
collision shapes, else its visual ones. A foot without shapes gets :data:`DEFAULT_SOLE` (a
share of the leg length) under its link's origin, and the preset says so.
"""

from __future__ import annotations

from pathlib import Path

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.footprint import foot_footprints
from mpcwalk.robot.survey.draft import Sole
from mpcwalk.robot.survey.legs import LegSurvey

#: Sole length and width of a foot without shapes, as shares of the leg length.
DEFAULT_SOLE = (0.30, 0.13)


def soles_from_geometry(description: Path, legs: LegSurvey) -> tuple[Sole, Sole]:
    """Each foot's sole (left, right): its collision footprint, else its visual one, else
    :data:`DEFAULT_SOLE`."""
    feet = (legs.left.foot, legs.right.foot)
    try:
        found = foot_footprints(description, feet)
    except ConfigurationError:
        found = {foot: {} for foot in feet}
    length, width = (share * legs.leg_length for share in DEFAULT_SOLE)
    soles = []
    for foot in feet:
        footprint = found[foot].get("collision") or found[foot].get("visual")
        if footprint is None:
            soles.append(
                Sole(
                    offset=(0.0, 0.0, 0.0),
                    size=(round(length, 3), round(width, 3)),
                    source="no shape on the foot: a default sole at the foot link's origin",
                )
            )
            continue
        soles.append(
            Sole(
                offset=tuple(round(float(c), 4) + 0.0 for c in footprint.offset),  # type: ignore[arg-type]
                size=(round(footprint.size[0], 3), round(footprint.size[1], 3)),
                source=f"lowest face of the foot's {footprint.source} shapes",
            )
        )
    return soles[0], soles[1]


__all__ = ["DEFAULT_SOLE", "soles_from_geometry"]
