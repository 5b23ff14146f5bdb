"""The repair some URDF files need before MuJoCo compiles them.

What MuJoCo (3.x/4.0, the compiler options of :mod:`mpcwalk.robot.scene`:
``balanceinertia="false" inertiafromgeom="false"``) refuses, found by compiling small URDFs
(``tests/test_urdf_repair.py``), and what Pinocchio silently accepts:

- **a moving rigid body without mass or inertia**: a link with a moving joint (revolute,
  continuous, prismatic, floating, planar) or the root link (it gets the free joint), plus
  the links fixed to it, none of which has both a mass and three principal inertias of at
  least ``mjMINVAL`` (1e-15) ("mass and inertia of moving bodies must be larger than
  mjMINVAL"). A link without ``<inertial>``, with mass 0, with a zero inertia matrix, or
  with a negative or non-finite mass is such a body when no link fixed to it has both;
- **an inertia matrix that is not positive definite**, on any link, moving or fixed: an
  eigenvalue zero, negative or below about 1e-14 kg m^2 ("inertia must have positive
  eigenvalues"; an all-zero matrix, a point mass, is accepted);
- **principal inertias A <= B <= C that break the triangle inequality A + B >= C**, on any
  link, by however little ("use 'balanceinertia' to fix");
- **an ``<inertial>`` without ``<mass>`` or ``<inertia>``, or an inertia without one of its
  six numbers, or a number that does not parse** (XML errors). A ``nan`` or ``inf`` MuJoCo
  reads on a fixed link, and then simulates nan.

:func:`repair_inertias` repairs **all** of them in one pass, in the text that *both*
engines then load, so that Pinocchio and MuJoCo keep describing the same robot (the
engines' check compares their CoM and the mass matrix, ``tests/test_robots.py``):

- the moving link of such a body gets both: a mass that is missing, zero, negative or
  non-finite becomes :data:`MIN_MASS` (a gram); elsewhere a non-finite or negative one
  becomes 0 (a fixed massless link stays massless);
- an inertia that is missing or non-finite, or zero on the moving link of such a body,
  becomes that of a cube of the link's mass at the density of water
  (:func:`cube_inertia`: a 1 cm cube for a gram, 13 cm for 2 kg), the link keeping its
  mass and centre of mass;
- an eigenvalue below :data:`MIN_EIGENVALUE` is raised to the cube's inertia (at least
  :data:`MIN_EIGENVALUE`), and the two smaller principal inertias are raised in the same
  proportion until A + B >= C (with a margin of :data:`TRIANGLE_MARGIN`); the principal
  axes stay.

MuJoCo's own compiler options were tried and not used: ``balanceinertia`` only mends the
triangle inequality (it replaces A, B and C by their mean, far from the description), and
``boundmass``/``boundinertia`` raise the mass and inertia of *every* body, the fixed
massless frames included, and still refuse a negative eigenvalue. Both act inside MuJoCo
only, so Pinocchio would keep the originals: the two engines would no longer describe the
same robot (CoM and mass matrix apart). The repair in the text keeps them equal.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np

#: Mass [kg] given to a moving link without one.
MIN_MASS = 1e-3
#: Density [kg/m^3] of the cube whose inertia a link without a valid one gets (water).
CUBE_DENSITY = 1000.0
#: Principal inertia [kg m^2] of a moving link of :data:`MIN_MASS` without one: a 1 cm cube.
MIN_INERTIA = MIN_MASS * 0.01**2 / 6.0
#: Smallest principal inertia [kg m^2] kept as it is (MuJoCo refuses below about 1e-14).
MIN_EIGENVALUE = 1e-12
#: MuJoCo's smallest mass and inertia of a moving body [kg], [kg m^2] (``mjMINVAL``).
MJ_MINVAL = 1e-15
#: Relative margin by which repaired principal inertias satisfy A + B >= C.
TRIANGLE_MARGIN = 1e-6

_INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
_MOVING = ("revolute", "continuous", "prismatic", "floating", "planar")


@dataclass(frozen=True)
class InertiaRepair:
    """One repaired link.

    Attributes:
        link: The link's name.
        reason: What MuJoCo refused in it ("no <inertial>", "inertia eigenvalue -0.1").
        mass: Its mass after the repair [kg].
        inertia: Its principal inertias after the repair [kg m^2], ascending.
    """

    link: str
    reason: str
    mass: float
    inertia: tuple[float, float, float]

    def __str__(self) -> str:
        return f"{self.link} ({self.reason})"


def cube_inertia(mass: float) -> float:
    """Principal inertia [kg m^2] of a solid cube of ``mass`` [kg] at :data:`CUBE_DENSITY`
    (:data:`MIN_INERTIA` for :data:`MIN_MASS`)."""
    if mass <= MIN_MASS:
        return MIN_INERTIA
    side = (mass / CUBE_DENSITY) ** (1.0 / 3.0)
    return mass * side**2 / 6.0


def _number(text: str | None) -> float:
    """``text`` as a float; nan when missing or not a number."""
    try:
        return float(text) if text is not None else math.nan
    except ValueError:
        return math.nan


def _matrix(values: dict[str, float]) -> np.ndarray:
    ixx, ixy, ixz, iyy, iyz, izz = (values[k] for k in _INERTIA_KEYS)
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


def _valid_eigenvalues(eigenvalues: np.ndarray, floor: float) -> tuple[np.ndarray, str]:
    """``eigenvalues`` (ascending) raised to what MuJoCo accepts, and what was wrong ("" if
    nothing)."""
    low, fixed, reason = eigenvalues[0], eigenvalues.copy(), ""
    if low < MIN_EIGENVALUE:
        reason = f"inertia eigenvalue {low:.3g} kg m^2"
        fixed = np.maximum(fixed, floor)
    a, b, c = np.sort(fixed)
    if a + b < c:
        reason = reason or f"inertia breaks A + B >= C ({a:.3g} + {b:.3g} < {c:.3g})"
        scale = c * (1.0 + TRIANGLE_MARGIN) / (a + b)  # raise A and B in proportion
        fixed = np.where(fixed < c, fixed * scale, fixed)
    return fixed, reason


def _link_inertial(link: ET.Element) -> tuple[float, dict[str, float], list[str]]:
    """Mass, inertia numbers (nan where missing or unreadable) and the problems of the text."""
    inertial = link.find("inertial")
    if inertial is None:
        return 0.0, dict.fromkeys(_INERTIA_KEYS, 0.0), ["no <inertial>"]
    problems = []
    mass_element, inertia_element = inertial.find("mass"), inertial.find("inertia")
    mass = _number(None if mass_element is None else mass_element.get("value"))
    if mass_element is None:
        problems.append("no <mass>")
    elif not math.isfinite(mass):
        problems.append(f"mass {mass_element.get('value')!r}")
    elif mass < 0.0:
        problems.append(f"mass {mass:g} kg")
    values = {
        k: _number(None if inertia_element is None else inertia_element.get(k))
        for k in _INERTIA_KEYS
    }
    if inertia_element is None:
        problems.append("no <inertia>")
    elif not all(math.isfinite(v) for v in values.values()):
        bad = [k for k, v in values.items() if not math.isfinite(v)]
        problems.append(f"inertia {', '.join(bad)} missing or not finite")
    return mass, values, problems


def _repair_link(link: ET.Element, must_carry: bool) -> tuple[float, np.ndarray] | None:
    """Repair ``link`` in place (``must_carry``: the link of a moving body that must have the
    mass and the inertia); its mass and principal inertias, or None when valid."""
    if link.find("inertial") is None and not must_carry:
        return None  # a massless fixed link: MuJoCo takes it
    mass, values, problems = _link_inertial(link)
    mass = given = mass if math.isfinite(mass) and mass >= 0.0 else 0.0
    if must_carry and mass < MJ_MINVAL:
        if not problems:
            problems.append(f"mass {mass:g} kg")
        mass = MIN_MASS
    inertia = _matrix(values)
    if not np.isfinite(inertia).all() or (must_carry and not inertia.any()):
        if np.isfinite(inertia).all() and "no <inertial>" not in problems:
            problems.append("zero inertia" + (f" with {given:g} kg" if given > 0 else ""))
        inertia = np.eye(3) * cube_inertia(mass)
    eigenvalues, rotation = np.linalg.eigh(0.5 * (inertia + inertia.T))
    if inertia.any():
        fixed, reason = _valid_eigenvalues(eigenvalues, max(cube_inertia(mass), MIN_EIGENVALUE))
        if reason:
            problems.append(reason)
            inertia = rotation @ np.diag(fixed) @ rotation.T
            eigenvalues = fixed
    if not problems:
        return None
    inertial = link.find("inertial")
    if inertial is None:
        inertial = ET.SubElement(link, "inertial")
    for tag in ("mass", "inertia"):
        if inertial.find(tag) is None:
            ET.SubElement(inertial, tag)
    inertial.find("mass").set("value", repr(float(mass)))  # type: ignore[union-attr]
    element = inertial.find("inertia")
    for key, (i, j) in zip(_INERTIA_KEYS, ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))):
        element.set(key, repr(float(inertia[i, j])))  # type: ignore[union-attr]
    link.set("_reason", "; ".join(problems))
    return mass, np.sort(eigenvalues)


def _rigid_bodies(root: ET.Element) -> list[list[ET.Element]]:
    """The links of each moving rigid body: a link with a moving joint, or the root link,
    then the links fixed to it (recursively)."""
    links = {str(link.get("name")): link for link in root.iter("link")}
    children: dict[str, list[tuple[str, bool]]] = {}
    has_parent = set()
    for joint in root.iter("joint"):
        parent, child = joint.find("parent"), joint.find("child")
        if parent is None or child is None:
            continue
        moving = joint.get("type") in _MOVING
        children.setdefault(str(parent.get("link")), []).append((str(child.get("link")), moving))
        has_parent.add(str(child.get("link")))
    heads = [name for name in links if name not in has_parent]
    heads += [c for kids in children.values() for c, moving in kids if moving]
    bodies = []
    for head in heads:
        body, stack = [], [head]
        while stack:
            name = stack.pop()
            if name in links:
                body.append(links[name])
            stack.extend(c for c, moving in children.get(name, ()) if not moving)
        bodies.append(body)
    return bodies


def _carries(links: list[ET.Element]) -> bool:
    """Whether one of the links other than the first has a mass and all three principal
    inertias of at least ``mjMINVAL`` (what MuJoCo asks of one link of a moving body)."""
    for link in links[1:]:
        mass, values, _ = _link_inertial(link)
        matrix = _matrix(values)
        if math.isfinite(mass) and mass >= MJ_MINVAL and np.isfinite(matrix).all():
            if np.linalg.eigvalsh(0.5 * (matrix + matrix.T))[0] >= MJ_MINVAL:
                return True
    return False


def inertia_repairs(text: str) -> tuple[str, list[InertiaRepair]]:
    """``text`` of a URDF with every inertia MuJoCo refuses repaired (see the module), and
    the repairs, one per link (the text unchanged when there are none).

    Raises:
        xml.etree.ElementTree.ParseError: ``text`` is not XML.
    """
    root = ET.fromstring(text)
    repairs = []
    must_carry = {body[0].get("name") for body in _rigid_bodies(root) if not _carries(body)}
    for link in root.iter("link"):
        repaired = _repair_link(link, link.get("name") in must_carry)
        if repaired is not None:
            mass, eigenvalues = repaired
            reason = link.attrib.pop("_reason")
            repairs.append(
                InertiaRepair(str(link.get("name")), reason, mass, tuple(map(float, eigenvalues)))  # type: ignore[arg-type]
            )
    if not repairs:
        return text, []
    return ET.tostring(root, encoding="unicode"), repairs


def repair_inertias(text: str) -> tuple[str, list[str]]:
    """``text`` of a URDF with every inertia MuJoCo refuses repaired, and the names of the
    links repaired (the text unchanged when there are none); :func:`inertia_repairs` also
    says what each link had."""
    repaired, repairs = inertia_repairs(text)
    return repaired, [repair.link for repair in repairs]


__all__ = [
    "CUBE_DENSITY",
    "MIN_EIGENVALUE",
    "MIN_INERTIA",
    "MIN_MASS",
    "InertiaRepair",
    "cube_inertia",
    "inertia_repairs",
    "repair_inertias",
]
