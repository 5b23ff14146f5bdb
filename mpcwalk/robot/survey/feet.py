"""The soles of a humanoid, measured on its feet's geometry.

The preset's sole (:attr:`~mpcwalk.robot.preset.RobotPreset.sole_offset` and
``sole_size``) is where the loader puts each foot's contact box, so it must lie under the
foot as drawn. :func:`sole_of_foot` reads the foot's geometry with Pinocchio (its
collision geometry, else its visual geometry: meshes of any format Pinocchio reads, boxes,
spheres, cylinders, capsules), with the bodies fixed to the foot, in the foot link's frame:

- the *bottom* is every point within :data:`BOTTOM_BAND` of the lowest one (along up, in
  the zero configuration: legs straight, feet flat);
- the sole is the bottom's bounding rectangle along forward and left; its offset is the
  rectangle's centre at the lowest height.

A foot without geometry gets :data:`DEFAULT_SOLE` (a share of the leg length) centred under
its link's origin, and the preset says so.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from mpcwalk.robot.survey.draft import Sole
from mpcwalk.robot.survey.legs import AXES, LegSurvey

#: Thickness of the band above the lowest point that counts as the sole [m].
BOTTOM_BAND = 0.005

#: Sole length and width of a foot without geometry, as shares of the leg length.
DEFAULT_SOLE = (0.30, 0.13)


def _primitive_points(geometry) -> np.ndarray | None:
    """Corners of the bounding box of a primitive shape (None for a mesh)."""
    if hasattr(geometry, "halfSide"):
        half = np.asarray(geometry.halfSide, dtype=float)
    elif hasattr(geometry, "radius") and hasattr(geometry, "halfLength"):
        half = np.array([geometry.radius, geometry.radius, geometry.halfLength], dtype=float)
        if type(geometry).__name__ == "Capsule":
            half[2] += geometry.radius
    elif hasattr(geometry, "radius"):
        half = np.full(3, float(geometry.radius))
    else:
        return None
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    return signs * half


def _points(geometry) -> np.ndarray | None:
    """Points of a shape in its own frame: mesh vertices or a primitive's box corners."""
    if hasattr(geometry, "vertices"):
        try:
            return np.asarray(geometry.vertices(), dtype=float)
        except (RuntimeError, TypeError):
            return None
    return _primitive_points(geometry)


def foot_points(model: pin.Model, geometry: pin.GeometryModel, foot: str) -> np.ndarray:
    """Points (n, 3) of the foot's geometry (and of the bodies fixed to it) in the frame of
    the foot link ``foot``."""
    frame = model.frames[model.getFrameId(foot)]
    to_foot = frame.placement.inverse()
    points = []
    for item in geometry.geometryObjects:
        if item.parentJoint != frame.parentJoint:
            continue
        local = _points(item.geometry)
        if local is None or not len(local):
            continue
        placement = to_foot * item.placement
        points.append(local @ placement.rotation.T + placement.translation)
    return np.vstack(points) if points else np.zeros((0, 3))


def sole_of_foot(
    model: pin.Model,
    geometry: pin.GeometryModel,
    foot: str,
    legs: LegSurvey,
    kind: str,
) -> Sole | None:
    """The sole of the foot link ``foot`` from ``geometry`` (named ``kind`` in the sole's
    source), or None when the foot has no geometry there."""
    points = foot_points(model, geometry, foot)
    if len(points) < 3:
        return None
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    rotation = data.oMf[model.getFrameId(foot)].rotation
    up, forward = rotation.T @ AXES[legs.up], rotation.T @ AXES[legs.forward]
    left = np.cross(up, forward)
    heights = points @ up
    lowest = float(heights.min())
    bottom = points[heights < lowest + BOTTOM_BAND]
    along, across = bottom @ forward, bottom @ left
    centre = (
        0.5 * (along.min() + along.max()) * forward
        + 0.5 * (across.min() + across.max()) * left
        + lowest * up
    )
    return Sole(
        offset=tuple(round(float(c), 4) for c in centre),  # type: ignore[arg-type]
        size=(round(float(np.ptp(along)), 3), round(float(np.ptp(across)), 3)),
        source=f"bottom of the foot's {kind} geometry ({len(points)} points)",
    )


def soles_from_geometry(
    description: Path, text: str, model: pin.Model, legs: LegSurvey
) -> tuple[Sole, Sole]:
    """Each foot's sole, from its collision geometry, else its visual geometry, else
    :data:`DEFAULT_SOLE`; meshes are looked for beside the description and in the package
    folders above it."""
    folders = [str(p) for p in (description.parent, *description.parents)][:6]
    soles: list[Sole | None] = [None, None]
    for kind, geometry_type in (
        ("collision", pin.GeometryType.COLLISION),
        ("visual", pin.GeometryType.VISUAL),
    ):
        if all(soles):
            break
        try:
            geometry = pin.buildGeomFromUrdfString(model, text, geometry_type, package_dirs=folders)
        except (RuntimeError, ValueError):
            continue
        for i, leg in enumerate((legs.left, legs.right)):
            if soles[i] is None:
                soles[i] = sole_of_foot(model, geometry, leg.foot, legs, kind)
    length, width = (share * legs.leg_length for share in DEFAULT_SOLE)
    default = Sole(
        offset=(0.0, 0.0, 0.0),
        size=(round(length, 3), round(width, 3)),
        source="no geometry on the foot: a default sole under the foot link's origin",
    )
    return (soles[0] or default, soles[1] or default)


__all__ = ["BOTTOM_BAND", "DEFAULT_SOLE", "foot_points", "sole_of_foot", "soles_from_geometry"]
