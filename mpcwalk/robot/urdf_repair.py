"""The repair some URDF files need before MuJoCo compiles them.

MuJoCo refuses a moving body (one with a joint) whose mass or inertia is zero; some
descriptions give their fingers no inertia (Romeo's 24 finger and thumb links). Such a link
gets a gram and the inertia of a 1 cm cube of it, in the text of the description that
*both* engines then load, so that Pinocchio and MuJoCo keep describing the same robot.
"""

import xml.etree.ElementTree as ET

#: Mass [kg] given to a moving link without one.
MIN_MASS = 1e-3
#: Principal inertia [kg m^2] given to a moving link without one: a 1 cm cube of 1 g.
MIN_INERTIA = MIN_MASS * 0.01**2 / 6.0


def repair_inertias(text: str) -> tuple[str, list[str]]:
    """``text`` of a URDF with every moving link of zero mass or inertia given
    :data:`MIN_MASS` and :data:`MIN_INERTIA`; the names of the links repaired (the text
    unchanged when there are none)."""
    root = ET.fromstring(text)
    moving = {
        joint.find("child").get("link")  # type: ignore[union-attr]
        for joint in root.iter("joint")
        if joint.get("type") not in (None, "fixed") and joint.find("child") is not None
    }
    repaired = []
    for link in root.iter("link"):
        if link.get("name") not in moving:
            continue
        inertial = link.find("inertial")
        if inertial is None:
            inertial = ET.SubElement(link, "inertial")
        mass = inertial.find("mass")
        if mass is None:
            mass = ET.SubElement(inertial, "mass", value="0")
        inertia = inertial.find("inertia")
        if inertia is None:
            inertia = ET.SubElement(
                inertial, "inertia", ixx="0", iyy="0", izz="0", ixy="0", ixz="0", iyz="0"
            )
        diagonal = [float(inertia.get(k, "0")) for k in ("ixx", "iyy", "izz")]
        if float(mass.get("value", "0")) > 0.0 and min(diagonal) > 0.0:
            continue
        mass.set("value", repr(max(float(mass.get("value", "0")), MIN_MASS)))
        for key, value in zip(("ixx", "iyy", "izz"), diagonal):
            inertia.set(key, repr(max(value, MIN_INERTIA)))
        repaired.append(str(link.get("name")))
    if not repaired:
        return text, []
    return ET.tostring(root, encoding="unicode"), repaired


__all__ = ["MIN_INERTIA", "MIN_MASS", "repair_inertias"]
