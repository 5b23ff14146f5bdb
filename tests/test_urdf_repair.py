"""The URDF inertia repair: every inertia MuJoCo refuses, found by compiling small URDFs with
the loader's compiler options, is repaired in one pass in the text both engines load."""

import itertools
import re
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from mpcwalk.robot.scene import urdf_spec
from mpcwalk.robot.urdf_repair import (
    MIN_EIGENVALUE,
    MIN_INERTIA,
    MIN_MASS,
    cube_inertia,
    inertia_repairs,
    repair_inertias,
)


def _inertial(mass, ixx, iyy, izz, ixy=0.0, ixz=0.0, iyz=0.0) -> str:
    return (
        f'<inertial><origin xyz="0.01 0 0"/><mass value="{mass}"/><inertia ixx="{ixx}" '
        f'iyy="{iyy}" izz="{izz}" ixy="{ixy}" ixz="{ixz}" iyz="{iyz}"/></inertial>'
    )


GOOD = _inertial(1.0, 0.1, 0.1, 0.1)


def _urdf(links: dict[str, str], joints: list[tuple[str, str, str]]) -> str:
    """A URDF: a base of 1 kg, ``links`` (name -> inertial text), ``joints`` (type, parent,
    child)."""
    text = f'<robot name="r"><link name="base">{GOOD}</link>'
    text += "".join(f'<link name="{name}">{inertial}</link>' for name, inertial in links.items())
    for i, (kind, parent, child) in enumerate(joints):
        text += (
            f'<joint name="j{i}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        )
    return text + "</robot>"


def _compile(text: str) -> mujoco.MjModel:
    """MuJoCo's model of ``text`` as the loader compiles it (free base, loader's options)."""
    return urdf_spec(Path("r.urdf"), Path("."), False, text).compile()


def _arm(inertial: str, kind: str = "revolute") -> str:
    return _urdf({"arm": inertial}, [(kind, "base", "arm")])


# Each fault of one moving link, with the error MuJoCo 3.x/4.0 gives for it.
FAULTS = {
    "no inertial": (_arm(""), "larger than mjMINVAL"),
    "zero mass, valid inertia": (_arm(_inertial(0, 0.1, 0.1, 0.1)), "larger than mjMINVAL"),
    "mass, zero inertia": (_arm(_inertial(2.0, 0, 0, 0)), "larger than mjMINVAL"),
    "prismatic, zero mass": (_arm(_inertial(0, 0, 0, 0), "prismatic"), "larger than mjMINVAL"),
    "one zero principal inertia": (_arm(_inertial(2.0, 0.1, 0.1, 0)), "positive eigenvalues"),
    "negative principal inertia": (_arm(_inertial(2.0, 0.1, 0.1, -0.1)), "positive eigenvalues"),
    "too small principal inertia": (_arm(_inertial(1.0, *[1e-16] * 3)), "positive eigenvalues"),
    "not positive definite": (_arm(_inertial(1.0, 0.1, 0.1, 0.1, ixy=0.2)), "positive eigen"),
    "triangle inequality": (_arm(_inertial(1.0, 0.1, 0.1, 0.3)), "A + B >= C"),
    "triangle, by 1e-9": (_arm(_inertial(1.0, 0.1, 0.1, 0.2 * (1 + 1e-9))), "A + B >= C"),
    "negative mass": (_arm(_inertial(-1.0, 0.1, 0.1, 0.1)), "larger than mjMINVAL"),
    "nan mass": (_arm(_inertial("nan", 0.1, 0.1, 0.1)), "larger than mjMINVAL"),
    "inf inertia": (_arm(_inertial(1.0, "inf", 0.1, 0.1)), "larger than mjMINVAL"),
    "no <inertia>": (_arm('<inertial><mass value="1"/></inertial>'), "missing element"),
    "inertia without ixy": (
        _arm('<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial>'),
        "required attribute missing",
    ),
    "mass on one link, inertia on the fixed one": (
        _urdf(
            {"arm": _inertial(1.0, 0, 0, 0), "tool": _inertial(0, 0.1, 0.1, 0.1)},
            [("revolute", "base", "arm"), ("fixed", "arm", "tool")],
        ),
        "larger than mjMINVAL",
    ),
    "fixed link, triangle": (
        _urdf(
            {"arm": GOOD, "tool": _inertial(1.0, 0.1, 0.1, 0.3)},
            [("revolute", "base", "arm"), ("fixed", "arm", "tool")],
        ),
        "A + B >= C",
    ),
}


@pytest.mark.parametrize("fault", list(FAULTS))
def test_each_fault_mujoco_refuses_is_repaired(fault):
    text, error = FAULTS[fault]
    with pytest.raises(ValueError, match=error.replace("+", r"\+")):
        _compile(text)
    repaired, repairs = inertia_repairs(text)
    assert [r.link for r in repairs] == ["tool" if fault.startswith("fixed") else "arm"]
    model = _compile(repaired)  # MuJoCo takes it now
    assert np.isfinite(model.body_mass).all() and np.isfinite(model.body_inertia).all()
    a, b, c = repairs[0].inertia
    assert a >= MIN_EIGENVALUE and a + b >= c
    assert inertia_repairs(repaired) == (repaired, [])  # nothing left to repair


def test_fourteen_links_with_mass_and_no_inertia_are_repaired_in_one_pass():
    """MuJoCo names only the first of them; the repair lists all 14, keeps each link's mass
    and gives it the inertia of a cube of that mass at the density of water."""
    names = [f"link{i}" for i in range(14)]
    links = {name: _inertial(0.5 + i, 0, 0, 0) for i, name in enumerate(names)}
    chain = ["base", *names]
    text = _urdf(links, [("revolute", p, c) for p, c in itertools.pairwise(chain)])
    with pytest.raises(ValueError, match="mjMINVAL"):
        _compile(text)
    repaired, repairs = inertia_repairs(text)
    assert [r.link for r in repairs] == names
    assert all(r.reason == f"zero inertia with {0.5 + i:g} kg" for i, r in enumerate(repairs))
    model = _compile(repaired)
    masses = model.body_mass[2:]
    np.testing.assert_allclose(masses, 0.5 + np.arange(14), rtol=0, atol=0)
    # 2.5 kg at 1000 kg/m^3: a 13.6 cm cube, 7.7e-3 kg m^2
    assert cube_inertia(2.5) == pytest.approx(2.5 * (2.5e-3) ** (2 / 3) / 6)
    np.testing.assert_allclose(model.body_inertia[4], [cube_inertia(2.5)] * 3, rtol=1e-12)
    # Pinocchio loads the same masses and inertias from the same text
    pin_model = pin.buildModelFromXML(repaired, pin.JointModelFreeFlyer())
    np.testing.assert_allclose([i.mass for i in pin_model.inertias][2:], masses, rtol=1e-15)
    np.testing.assert_allclose(
        np.diag(pin_model.inertias[4].inertia), model.body_inertia[4], rtol=1e-12
    )


def test_triangle_repair_keeps_the_principal_axes_and_raises_the_two_smaller():
    rotation = pin.rpy.rpyToMatrix(0.3, -0.2, 0.5)
    matrix = rotation @ np.diag([0.1, 0.15, 0.4]) @ rotation.T
    text = _arm(
        _inertial(
            1.0, matrix[0, 0], matrix[1, 1], matrix[2, 2], matrix[0, 1], matrix[0, 2], matrix[1, 2]
        )
    )
    with pytest.raises(ValueError, match="A \\+ B >= C"):
        _compile(text)
    repaired, repairs = inertia_repairs(text)
    a, b, c = repairs[0].inertia
    assert c == pytest.approx(0.4) and a + b == pytest.approx(0.4 * (1 + 1e-6))
    assert a / b == pytest.approx(0.1 / 0.15)  # raised in proportion
    assert "0.1 + 0.15 < 0.4" in repairs[0].reason
    inertia = pin.buildModelFromXML(repaired, pin.JointModelFreeFlyer()).inertias[2].inertia
    axis = rotation[:, 2]  # the largest principal axis stays
    assert axis @ inertia @ axis == pytest.approx(0.4)
    _compile(repaired)


def test_what_mujoco_takes_stays_as_written():
    """Massless fixed frames, a massless moving link holding a fixed link with mass, a point
    mass fixed to a moving link, and a small but valid inertia are left alone."""
    text = _urdf(
        {
            "frame": "",
            "holder": "",
            "payload": GOOD,
            "arm": GOOD,
            "point": _inertial(1.0, 0, 0, 0),
            "small": _inertial(1.0, 1e-11, 1e-11, 1e-11),
        },
        [
            ("fixed", "base", "frame"),
            ("revolute", "base", "holder"),
            ("fixed", "holder", "payload"),
            ("revolute", "base", "arm"),
            ("fixed", "arm", "point"),
            ("revolute", "base", "small"),
        ],
    )
    _compile(text)
    assert repair_inertias(text) == (text, [])


def test_a_massless_moving_link_holding_a_point_mass_is_repaired():
    """MuJoCo asks one link of a moving rigid body (the moving link and the links fixed to it)
    to have both a mass and an inertia: a point mass fixed to a massless link is refused."""
    text = _urdf(
        {"holder": "", "point": _inertial(1.0, 0, 0, 0)},
        [("revolute", "base", "holder"), ("fixed", "holder", "point")],
    )
    with pytest.raises(ValueError, match="mjMINVAL"):
        _compile(text)
    repaired, repairs = inertia_repairs(text)
    # MuJoCo asks one link of the body to have both: the holder gets a gram, a 1 cm cube
    assert [(r.link, r.mass, r.reason) for r in repairs] == [("holder", MIN_MASS, "no <inertial>")]
    assert repairs[0].inertia == (MIN_INERTIA,) * 3 and MIN_MASS * 1e-4 / 6 == MIN_INERTIA
    _compile(repaired)


def test_every_example_robot_data_urdf_mujoco_refuses_compiles_once_repaired():
    """The URDFs of example-robot-data: 21 of them MuJoCo refuses as written (zero masses,
    negative eigenvalues, the triangle inequality); each compiles once repaired."""
    from mpcwalk.robot.loading import example_robot_data_dir

    root = example_robot_data_dir()
    if root is None:
        pytest.skip("example-robot-data is not installed")
    refused = 0
    for path in sorted(root.rglob("*.urdf")):
        text = path.read_text()
        text = re.sub(r"<(visual|collision)>.*?</\1>", "", text, flags=re.DOTALL)
        if "<link" not in text or "world" in re.findall(r'<link name="([^"]+)"', text)[:1]:
            continue
        try:
            _compile(text)
        except ValueError:
            refused += 1
            repaired, repairs = inertia_repairs(text)
            assert repairs, path.name
            _compile(repaired)
    assert refused >= 20
