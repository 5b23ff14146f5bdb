"""A biped written as a URDF in the tests: boxes and cylinders, joints with meaningless
names, its base turned by ``base_yaw`` (the description's x axis backward for pi), optional
links with a mass and no inertia, optionally without arms."""

from __future__ import annotations

import math


def _inertia(mass: float, size: tuple[float, float, float], zero: bool) -> str:
    if zero:
        return '<inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/>'
    x, y, z = size
    return (
        f'<inertia ixx="{mass * (y * y + z * z) / 12:.6g}" iyy="{mass * (x * x + z * z) / 12:.6g}" '
        f'izz="{mass * (x * x + y * y) / 12:.6g}" ixy="0" ixz="0" iyz="0"/>'
    )


def _link(name: str, mass: float, size, centre=(0.0, 0.0, 0.0), *, zero=False, collision=False):
    x, y, z = size
    cx, cy, cz = centre
    geometry = f'<geometry><box size="{x} {y} {z}"/></geometry>'
    origin = f'<origin xyz="{cx} {cy} {cz}" rpy="0 0 0"/>'
    shapes = f"<visual>{origin}{geometry}</visual>"
    if collision:
        shapes += f"<collision>{origin}{geometry}</collision>"
    return (
        f'<link name="{name}"><inertial>{origin}<mass value="{mass}"/>'
        f"{_inertia(mass, size, zero)}</inertial>{shapes}</link>"
    )


def _joint(name, parent, child, xyz, axis, low=-1.5, high=1.5, rpy=(0.0, 0.0, 0.0)):
    return (
        f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz[0]:.6g} {xyz[1]:.6g} {xyz[2]:.6g}" rpy="{rpy[0]:.6g} {rpy[1]:.6g} '
        f'{rpy[2]:.6g}"/><axis xyz="{axis}"/><limit lower="{low}" upper="{high}" effort="150" '
        'velocity="10"/></joint>'
    )


def biped_urdf(*, base_yaw: float = 0.0, zero_inertia: int = 0, arms: bool = True) -> str:
    """The URDF text of the test biped (about 30 kg, hips 0.8 m high)."""
    c, s = math.cos(base_yaw), math.sin(base_yaw)

    def turned(x: float, y: float, z: float) -> tuple[float, float, float]:
        # joints leaving the base, written in a base frame turned by base_yaw
        return (c * x + s * y, -s * x + c * y, z)

    parts = ['<robot name="quirky_biped">', _link("trunk", 10.0, (0.15, 0.25, 0.15))]
    zero_left = zero_inertia
    for sign, letter in ((1.0, "p"), (-1.0, "q")):
        links = [f"{letter}{i}" for i in range(6)]
        masses = (0.5, 0.5, 3.0, 2.0, 0.3, 1.0)
        sizes = [(0.05, 0.05, 0.05), (0.05, 0.05, 0.05), (0.08, 0.08, 0.4)]
        sizes += [(0.07, 0.07, 0.4), (0.04, 0.04, 0.04), (0.22, 0.1, 0.03)]
        centres = [(0, 0, 0), (0, 0, 0), (0, 0, -0.2), (0, 0, -0.2), (0, 0, 0), (0.03, 0, -0.05)]
        for i, name in enumerate(links):
            zero = zero_left > 0 and i in (0, 1, 4)
            if zero:
                zero_left -= 1
            parts.append(_link(name, masses[i], sizes[i], centres[i], zero=zero, collision=i == 5))
        # in the leg's own frames the base's turn carries down: undo it at the hip
        parts += [
            _joint(
                f"j{letter}a",
                "trunk",
                links[0],
                turned(0.0, sign * 0.1, -0.1),
                "0 0 1",
                rpy=(0.0, 0.0, -base_yaw),
            ),
            _joint(f"j{letter}b", links[0], links[1], (0, 0, 0), "1 0 0", -0.5, 0.5),
            _joint(f"j{letter}c", links[1], links[2], (0, 0, 0), "0 1 0", -1.5, 0.5),
            _joint(f"j{letter}d", links[2], links[3], (0, 0, -0.4), "0 1 0", -0.05, 2.2),
            _joint(f"j{letter}e", links[3], links[4], (0, 0, -0.4), "0 1 0", -1.0, 1.0),
            _joint(f"j{letter}f", links[4], links[5], (0, 0, 0), "1 0 0", -0.5, 0.5),
        ]
    parts += [
        _link("chest", 8.0, (0.15, 0.3, 0.3), (0, 0, 0.15)),
        _joint(
            "w1",
            "trunk",
            "chest",
            turned(0.0, 0.0, 0.08),
            "0 0 1",
            -0.5,
            0.5,
            rpy=(0.0, 0.0, -base_yaw),
        ),
    ]
    if arms:
        for sign, letter in ((1.0, "u"), (-1.0, "v")):
            roll = (-0.2, 1.5) if sign > 0 else (-1.5, 0.2)
            parts += [
                _link(f"{letter}0", 0.3, (0.05, 0.05, 0.05)),
                _link(f"{letter}1", 0.6, (0.06, 0.06, 0.25), (0, 0, -0.125)),
                _link(f"{letter}2", 0.4, (0.05, 0.05, 0.25), (0, 0, -0.125)),
                _link(f"{letter}3", 0.1, (0.04, 0.04, 0.04)),
                _joint(f"{letter}p", "chest", f"{letter}0", (0, sign * 0.2, 0.27), "0 1 0"),
                _joint(f"{letter}r", f"{letter}0", f"{letter}1", (0, 0, 0), "1 0 0", *roll),
                _joint(f"{letter}e", f"{letter}1", f"{letter}2", (0, 0, -0.25), "0 1 0", -2.0, 0.0),
                f'<joint name="{letter}h" type="fixed"><parent link="{letter}2"/>'
                f'<child link="{letter}3"/><origin xyz="0 0 -0.25" rpy="0 0 0"/></joint>',
            ]
    parts.append("</robot>")
    return "\n".join(parts)
