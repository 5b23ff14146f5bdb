"""`mpcwalk robots check`: every shipped preset passes the checks a preset must pass, and a
broken one fails at the check that finds it."""

import pytest

from mpcwalk.cli import main as cli_main
from mpcwalk.robot import loading, robot_names
from mpcwalk.walking.robot_check import check_robot


@pytest.mark.slow
@pytest.mark.parametrize("name", robot_names())
def test_every_shipped_preset_passes(name, capsys):
    assert cli_main(["robots", "check", name]) == 0
    out = capsys.readouterr().out
    assert "FAIL" not in out and "ok   it walks" in out


def _broken(tmp_path, old: str, new: str):
    (tmp_path / "bioloid_like.xml").write_text(
        (loading.ROBOTS_DIR / "bioloid_like.xml").read_text()
    )
    text = (loading.PRESETS_DIR / "bioloid_like.toml").read_text()
    assert old in text
    preset = tmp_path / "broken.toml"
    preset.write_text(text.replace(old, new))
    return preset


def test_a_crooked_posture_fails_the_posture_check(tmp_path):
    preset = _broken(tmp_path, "left_foot_pitch = -0.38", "left_foot_pitch = -0.2")
    results = {r.name: r for r in check_robot(preset, walk=False)}
    failed = [name for name, r in results.items() if not r.passed]
    assert failed == ["the nominal posture is flat"]  # and no simulation after it
    assert "it stands under its servos" not in results
    detail = results["the nominal posture is flat"].detail
    assert "L sole not flat: tilted 10.31 deg" in detail  # 0.18 rad
    assert "change left_foot_pitch by -0.1800 rad (to -0.3800)" in detail


def test_a_wrong_com_height_and_a_missing_frame_are_found(tmp_path, capsys):
    preset = _broken(tmp_path, "com_height = 0.230", "com_height = 0.300")
    posture = {r.name: r for r in check_robot(preset, walk=False)}["the nominal posture is flat"]
    assert "preset says 0.3000 m (set com_height = 0.2303)" in posture.detail
    preset = _broken(tmp_path, 'left = "left_sole"', 'left = "left_toe"')
    assert cli_main(["robots", "check", str(preset)]) == 1
    out = capsys.readouterr().out
    assert "FAIL it loads" in out and "left_toe" in out
    assert cli_main(["robots", "check"]) == 2


def test_a_urdf_without_finger_inertias_is_repaired_for_both_engines():
    from mpcwalk.robot.urdf_repair import MIN_MASS, repair_inertias

    text = """<robot name="r"><link name="base"><inertial><mass value="1"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <link name="finger"/><link name="tip"><inertial><mass value="0"/>
    <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <link name="frame"/>
    <joint name="j1" type="revolute"><parent link="base"/><child link="finger"/></joint>
    <joint name="j2" type="revolute"><parent link="finger"/><child link="tip"/></joint>
    <joint name="f" type="fixed"><parent link="base"/><child link="frame"/></joint></robot>"""
    repaired, names = repair_inertias(text)
    assert names == ["finger", "tip"]  # moving links only; the fixed frame stays massless
    assert repaired.count(f'value="{MIN_MASS!r}"') == 2
    assert repair_inertias(repaired) == (repaired, [])


@pytest.mark.slow
def test_romeo_walks_ten_steps_with_mpc():
    """Romeo's URDF gives its fingers no inertia, which MuJoCo refuses; repaired in the text
    both engines load, it loads, the engines agree (`test_robots.py`) and it walks."""
    from mpcwalk.walking.runner import run_walk

    result = run_walk("romeo", controller="mpc", command=(0.1, 0.0, 0.0), nb_steps=10)
    m = result.metrics
    assert not m.fell and m.steps_completed == m.steps_planned == 11
    assert m.foot_position_error_cm_max < 3.0  # measured 1.44 cm (1.27 cm with 300 N m/rad ankles)
