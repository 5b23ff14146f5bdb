"""A sole measured on Collada meshes: the file's up axis is honoured (iCub's feet are drawn
Y up; read as drawn, their 15.6 x 6.1 cm soles came out 6.1 x 15.6 cm)."""

import numpy as np
import pytest

from mpcwalk.robot.footprint import collada_up_rotation, sole_from_geometry

# a foot-shaped box: 16 cm long (forward), 6 cm wide, 4 cm high, its heel 4 cm behind the
# origin and its sole at the origin's height
LENGTH, WIDTH, HEIGHT, HEEL = 0.16, 0.06, 0.04, 0.04


def _collada(up: str) -> str:
    """The box drawn with ``up`` as its up axis (forward x in both; Y up: width along z)."""
    xs, ups, sides = (-HEEL, LENGTH - HEEL), (0.0, HEIGHT), (-WIDTH / 2, WIDTH / 2)
    if up == "Y_UP":  # x forward, y up, z to the right
        corners = [(x, u, -s) for x in xs for u in ups for s in sides]
    else:  # x forward, y to the left, z up
        corners = [(x, s, u) for x in xs for u in ups for s in sides]
    # the 12 triangles of the box (corner index = 4 x + 2 up + side)
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1)]
    faces += [(2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    positions = " ".join(f"{v:g}" for corner in corners for v in corner)
    indices = " ".join(str(i) for face in faces for i in face)
    return f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>{up}</up_axis></asset>
  <library_geometries><geometry id="box" name="box"><mesh>
    <source id="box-pos"><float_array id="box-pos-array" count="24">{positions}</float_array>
      <technique_common><accessor source="#box-pos-array" count="8" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="box-vtx"><input semantic="POSITION" source="#box-pos"/></vertices>
    <triangles count="12"><input semantic="VERTEX" source="#box-vtx" offset="0"/><p>{indices}</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="Scene"><node id="box-node">
    <instance_geometry url="#box"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
"""


def _urdf(mesh: str) -> str:
    return f"""<robot name="foot">
  <link name="foot">
    <inertial><mass value="0.5"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 -0.05"/><geometry><mesh filename="{mesh}"/></geometry></collision>
  </link>
</robot>
"""


@pytest.mark.parametrize("up", ["Y_UP", "Z_UP"])
def test_a_collada_foot_drawn_with_either_axis_up_gives_the_same_sole(tmp_path, up):
    (tmp_path / "foot.dae").write_text(_collada(up))
    (tmp_path / "foot.urdf").write_text(_urdf("foot.dae"))
    footprint = sole_from_geometry(tmp_path / "foot.urdf", "foot")
    assert footprint.source == "collision"
    assert footprint.size == pytest.approx((LENGTH, WIDTH), abs=1e-6)
    assert footprint.offset == pytest.approx((LENGTH / 2 - HEEL, 0.0, -0.05), abs=1e-6)


def test_the_up_axis_rotations_are_rotations_taking_that_axis_up(tmp_path):
    for up, axis in (("X_UP", 0), ("Y_UP", 1), ("Z_UP", 2)):
        path = tmp_path / f"{up}.dae"
        path.write_text(f"<COLLADA><asset><up_axis>{up}</up_axis></asset></COLLADA>")
        rotation = collada_up_rotation(path)
        assert rotation @ rotation.T == pytest.approx(np.eye(3))
        assert np.linalg.det(rotation) == pytest.approx(1.0)
        assert rotation @ np.eye(3)[axis] == pytest.approx([0.0, 0.0, 1.0])
    # the format's default is Y up; other files and missing ones are left as they are
    (tmp_path / "bare.dae").write_text("<COLLADA><asset/></COLLADA>")
    assert collada_up_rotation(tmp_path / "bare.dae") @ [0, 1, 0] == pytest.approx([0, 0, 1])
    assert collada_up_rotation(tmp_path / "foot.stl") == pytest.approx(np.eye(3))
    assert collada_up_rotation(tmp_path / "missing.dae") == pytest.approx(np.eye(3))
