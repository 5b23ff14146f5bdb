"""The papers' engines walk as published, named controllers, default timings, the robot's own
reachability and the heading held over long walks."""

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import get_robot, walk

from mpcwalk.cli import build_parser
from mpcwalk.cli import main as cli_main
from mpcwalk.cli.walk_options import spec_from_args
from mpcwalk.control.stabilizers.footstep_reaiming import FootstepReaiming
from mpcwalk.exceptions import ConfigurationError, NotRegistered
from mpcwalk.footsteps.footstep import StepTiming
from mpcwalk.sim import parse_push
from mpcwalk.walking.footstep_planning import plan_walk_footsteps
from mpcwalk.walking.lipm_plan import plan_walk
from mpcwalk.walking.runner import run_walk
from mpcwalk.walking.specification import CONTROLLERS, ControllerSpec, WalkSpec

ROOT = Path(__file__).resolve().parent.parent
PATHS = ROOT / "mpcwalk" / "experiments" / "paper_a" / "paths"
F1_F2 = ["0,0.1,0,5,0", "3.0,0.05,10,5,0"]  # paper M Fig. 2: (0, 5, 0) N at rest, (10, 5, 0) N


def test_controllers_are_listed_and_named(capsys):
    assert cli_main(["controllers"]) == 0
    out = capsys.readouterr().out
    for name in ("paper-m", "paper-m-open", "paper-a", "preview", "mpc", "mpc-steps", "static-qp"):
        assert name in CONTROLLERS and f"{name} " in out
    paper_m = ControllerSpec.named("paper-m")
    assert (paper_m.generator, paper_m.feedback, paper_m.stabilizers, paper_m.arm_swing) == (
        "analytic",
        False,
        ("gyro",),
        0.8,
    )
    assert paper_m.name == "paper-m" and CONTROLLERS.load("paper-m") == paper_m
    with pytest.raises(NotRegistered, match="Unknown controller 'paper-x'.*paper-m"):
        ControllerSpec.named("paper-x")


def test_parts_beside_a_named_controller_change_it_into_a_custom_one():
    args = ["walk", "--controller", "paper-m", "--generator", "mpc", "--steps", "2"]
    spec = spec_from_args(build_parser().parse_args([*args, "--out", "w"]), out=Path("w"))
    controller = spec.controller
    assert controller.name == "custom" and controller.generator == "mpc"
    # the rest of paper-m stays: open loop, gyro stabilizer, arm swing
    assert (controller.feedback, controller.stabilizers, controller.arm_swing) == (
        False,
        ("gyro",),
        0.8,
    )
    spec = WalkSpec.build("bioloid-like", controller="mpc", stabilizers=("gyro",), nb_steps=2)
    assert spec.controller == ControllerSpec(generator="mpc", stabilizers=("gyro",))
    # a part given with the named controller's own value leaves it named
    paper_m = ControllerSpec.named("paper-m")
    spec = WalkSpec.build("bioloid-like", controller="paper-m", generator="analytic")
    assert spec.controller == paper_m and spec.controller.name == "paper-m"
    args = ["walk", "--controller", "paper-m", "--stabilizer", "gyro", "--steps", "2"]
    spec = spec_from_args(build_parser().parse_args([*args, "--out", "w"]), out=Path("w"))
    assert spec.controller == paper_m


@pytest.mark.slow
@pytest.mark.parametrize(
    "command, kwargs",
    [
        pytest.param((0.1, 0.0, math.pi / 9.0), {"duration": 10.0}, id="turning-fig1"),
        pytest.param((0.1, 0.0, 0.0), {"nb_steps": 20}, id="straight-20-steps"),
    ],
)
def test_paper_m_open_loop_walks_as_published(command, kwargs):
    """Paper M's closed form alone (stabilizer off), on the default sensors."""
    result = run_walk(
        get_robot("bioloid-like"), controller="paper-m-open", command=command, **kwargs
    )
    m = result.metrics
    assert result.config.state_source == "estimator" and result.config.noise_scale == 1.0
    assert not m.fell, m.fall_reason
    assert m.steps_completed == m.steps_planned == 21
    assert abs(m.yaw_change_deg - m.yaw_change_planned_deg) < 0.05 * 200.0 + 1.0


@pytest.mark.slow
def test_paper_m_engine_survives_f1_and_f2():
    result = walk(
        "bioloid-like",
        "paper-m",
        command=(0.1, 0.0, 0.0),
        duration=5.0,
        pushes=[parse_push(text) for text in F1_F2],
    )
    assert not result.metrics.fell, result.metrics.fall_reason
    assert result.config.stabilizer == "gyro" and result.config.arm_swing == 0.8


@pytest.mark.slow
@pytest.mark.parametrize("path", ["straight.mdat", "turning.mdat"])
def test_paper_a_walks_its_paths_with_no_timing_option(path):
    """Paper A's gait on atlas-like at its own timing (12 s per step); the first 4 steps."""
    result = run_walk(get_robot("atlas-like"), controller="paper-a", path=PATHS / path, nb_steps=4)
    m = result.metrics
    assert result.config.step_duration_s == 12.0
    assert not m.fell, m.fall_reason
    assert m.steps_completed == m.steps_planned == 4
    assert m.foot_position_error_cm_max < 5.0  # paper A: 4.96 cm max


@pytest.mark.parametrize("generator", ["static", "static-qp"])
def test_static_plans_with_default_options_stay_in_the_support_polygon(generator, tmp_path):
    assert cli_main(["plan", "--generator", generator, "--out", str(tmp_path)]) == 0
    result = plan_walk(generator, None, 6)
    assert result.metrics["step_duration_s"] == 12.0
    assert result.metrics["zmp_margin_min_m"] > 0.0
    assert result.metrics["com_margin_min_m"] > 0.0
    assert result.metrics["qp_failures"] == 0


@pytest.mark.parametrize("generator", ["static", "static-qp"])
def test_infeasible_static_timing_is_refused_with_the_fastest_feasible_one(generator, tmp_path):
    with pytest.raises(ConfigurationError, match=r"fastest feasible timing is a step duration"):
        plan_walk(generator, None, 6, timing=StepTiming(1.0, 0.2))
    out = tmp_path / "walk"
    code = cli_main(
        ["walk", "--robot", "atlas-like", "--generator", generator, "--step-duration", "1"]
        + ["--steps", "4", "--no-progress", "--out", str(out)]
    )
    assert code == 2 and not (out / "metrics.json").exists()
    # the fastest timing the message gives plans with the ZMP on the soles
    with pytest.raises(ConfigurationError) as refused:
        plan_walk(generator, None, 6, timing=StepTiming(1.0, 0.5))
    fastest = float(str(refused.value).split("step duration of ")[1].split(" s")[0])
    result = plan_walk(generator, None, 6, timing=StepTiming(fastest, 0.5))
    assert result.metrics["zmp_margin_min_m"] > 0.0


def _bioloid_path(tmp_path) -> Path:
    """A straight path for bioloid-like: feet 0.08 m apart, 8 steps of 0.04 to 0.08 m."""
    rows = [(0.0, 0.0)] * 2 + [(0.04, 0.0), (0.04, 0.08), (0.12, 0.08), (0.12, 0.16)]
    rows += [(0.2, 0.16), (0.2, 0.24), (0.28, 0.24), (0.28, 0.28)]
    lines = [f"{xl} 0.04 0 1 0 0 0 {xr} -0.04 0 1 0 0 0" for xl, xr in rows]
    path = tmp_path / "bioloid_straight.mdat"
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.slow
def test_path_reaims_with_the_robots_own_reachability(tmp_path):
    result = walk("bioloid-like", "mpc", path=_bioloid_path(tmp_path), stabilizers=("reaim",))
    m = result.metrics
    assert not m.fell and m.steps_completed == m.steps_planned == 8
    assert m.foot_position_error_cm_max < 1.0  # 10.4 cm with Atlas's rectangle
    assert abs(m.yaw_change_deg) < 2.0


def test_state_machine_takes_the_robots_rectangle_at_reset():
    from stabilizer_inputs import stabilizer_input  # the suite's hand-built inputs

    from mpcwalk.footsteps.footstep import FootGeometry
    from mpcwalk.footsteps.velocity_planner import VelocityCommand
    from mpcwalk.gait.contact_schedule import ContactSchedule

    for name in ("bioloid-like", "atlas-like"):
        robot = get_robot(name)
        plan = plan_walk_footsteps(robot, command=VelocityCommand(0.05, 0.0, 0.0), nb_steps=2)
        schedule = ContactSchedule(plan, FootGeometry(*robot.sole_size))
        machine = FootstepReaiming()
        machine.reset(stabilizer_input(robot, schedule, t=0.0))
        assert machine.rectangle == robot.leg_limits.rectangle()


@pytest.mark.slow
def test_long_turning_walk_holds_the_commanded_yaw():
    """60 s at 0.3 rad/s (120 steps, almost three turns): the yaw within 1 % of the command
    (2.5 % short of it without the heading hold)."""
    result = run_walk(
        get_robot("bioloid-like"), controller="mpc", command=(0.1, 0.0, 0.3), duration=60.0
    )
    m = result.metrics
    assert not m.fell
    commanded = math.degrees(0.3) * m.walking_time_planned_s * 120 / 121  # the closing step
    assert m.yaw_change_planned_deg == pytest.approx(commanded, rel=0.01)
    assert abs(m.yaw_change_deg - m.yaw_change_planned_deg) < 0.01 * m.yaw_change_planned_deg
    assert m.foot_step_error_cm_max < 1.0


@pytest.mark.slow
@pytest.mark.parametrize("direction", ["0,-7.0,0", "-7.0,0,0"])  # 0.7 N s right, back
def test_pushes_mpc_steps_falls_under_are_survived_with_the_step_timing_adapted(direction):
    """0.7 N s to the right or backwards at 3.0 s of a 0.1 m/s walk on bioloid-like (in
    single support of a right step): mpc-steps falls; mpc-timing (the same, its landing
    brought forward when the capture point would leave the leg's reach) walks on, and its
    swing foot's reference does not jump when the schedule's clock does."""
    push = parse_push(f"3.0,0.1,{direction}")
    runs = {
        name: walk("bioloid-like", name, command=(0.1, 0.0, 0.0), duration=6.0, pushes=[push])
        for name in ("mpc-steps", "mpc-timing")
    }
    assert runs["mpc-steps"].metrics.outcome == "fell"
    timed = runs["mpc-timing"]
    assert timed.metrics.outcome == "walked" and timed.metrics.fallback_ticks == 0
    jumps = np.abs(np.diff(timed.log.feet_reference, axis=0)).max()
    assert jumps < 0.02  # [m] per 10 ms tick


@pytest.mark.slow
def test_a_lateral_push_towards_the_stance_leg_is_walked_through():
    """The issue's push: 0.35 N s to the left at 3.0 s of a 0.1 m/s walk on bioloid-like,
    as the right leg lifts (the left one stands: the swing leg may not cross). paper-m's
    engine falls; the footstep-adaptive MPCs, with and without step timing, walk on (they
    fell when the push map was first drawn). Beyond about 0.4 N s all fall: the LIPM's
    bound there is the ankle's, 0.49 N s, with or without steps (results/capture_map)."""
    push = parse_push("3.0,0.1,0,3.5,0")
    outcomes = {
        name: walk(
            "bioloid-like", name, command=(0.1, 0.0, 0.0), duration=6.0, pushes=[push]
        ).metrics.outcome
        for name in ("paper-m", "mpc-steps", "mpc-timing")
    }
    assert outcomes == {"paper-m": "fell", "mpc-steps": "walked", "mpc-timing": "walked"}


@pytest.mark.slow
def test_a_push_towards_the_foot_about_to_lift_is_held_in_double_support():
    """0.8 N s to the left from 2.458 s of a 5-step walk at 0.1 m/s on bioloid-like (the
    push map's cell 90 deg, phase 0.92: the right foot has just landed, the left one lifts
    at 2.55 s). mpc and mpc-steps lift it on time and fall; mpc-timing puts the lift-off
    off while the DCM error points to that foot (both feet down, the ZMP on its sole) and
    walks on."""
    from mpcwalk.sim import ExternalForce

    push = ExternalForce(1.0 + 2.9167 * 0.5, 0.1, np.array([0.0, 8.0, 0.0]))
    fell = {
        name: walk(
            "bioloid-like", name, command=(0.1, 0.0, 0.0), nb_steps=5, pushes=[push]
        ).fall.fell
        for name in ("mpc", "mpc-steps", "mpc-timing")
    }
    assert fell == {"mpc": True, "mpc-steps": True, "mpc-timing": False}
