"""Paper A: state machine, clamping with carried remainder, path errors, closed-loop walk."""

import numpy as np
import pytest
from conftest import get_robot
from stabilizer_inputs import estimated_state, foot, stabilizer_input

from mpcwalk.control.stabilizers import (
    STABILIZERS,
    Stabilizer,
    StabilizerChain,
    make_stabilizer,
)
from mpcwalk.control.stabilizers.ankle_imu import AnkleImuStabilizer
from mpcwalk.control.stabilizers.footstep_reaiming import FootstepReaiming, GaitState
from mpcwalk.exceptions import (
    ConfigurationError,
    FootstepFileError,
    InfeasibleStep,
    StabilizerNotFound,
)
from mpcwalk.experiments.paper_a.config import DEFAULT_SPECS, PATHS_DIR, load_config
from mpcwalk.experiments.paper_a.run import paper_a_sweep
from mpcwalk.experiments.paper_a.table import PAPER_A_LABEL, PAPER_A_ROW, format_table
from mpcwalk.experiments.paper_a.walks import (
    TimedController,
    placement_errors,
    table_row,
    walk_path,
)
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, StepTiming
from mpcwalk.footsteps.mdat import parse_mdat, plan_from_path
from mpcwalk.footsteps.path_follower import PathFollower
from mpcwalk.footsteps.reachability import ATLAS_REACHABILITY
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.swing_foot import FeetState

STRAIGHT = PATHS_DIR / "straight.mdat"
LINE = "{xl} {yl} 0 1 0 0 0 {xr} {yr} 0 1 0 0 0"


def _schedule(nb_steps=4, T=1.0):
    left = Footstep(Side.LEFT, [0.0, 0.12, 0.0], 0.0)
    right = Footstep(Side.RIGHT, [0.0, -0.12, 0.0], 0.0)
    steps, feet = [], {Side.LEFT: left, Side.RIGHT: right}
    for k in range(nb_steps):
        side = Side.RIGHT if k % 2 == 0 else Side.LEFT
        feet[side] = feet[side].moved(position=feet[side].position + [0.2, 0.0, 0.0])
        steps.append(feet[side])
    plan = FootstepPlan(left, right, steps, StepTiming(step_duration=T))
    return ContactSchedule(plan)


def test_state_machine_cycles_through_paper_a_states():
    schedule = _schedule(nb_steps=4, T=1.0)
    machine = FootstepReaiming()
    machine.schedule = schedule
    for t in np.arange(0.0, schedule.duration, 0.01):
        machine.update(float(t))
    states = [state for _, state in machine.history]
    assert states == [
        GaitState.BEGIN,
        GaitState.LIFT_RIGHT,
        GaitState.LOWER_RIGHT,
        GaitState.LIFT_LEFT,
        GaitState.LOWER_LEFT,
        GaitState.LIFT_RIGHT,
        GaitState.LOWER_RIGHT,
        GaitState.LIFT_LEFT,
        GaitState.LOWER_LEFT,
        GaitState.DONE,
    ]
    times = [t for t, _ in machine.history]
    # lift at the step start (walk_start = 1 s), lower at the middle of single support
    assert times[1] == pytest.approx(schedule.walk_start, abs=0.011)
    assert times[2] == pytest.approx(schedule.walk_start + 0.5, abs=0.011)
    assert times[-1] == pytest.approx(schedule.walk_end, abs=0.011)


def test_state_machine_refuses_to_go_back_in_time():
    machine = FootstepReaiming()
    machine.schedule = _schedule()
    assert machine.update(1.1) is GaitState.LIFT_RIGHT
    with pytest.raises(ConfigurationError, match="cannot go from 'lift right' to 'begin'"):
        machine.update(0.2)
    # skipping a state (a tick longer than half a step) is refused too
    fresh = FootstepReaiming()
    fresh.schedule = machine.schedule
    fresh.update(1.1)
    with pytest.raises(ConfigurationError, match="from 'lift right' to 'lift left'"):
        fresh.update(2.1)


def test_reaim_from_measured_support_corrects_drift():
    schedule = _schedule(nb_steps=2)
    machine = FootstepReaiming()
    machine.schedule = schedule
    planned_support = schedule.plan.support_foot(0)
    drift = np.array([0.03, -0.01, 0.0])
    measured = planned_support.moved(position=planned_support.position + drift)
    offset = machine.aim_step(0, measured)
    # the landing relative to the measured support hits the file target: the reference
    # frame shifts it back by the support's drift
    assert offset == pytest.approx([-0.03, 0.01, 0.0], abs=1e-12)
    assert machine.landings[0].xy == pytest.approx(schedule.plan.steps[0].xy)
    # a yaw drift of the support turns the landing about it
    turned = planned_support.moved(yaw=0.05)
    offset = machine.aim_step(0, turned)
    assert offset[2] == pytest.approx(-0.05, abs=1e-12)


def test_reaiming_stabilizer_works_from_a_hand_built_input():
    """No controller: the state machine reads the measured support sole of a typed input and
    moves the swing foot's and the CoM's targets by the landing offset."""
    robot, schedule = get_robot("atlas-like"), _schedule(nb_steps=2)
    machine = FootstepReaiming(yaw_source="sole")
    chain = StabilizerChain([machine, Stabilizer()])
    t = schedule.walk_start + 0.3  # step 0: the right foot swings, the left one supports
    drift = np.array([0.03, -0.01, 0.0])
    support = schedule.plan.support_foot(0).position + drift
    state = estimated_state(sole_positions=(support, schedule.plan.initial_right.position))
    inputs = stabilizer_input(robot, schedule, t=t, state=state)
    chain.reset(inputs)
    assert machine.schedule is schedule
    targets = chain.adjust_targets(inputs)
    assert machine.state is GaitState.LIFT_RIGHT
    assert machine.offsets[Side.RIGHT] == pytest.approx([-0.03, 0.01, 0.0], abs=1e-12)
    assert machine.landings[0].xy == pytest.approx(schedule.plan.steps[0].xy)
    before = inputs.targets
    np.testing.assert_array_equal(targets.feet.left.position, before.feet.left.position)
    moved = targets.feet.right.position[:2] - before.feet.right.position[:2]
    assert np.linalg.norm(moved) > 0.0  # part of the way to the re-aimed landing
    np.testing.assert_allclose(targets.com_xy - before.com_xy, 0.5 * moved, atol=1e-15)


def test_clamping_carries_the_remainder():
    left = Footstep(Side.LEFT, [0.0, 0.12, 0.0], 0.0)
    right = Footstep(Side.RIGHT, [0.0, -0.12, 0.0], 0.0)
    target = Footstep(Side.LEFT, [0.5, 0.12, 0.0], 0.0)  # 0.5 m: beyond x_max = 0.30 m
    follower = PathFollower(left, right, [target], ATLAS_REACHABILITY)
    first = follower.next_step(right, left)
    assert first.xy == pytest.approx([0.30, 0.12])  # clamped onto the rectangle border
    assert follower.nb_clamped_steps == 1 and not follower.finished
    # the other foot aims at its own file pose (x = 0), which lies behind the rectangle
    # (x_min = -0.15 m): it is drawn forward to the nearest safe point
    second = follower.next_step(first, right)
    assert second.side is Side.RIGHT and second.xy == pytest.approx([0.15, -0.12])
    third = follower.next_step(second, first)  # remainder carried: 0.2 m still missing
    assert third.xy == pytest.approx([0.45, 0.12])
    fourth = follower.next_step(third, second)
    fifth = follower.next_step(fourth, third)
    assert fourth.xy == pytest.approx([0.30, -0.12])
    assert fifth.xy == pytest.approx([0.5, 0.12])  # the target, exactly
    assert follower.nb_extra_steps == 4 and follower.nb_clamped_steps == 4


def test_malformed_path_names_the_line():
    text = "# comment\n" + LINE.format(xl=0, yl=0.12, xr=0, yr=-0.12) + "\n0 0.12 0 1 0 0\n"
    with pytest.raises(FootstepFileError, match=r"<string>:3.*expected 14 numbers") as error:
        parse_mdat(text)
    assert error.value.line == 3
    text = (
        LINE.format(xl=0, yl=0.12, xr=0, yr=-0.12)
        + "\n"
        + LINE.format(xl="0.2", yl="abc", xr=0, yr=-0.12)
    )
    with pytest.raises(FootstepFileError, match=r":2 \(field 'ylf'\).*'abc' is not a number"):
        parse_mdat(text)


def test_unreachable_path_names_the_line():
    lines = [
        LINE.format(xl=0, yl=0.12, xr=0, yr=-0.12),
        LINE.format(xl=0, yl=0.12, xr=0, yr=-0.12),
        LINE.format(xl=0, yl=3.0, xr=0, yr=-0.12),
    ]  # left foot 2.9 m sideways
    waypoints = parse_mdat("\n".join(lines))
    with pytest.raises(InfeasibleStep, match=r"line 3.*out of reach"):
        plan_from_path(waypoints, rectangle=ATLAS_REACHABILITY, max_extra_steps=3)


def test_stabilizer_names():
    assert STABILIZERS.names() == ["none", "ankle-imu", "gyro", "reaim"]
    assert make_stabilizer("none") is None and make_stabilizer(None) is None
    assert isinstance(make_stabilizer("ankle-imu"), AnkleImuStabilizer)
    reaim = make_stabilizer("reaim")
    assert isinstance(reaim, FootstepReaiming) and reaim.name == "reaim"
    assert reaim.yaw_source == "imu" and reaim.holds_heading
    assert make_stabilizer("reaim", yaw_source="sole").yaw_source == "sole"
    with pytest.raises(
        StabilizerNotFound, match=r"Unknown stabilizer 'gyros'.*ankle-imu, gyro, reaim\. \(mpcwalk"
    ):
        make_stabilizer("gyros")
    with pytest.raises(ConfigurationError, match="stabilizer 'gyro' takes no option 'kp'; its"):
        make_stabilizer("gyro", kp=1.0)
    with pytest.raises(
        ConfigurationError, match="AnkleImuStabilizer kp must be a number >= 0, got -1.0"
    ):
        AnkleImuStabilizer(kp=-1.0)


def test_the_shipped_comparison_is_paper_a_gait_the_static_qp_and_the_mpc():
    assert [(s.generator, s.step_duration, s.double_support_ratio) for s in DEFAULT_SPECS] == [
        ("static", 12.0, 0.2),
        ("static", 3.5, 0.5),
        ("static-qp", 12.0, 0.2),
        ("static-qp", 3.0, 0.5),
        ("mpc", 1.0, 0.2),
        ("mpc", 0.8, 0.2),
        ("mpc", 0.6, 0.2),
    ]
    assert DEFAULT_SPECS[0].label == PAPER_A_LABEL and DEFAULT_SPECS[0].ankle_imu
    assert DEFAULT_SPECS[3].generator_options == (("com_margin", 0.04), ("zmp_margin", 0.03))
    assert [s.swing_profile for s in DEFAULT_SPECS[:3]] == ["ctraj", "ctraj", "cosine"]
    assert DEFAULT_SPECS[0].controller().stabilizers == ("reaim", "ankle-imu")
    quick = load_config(quick=True)
    assert [s.label for s in quick.specs] == ["mpc, 1.0 s"] and quick.nb_steps == 2
    assert load_config().paths == ("straight", "turning", "ramp")
    assert sorted(p.name for p in PATHS_DIR.glob("*.mdat")) == [
        "ramp.mdat",
        "straight.mdat",
        "turning.mdat",
    ]
    assert sorted(p.name for p in PATHS_DIR.glob("*.toml")) == ["ramp.toml"]  # its terrain
    cases = paper_a_sweep(load_config()).cases
    assert {c.path_name: c.terrain for c in cases} == {
        "straight": None,
        "turning": None,
        "ramp": str(PATHS_DIR / "ramp.toml"),
    }


@pytest.mark.slow
def test_the_quick_paper_a_table(tmp_path):
    """`mpcwalk experiment run paper_a --quick`: the MPC at 1 s per step, two steps of the
    straight path: its row, its top view and placement errors, paper A's row above it."""
    from mpcwalk.cli import main as cli_main
    from mpcwalk.sweep import read_rows

    out = tmp_path / "paper_a"
    command = ["experiment", "run", "paper_a", "--quick", "--out", str(out), "--no-progress"]
    assert cli_main(command) == 0
    (row,) = read_rows(out / "results.csv")
    assert row["case_id"] == "straight/mpc, 1.0 s" and not row["error"]
    assert row["row"]["steps"] == "2/2" and not row["row"]["fell"]
    assert len(row["position_errors_cm"]) == 2
    assert row["row"]["position_error_mean_cm"] == pytest.approx(
        np.mean(row["position_errors_cm"]), rel=1e-9
    )
    assert 0.0 < row["row"]["position_error_max_cm"] < 1.5
    report = (out / "report.md").read_text()
    assert "paper A (Atlas, DRCsim, reported)" in report and "| mpc, 1.0 s | straight |" in report
    assert "mpcwalk experiment run paper_a --quick" in report
    for name in ("top_straight_mpc_1s.png", "placement_errors_straight.png"):
        assert (out / name).stat().st_size > 1000


def test_table_has_paper_a_row_first():
    table = format_table([])
    assert "paper A (Atlas, DRCsim, reported)" in table.splitlines()[2]
    assert "| 4.96 |" in table and "| 2.05 |" in table and PAPER_A_ROW["step_duration_s"] == 12


@pytest.mark.slow
def test_straight_walk_mpc_meets_the_placement_goals():
    """The issue's goal for the best QP controller, on the whole straight path at 1 s/step:
    mean position error < 0.5 cm, max < 1.5 cm, yaw mean < 0.2 deg, max < 1 deg, no fall."""
    spec = TimedController("mpc, 1.0 s", "mpc", 1.0)
    result = walk_path(spec, STRAIGHT)
    row = table_row(spec, "straight", result)
    assert not row["fell"]
    assert row["steps"] == "18/18"
    assert row["position_error_mean_cm"] < 0.5
    assert row["position_error_max_cm"] < 1.5
    assert row["yaw_error_mean_deg"] < 0.2
    assert row["yaw_error_max_deg"] < 1.0
    positions, _yaws = placement_errors(result)
    assert len(positions) == 18
    assert np.mean(positions) == pytest.approx(row["position_error_mean_cm"], rel=1e-9)


@pytest.mark.slow
def test_the_3d_ramp_path_is_walked_within_paper_a_s_flat_ground_figures():
    """Paper A's 3D goal: the straight path placed on a 5 deg ramp up, a landing and a ramp
    down (heights and tilted quaternions in ramp.mdat), walked on that terrain at 1 s/step
    with the landings, in 3D, under paper A's flat-ground errors (2.05 cm mean, 4.96 cm
    max). Before the swing over a brow kept paper M's profile the robot fell there."""
    spec = TimedController("mpc, 1.0 s", "mpc", 1.0)
    result = walk_path(spec, PATHS_DIR / "ramp.mdat", terrain=PATHS_DIR / "ramp.toml")
    row = table_row(spec, "ramp", result)
    assert not row["fell"] and row["steps"] == "18/18"
    assert row["position_error_mean_cm"] < PAPER_A_ROW["position_error_mean_cm"]
    assert row["position_error_max_cm"] < PAPER_A_ROW["position_error_max_cm"]
    positions, _yaws = placement_errors(result)
    assert len(positions) == 18
    assert max(result.log.sole_positions[:, :, 2].max(axis=0)) > 0.07  # it went up the ramp


@pytest.mark.slow
def test_paper_a_gait_walks_with_ankle_imu():
    """Paper A's gait (static generator + ankle-imu + re-aiming), shortened, at the
    fastest upright timing found (3.5 s, r_ds 0.5), 3 steps."""
    spec = TimedController(
        "paper A", "static", 3.5, double_support_ratio=0.5, ankle_imu=True, swing_profile="ctraj"
    )
    result = walk_path(spec, STRAIGHT, nb_steps=3)
    assert not result.fall.fell
    assert result.metrics.steps_completed == 3
    assert result.metrics.foot_position_error_cm_max < PAPER_A_ROW["position_error_max_cm"]
    assert result.config.stabilizer == "reaim+ankle-imu"


@pytest.mark.slow
def test_ankle_strategy_makes_the_difference_at_three_seconds_a_step():
    """Faster (3 s per step) the ankle strategy and IMU correction make the difference over
    four steps (on the whole path it still falls, at step 7, and at step 2 without them)."""
    fast = dict(double_support_ratio=0.5, swing_profile="ctraj")
    without = walk_path(TimedController("b", "static", 3.0, **fast), STRAIGHT, nb_steps=4)
    assert without.fall.fell
    with_ankle = walk_path(
        TimedController("a", "static", 3.0, ankle_imu=True, **fast), STRAIGHT, nb_steps=4
    )
    assert not with_ankle.fall.fell


@pytest.mark.parametrize(
    "com_offset, joint, sign",
    [((0.05, 0.0), "left_ankle_pitch", 1.0), ((0.0, 0.05), "left_ankle_roll", -1.0)],
)
def test_ankle_strategy_turns_the_body_back_over_the_foot(com_offset, joint, sign):
    """CoM 5 cm ahead of (left of) the reference over a left support foot: the ankle pitch
    (roll) correction is +kp (-kp) times the 0.05 rad angle (plus the first integral step):
    a joint angle q turns the body above the planted foot by -q, back over the foot."""
    robot = get_robot("atlas-like")
    names = robot.joint_names
    stabilizer = AnkleImuStabilizer(kp=0.5, ki=0.2, kd=0.0, imu_gain=0.0)
    feet = FeetState(0.0, 0, foot([0.0, 0.1, 0.0]), foot([0.0, -0.1, 0.05], in_contact=False))
    state = estimated_state(
        com=(com_offset[0], 0.1 + com_offset[1], 1.0),
        sole_positions=((0.0, 0.1, 0.0), (0.0, -0.1, 0.05)),
        nb_joints=len(names),
    )
    inputs = stabilizer_input(
        robot, _schedule(), t=0.01, feet=feet, com_reference=(0.0, 0.1, 1.0), state=state
    )
    stabilizer.reset(inputs)
    assert inputs.support_weights == (1.0, 0.0)  # all on the left foot
    targets = np.zeros(len(names))
    out = stabilizer.adjust_joint_targets(inputs, targets)
    expected = sign * 0.05 * (0.5 + 0.2 * 0.01)
    assert out[names.index(joint)] == pytest.approx(expected, rel=1e-9)
    changed = {names[i] for i in np.flatnonzero(out)}
    assert changed <= {"left_ankle_pitch", "left_ankle_roll"}  # the swing foot is left alone
    assert np.all(targets == 0.0)  # input untouched
