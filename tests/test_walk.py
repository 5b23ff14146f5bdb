"""Closed-loop walks in MuJoCo: the robots walk, and the runner and CLI report it."""

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import get_robot, walk

from mpcwalk.cli import main as cli_main
from mpcwalk.sim import FallDetector, parse_push
from mpcwalk.walking.footstep_planning import plan_walk_footsteps
from mpcwalk.walking.metrics import (
    WalkMetrics,
    cop_margins,
    landing_check_times,
    loaded_soles,
    measured_zmp,
)
from mpcwalk.walking.runner import run_walk
from mpcwalk.walking.specification import read_spec

ROOT = Path(__file__).resolve().parent.parent
TURN_RATE = math.radians(20.0)  # [rad/s] paper M's turning walk


def check_walk(
    m: WalkMetrics,
    *,
    distance_tolerance,
    foot_error_cm,
    cop_margin_min=-0.001,
    yaw_tolerance=5.0,
    foot_yaw_error_deg=5.0,
):
    """What every required walk must show (tolerances in the units of the fields)."""
    assert not m.fell, m.fall_reason
    assert m.steps_completed == m.steps_planned
    assert abs(m.distance_m - m.distance_planned_m) < distance_tolerance
    assert abs(m.yaw_change_deg - m.yaw_change_planned_deg) < yaw_tolerance
    # landings: world frame (includes the drift of earlier steps, as paper A's Fig. 8) and
    # relative to the support foot they were taken from
    assert m.foot_position_error_cm_max < foot_error_cm
    assert m.foot_step_error_cm_max < 1.0
    assert m.foot_yaw_error_deg_max < foot_yaw_error_deg
    assert m.foot_step_yaw_error_deg_max < 2.0
    # measured CoP against the soles that carry force: inside but for a sole rocking on an
    # edge (its ZMP on its origin's plane a fraction of a millimetre beyond it)
    assert m.cop_margin_p05_m > 0.0
    assert m.cop_margin_min_m > cop_margin_min
    assert m.cop_outside_share < 0.05
    assert m.mpc_failures == 0
    assert m.time_simulated_s > 0.0 and m.real_time_factor > 0.0


@pytest.mark.slow
@pytest.mark.parametrize("generator", ["analytic", "preview", "mpc"])
def test_small_humanoid_walks_twenty_steps_forward(generator):
    """Paper M's Table 1: T = 0.5 s, z_c = 0.23 m, z_step = 0.04 m, r_ds = 0.2, 0.1 m/s."""
    result = walk("bioloid-like", generator=generator, command=(0.1, 0.0, 0.0), nb_steps=20)
    m, config = result.metrics, result.config
    assert (
        config.step_duration_s,
        config.com_height_m,
        config.step_height_m,
        config.double_support_ratio,
    ) == (0.5, 0.23, 0.04, 0.2)
    assert m.steps_planned == 21 and m.closing_steps == 1  # 20 steps and the closing one
    assert m.distance_planned_m == pytest.approx(1.0)
    check_walk(
        m,
        distance_tolerance=0.06,
        foot_error_cm=5.0,
    )


@pytest.mark.slow
@pytest.mark.parametrize("generator", ["analytic", "preview", "mpc"])
def test_small_humanoid_turning_walk_of_paper_m(generator):
    """0.1 m/s and 20 deg/s for 10 s: 200 deg of yaw."""
    result = walk("bioloid-like", generator=generator, command=(0.1, 0.0, TURN_RATE), duration=10.0)
    m = result.metrics
    assert m.yaw_change_planned_deg == pytest.approx(200.0)
    # 10 s of walking: 20 steps and the closing one, 1 s standing before and after
    assert result.config.nb_steps == 20 and m.steps_planned == 21
    assert m.walking_time_planned_s == pytest.approx(10.5)
    assert m.time_planned_s == pytest.approx(12.5) == m.time_simulated_s
    # world-frame errors grow with the heading drift of the stance feet (yaw slips of a
    # fraction of a degree per step with the preview generator), the per-step ones do not
    check_walk(
        m,
        distance_tolerance=0.1,
        foot_error_cm=10.0,
        yaw_tolerance=12.0,
        foot_yaw_error_deg=12.0,
    )


@pytest.mark.slow
def test_large_humanoid_walks_ten_steps_at_one_second_per_step():
    result = run_walk(
        get_robot("atlas-like"), controller="mpc", command=(0.2, 0.0, 0.0), nb_steps=10
    )
    assert result.config.step_duration_s <= 1.0  # paper A needed 12 s per step
    check_walk(result.metrics, distance_tolerance=0.1, foot_error_cm=7.0)


@pytest.mark.slow
def test_unitree_g1_walks_ten_steps():
    result = run_walk(get_robot("g1"), controller="mpc", command=(0.2, 0.0, 0.0), nb_steps=10)
    check_walk(result.metrics, distance_tolerance=0.06, foot_error_cm=5.0)


@pytest.mark.slow
def test_large_humanoid_follows_paper_a_path_file():
    path = ROOT / "mpcwalk" / "experiments" / "paper_a" / "paths" / "straight.mdat"
    robot = get_robot("atlas-like")
    result = run_walk(robot, controller="mpc", path=path, nb_steps=6)
    m = result.metrics
    assert m.steps_planned == 6 and m.closing_steps == 0 and result.config.path == str(path)
    plan = result.schedule.plan
    # the file's two steps in place, then forward steps within paper A's rectangle
    assert plan.steps[0].xy[0] == pytest.approx(0.0, abs=1e-9)
    assert max(step.xy[0] for step in plan.steps) > 0.2
    assert not m.fell and m.steps_completed == 6
    assert m.foot_step_error_cm_max < 2.0 and m.foot_position_error_cm_max < 5.0


def test_fall_ends_the_run_early_and_says_why():
    push = parse_push("1.2,0.2,0,40,0")  # 40 N sideways on a 2 kg robot
    result = walk("bioloid-like", "mpc", command=(0.1, 0.0, 0.0), nb_steps=6, pushes=[push])
    m = result.metrics
    assert m.fell and result.fall.fell
    assert "base" in m.fall_reason
    assert m.time_simulated_s < m.time_planned_s - 1.0
    assert m.time_planned_s == pytest.approx(result.schedule.duration)
    assert m.time_simulated_s == pytest.approx(m.fall_time_s)
    assert m.steps_completed < m.steps_planned
    assert result.to_dict()["config"]["pushes"] == [[1.2, 0.2, 0.0, 40.0, 0.0]]


def test_log_round_trips_and_metrics_match_it(tmp_path, capsys):
    robot = get_robot("bioloid-like")
    result = run_walk(
        robot,
        controller="mpc",
        command=(0.1, 0.0, 0.0),
        nb_steps=1,
        fall_detector=FallDetector.for_robot(robot),
    )
    assert capsys.readouterr() == ("", "")  # a library is quiet: no progress bar by default
    # metrics.json: the WalkMetrics fields, then the configuration in its own block
    data = json.loads(json.dumps(result.to_dict()))
    assert list(data) == [f.name for f in dataclasses.fields(WalkMetrics)] + ["config"]
    assert data["config"]["nb_steps"] == 1 and data["config"]["robot"] == "bioloid-like"
    assert result.metrics["fell"] is result.metrics.fell is False
    log, schedule = result.log, result.schedule
    n = len(log)
    assert n == round(schedule.duration / 0.01)
    np.testing.assert_allclose(np.diff(log.time), 0.01, atol=1e-9)
    for name, shape in (
        ("com", (n, 3)),
        ("cop", (n, 3)),
        ("sole_positions", (n, 2, 3)),
        ("foot_wrenches", (n, 2, 6)),
        ("joint_targets", (n, len(robot.joint_names))),
        ("actuator_force", (n, robot.mj_model.nu)),
        ("estimate_time", (n,)),
        ("estimated_com", (n, 3)),
        ("estimated_com_velocity", (n, 3)),
        ("estimated_base_rpy", (n, 3)),
        ("estimated_contact", (n, 2)),
    ):
        assert getattr(log, name).shape == shape
    saved = np.load(log.save(tmp_path / "walk_log.npz"))
    np.testing.assert_array_equal(saved["com"], log.com)
    assert tuple(saved["joint_names"]) == log.joint_names
    table = np.genfromtxt(log.save(tmp_path / "walk_log.csv"), delimiter=",", names=True)
    np.testing.assert_allclose(table["cop_x"], log.cop[:, 0], rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(table["estimated_com_x"], log.estimated_com[:, 0], rtol=1e-5)
    np.testing.assert_allclose(table["right_force_z"], log.foot_wrenches[:, 1, 2], rtol=1e-5)
    assert len(table) == n
    margins = cop_margins(log, schedule)
    assert result.metrics.cop_margin_min_m == pytest.approx(np.nanmin(margins))
    # the logged wrenches (moments about the soles) give the logged CoP where every sole in
    # contact carries force
    zmp, _ = measured_zmp(log)
    every = (loaded_soles(log) == log.contact).all(axis=1) & log.contact.any(axis=1)
    assert every.mean() > 0.9
    np.testing.assert_allclose(zmp[every], log.cop[every, :2], atol=5e-4)
    assert result.metrics.steps_completed == len(landing_check_times(schedule)) == 2
    com = log.com[:, :2]
    assert result.metrics.distance_m == pytest.approx(np.linalg.norm(com[-1] - com[0]))


def test_leg_limits_and_plans_come_from_the_presets():
    bioloid, atlas = get_robot("bioloid-like"), get_robot("atlas-like")
    assert bioloid.leg_limits.half_stance_width == pytest.approx(0.04)
    assert bioloid.leg_limits.y_sep == pytest.approx(0.04)
    assert atlas.leg_limits.max_step_forward == pytest.approx(0.30)
    plan = plan_walk_footsteps(bioloid, command=(0.1, 0.0, 0.0), nb_steps=4)
    left, right = bioloid.compute_sole_placements(bioloid.q0)
    np.testing.assert_allclose(plan.initial_left.position, left.translation, atol=1e-12)
    np.testing.assert_allclose(plan.initial_right.position, right.translation, atol=1e-12)
    assert plan.nb_steps == 5


@pytest.mark.slow
def test_walk_command_writes_metrics_log_plots_and_video(tmp_path, capsys):
    out = tmp_path / "walk"
    code = cli_main(
        [
            "walk",
            "--robot",
            "bioloid-like",
            "--generator",
            "mpc",
            "--vx",
            "0.1",
            "--steps",
            "2",
            "--out",
            str(out),
            "--video",
            "--no-progress",
        ]
    )
    assert code == 0
    metrics = json.loads((out / "metrics.json").read_text())
    config = metrics.pop("config")
    # the metrics are exactly the WalkMetrics fields, the configuration has its own block
    assert list(metrics) == [f.name for f in dataclasses.fields(WalkMetrics)]
    assert "zmp_margin_min_m" not in metrics and metrics["cop_margin_min_m"] is not None
    assert metrics["fell"] is False and metrics["steps_planned"] == 3
    assert metrics["closing_steps"] == 1 and config["nb_steps"] == 2
    assert config["robot"] == "bioloid-like" and config["generator"] == "mpc"
    assert config["command"] == {"vx": 0.1, "vy": 0.0, "vyaw": 0.0}
    assert not {"robot", "generator", "step_duration_s", "pushes"} & set(metrics)
    # on the estimator by default, with the robot's sensors and one period of latency
    assert config["state_source"] == "estimator" and config["latency_s"] == 0.01
    assert config["noise_scale"] == 1.0 and config["seed"] == 0
    assert config["model_mismatch"]["mass_scale"] == 1.0
    assert 0.0 < metrics["estimator_com_error_rms_m"] < 0.005
    for name in ("walk_log.npz", "top_view.png", "com_cop.png", "estimator.png", "walk.mp4"):
        assert (out / name).stat().st_size > 1000, name
    # the walk itself, to walk it again (mpcwalk walk --spec): the video is where it was written
    spec = read_spec(out / "spec.toml")
    assert spec.plan.command == (0.1, 0.0, 0.0) and spec.plan.nb_steps == 2
    assert spec.controller.name == "mpc" and spec.run.video == str(out / "walk.mp4")
    out_text = capsys.readouterr().out
    assert "no fall" in out_text and "2 steps + 1 closing step" in out_text
    assert "CoP margin min" in out_text and "ZMP margin" not in out_text
    assert "state: estimator (noise x1, latency 10 ms); estimator CoM error RMS" in out_text


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--robot", "nope", "--duration", "1"], "Unknown robot 'nope'"),
        (["--generator", "nope", "--duration", "1"], "Unknown pattern generator"),
        (["--vx", "0.1", "--path", "x.mdat", "--duration", "1"], "not both"),
        (["--vx", "0.1"], "needs --duration"),
        (["--vx", "0.5", "--duration", "1"], "vx=0.5"),
        (["--push", "1,2", "--duration", "1"], "Push '1,2' is malformed"),
        (["--path", "missing.mdat"], "missing.mdat"),
    ],
)
def test_walk_command_bad_input_exits_with_code_2(tmp_path, capsys, argv, message):
    code = cli_main(["walk", "--out", str(tmp_path / "out"), "--no-progress", *argv])
    assert code == 2
    assert message in capsys.readouterr().err


def test_robots_command_lists_the_robots_that_load(capsys):
    assert cli_main(["robots"]) == 0
    output = capsys.readouterr().out
    for name in ("bioloid-like", "atlas-like", "g1"):
        assert name in output


def test_robots_command_without_robots_is_an_error(monkeypatch, capsys):
    import mpcwalk.robot.loading as loading

    monkeypatch.setattr(loading, "robot_names", lambda: ())
    assert cli_main(["robots"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mpcwalk: error: No robot found: searched ")
