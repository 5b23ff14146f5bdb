"""``mpcwalk robots init``: a URDF humanoid written here becomes a preset that walks."""

import math

import pytest
from urdf_biped import biped_urdf

import mpcwalk
from mpcwalk.cli.main import main
from mpcwalk.robot.loading import example_robot_data_dir
from mpcwalk.robot.preset import RobotPreset

pytestmark = pytest.mark.skipif(
    example_robot_data_dir() is None, reason="URDF robots load with example-robot-data"
)


@pytest.fixture(scope="module")
def quirky(tmp_path_factory):
    """A biped with meaningless joint names, its base turned by pi (the description's x
    axis points backward) and three links with a mass and no inertia, drafted and checked
    (with its short walk) by ``robots init``."""
    folder = tmp_path_factory.mktemp("quirky")
    (folder / "quirky.urdf").write_text(biped_urdf(base_yaw=math.pi, zero_inertia=3))
    preset = folder / "quirky.toml"
    code = main(["robots", "init", str(folder / "quirky.urdf"), "--out", str(preset)])
    return preset, code


def test_init_writes_a_preset_that_passes_its_checks(quirky):
    preset, code = quirky
    assert code == 0  # every check passed, the short walk with mpc included
    draft = RobotPreset.from_file(preset)
    assert draft.description == "quirky.urdf"  # beside the preset
    assert draft.foot_frames == ("p5", "q5")
    assert draft.joints["left_knee"] == "jpd"
    assert draft.base_forward == "-x"
    text = preset.read_text()
    assert "# note: repaired the inertia of 3 link(s): p0, p1, p4" in text
    assert "# LOOK" not in text


def test_the_drafted_robot_walks_with_every_controller_family(quirky):
    preset, _ = quirky
    robot = mpcwalk.load_robot(preset)
    for controller in ("mpc", "mpc-steps", "paper-m"):
        result = mpcwalk.run_walk(robot, controller=controller, command=(0.1, 0.0, 0.0), nb_steps=4)
        assert not result.metrics.fell, controller
        assert result.metrics.steps_completed == result.metrics.steps_planned, controller


def test_init_refuses_bad_input_before_anything_runs(tmp_path, capsys):
    missing = tmp_path / "missing.urdf"
    assert main(["robots", "init", str(missing), "--out", str(tmp_path / "x.toml")]) == 2
    assert "is not a file" in capsys.readouterr().err
    urdf = tmp_path / "quirky.urdf"
    urdf.write_text(biped_urdf())
    (tmp_path / "taken.toml").write_text("")
    assert main(["robots", "init", str(urdf), "--out", str(tmp_path / "taken.toml")]) == 2
    assert "--overwrite" in capsys.readouterr().err
    assert main(["robots", "init", str(urdf)]) == 2
