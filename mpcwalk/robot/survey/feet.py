"""The soles of a humanoid for its drafted preset, measured on its feet's geometry.

The preset's sole (``sole_offset``, ``sole_size``) is where the loader puts each foot's
contact box, in the foot link's axes, so it must lie under the foot as drawn:
:func:`~mpcwalk.robot.footprint.sole_from_geometry` measures the lowest face of the foot's
collision shapes, else its visual ones. A foot without shapes gets :data:`DEFAULT_SOLE` (a
share of the leg length) under its link's origin, and the preset says so.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.footprint import foot_footprints
from mpcwalk.robot.survey.legs import LegSurvey
from mpcwalk.robot.survey.parts import Sole

#: Sole length and width of a foot without shapes, as shares of the leg length.
DEFAULT_SOLE = (0.30, 0.13)

#: Largest turn [deg] of a foot link from its sole before the preset says ``sole_rpy``.
ALIGNED = 1.0


def sole_axes(model: pin.Model, foot: str) -> np.ndarray:
    """The sole's axes (columns: forward, left, up of the robot standing in the zero
    configuration, the legs straight) in the frame of the foot link ``foot``; ``model`` is
    in the loader's frame (base x forward, z up)."""
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    return data.oMf[model.getFrameId(foot)].rotation.T.copy()


def soles_from_geometry(description: Path, model: pin.Model, legs: LegSurvey) -> tuple[Sole, Sole]:
    """Each foot's sole (left, right): its collision footprint, else its visual one, else
    :data:`DEFAULT_SOLE`, measured along the sole's axes (the left foot's, also used for
    the right one, as the preset has one ``sole_rpy``)."""
    feet = (legs.left.foot, legs.right.foot)
    axes = sole_axes(model, legs.left.foot)
    angle = float(np.degrees(np.linalg.norm(pin.log3(axes))))
    rpy = (0.0, 0.0, 0.0)
    if angle > ALIGNED:
        rpy = tuple(round(float(a), 4) + 0.0 for a in pin.rpy.matrixToRpy(axes))  # type: ignore[assignment]
        axes = pin.rpy.rpyToMatrix(np.array(rpy))
    try:
        found = foot_footprints(description, feet, axes=axes if angle > ALIGNED else None)
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
                    rpy=rpy,
                )
            )
            continue
        soles.append(
            Sole(
                offset=tuple(round(float(c), 4) + 0.0 for c in footprint.offset),  # type: ignore[arg-type]
                size=(round(footprint.size[0], 3), round(footprint.size[1], 3)),
                source=f"lowest face of the foot's {footprint.source} shapes",
                rpy=rpy,
            )
        )
    return _shared(soles[0], soles[1])


def _shared(left: Sole, right: Sole) -> tuple[Sole, Sole]:
    """One sole both feet can take (a preset has one ``sole_offset``): mirrored feet (their
    centres off the foot link's x axis by opposite amounts) get a centred sole narrowed to
    fit both."""
    shift = 0.5 * (left.offset[1] - right.offset[1])
    if abs(left.offset[1] + right.offset[1]) > 1e-3 or abs(shift) < 1e-3:
        return left, right
    narrowed = Sole(
        offset=(left.offset[0], 0.0, left.offset[2]),
        size=(left.size[0], round(left.size[1] - 2.0 * abs(shift), 3)),
        source=left.source + f", narrowed by {2000 * abs(shift):.0f} mm to fit both mirrored feet",
        rpy=left.rpy,
    )
    return narrowed, narrowed


__all__ = ["ALIGNED", "DEFAULT_SOLE", "sole_axes", "soles_from_geometry"]
