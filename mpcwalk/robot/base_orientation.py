"""The base orientation of a description: which axes of its root link point forward and up.

mpcwalk's conventions put the floating base with x forward and z up. A description whose root
link is mounted otherwise (its x axis pointing backward, its y axis forward...) says so in its
preset's ``[base]`` table (``forward = "-x"``); the loader then re-expresses the root link of
the URDF text in a frame with x forward and z up (:func:`reorient_urdf_root`): the root link's
inertial, visual and collision origins and the origins of the joints leaving it turn by the
same fixed rotation, in the text that *both* Pinocchio and MuJoCo load, so the floating base
both engines add sits in the conventional frame and every other link keeps its own.
"""

import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError

#: The unit vector of each axis name a ``[base]`` table may use.
AXIS_VECTORS = {
    "x": (1.0, 0.0, 0.0),
    "-x": (-1.0, 0.0, 0.0),
    "y": (0.0, 1.0, 0.0),
    "-y": (0.0, -1.0, 0.0),
    "z": (0.0, 0.0, 1.0),
    "-z": (0.0, 0.0, -1.0),
}

BASE_AXES = tuple(AXIS_VECTORS)
"""The axes a preset's ``[base]`` table may name."""


def base_rotation(forward: str, up: str) -> np.ndarray:
    """Rotation (3, 3) whose columns are the conventional base axes (x forward, y left, z up)
    in the frame of a root link whose axis ``forward`` points forward and ``up`` points up
    (``"x"``, ``"-x"``, ``"y"``, ``"-y"``, ``"z"``, ``"-z"``).

    Raises:
        ConfigurationError: An unknown axis, or ``forward`` and ``up`` along one axis.
    """
    if forward not in AXIS_VECTORS or up not in AXIS_VECTORS or forward[-1] == up[-1]:
        raise ConfigurationError(
            f"The base axes forward = {forward!r}, up = {up!r} are not two different axes "
            f"among {', '.join(AXIS_VECTORS)}."
        )
    x_axis, z_axis = np.array(AXIS_VECTORS[forward]), np.array(AXIS_VECTORS[up])
    return np.column_stack([x_axis, np.cross(z_axis, x_axis), z_axis])


def _origin(element: ET.Element) -> ET.Element:
    origin = element.find("origin")
    if origin is None:
        origin = ET.SubElement(element, "origin")
    return origin


def _turn(origin: ET.Element, rotation: np.ndarray) -> None:
    """Pre-multiply the pose of a URDF ``<origin>`` by ``rotation``."""
    xyz = np.array([float(v) for v in origin.get("xyz", "0 0 0").split()])
    rpy = np.array([float(v) for v in origin.get("rpy", "0 0 0").split()])
    turned = rotation @ pin.rpy.rpyToMatrix(rpy)
    origin.set("xyz", " ".join(repr(float(v)) for v in rotation @ xyz))
    origin.set("rpy", " ".join(repr(float(v)) for v in pin.rpy.matrixToRpy(turned)))


def reorient_urdf_root(text: str, forward: str, up: str) -> str:
    """``text`` of a URDF whose root link has its axis ``forward`` pointing forward and ``up``
    pointing up, with that root link re-expressed in the frame x forward, z up (the text
    unchanged for ``forward = "x"``, ``up = "z"``).

    Raises:
        ConfigurationError: Bad axes (:func:`base_rotation`), or a URDF without a single root
            link.
    """
    rotation = base_rotation(forward, up)
    if np.array_equal(rotation, np.eye(3)):
        return text
    to_base = rotation.T  # a vector in the root link's frame -> in the conventional frame
    root = ET.fromstring(text)
    children = {child.get("link") for child in root.iter("child")}
    roots = [link for link in root.findall("link") if link.get("name") not in children]
    if len(roots) != 1:
        raise ConfigurationError(
            f"The URDF has {len(roots)} root links ({', '.join(str(r.get('name')) for r in roots)}); "
            "a [base] table needs exactly one."
        )
    name = roots[0].get("name")
    for tag in ("inertial", "visual", "collision"):
        for element in roots[0].findall(tag):
            _turn(_origin(element), to_base)
    for joint in root.findall("joint"):
        parent = joint.find("parent")
        if parent is not None and parent.get("link") == name:
            _turn(_origin(joint), to_base)
    return ET.tostring(root, encoding="unicode")


__all__ = [
    "AXIS_VECTORS",
    "BASE_AXES",
    "base_rotation",
    "reorient_urdf_root",
]
