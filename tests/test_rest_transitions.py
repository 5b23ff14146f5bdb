"""Paper M's closed form starts and stops at rest where the robot cannot follow its velocity
jump (the capturability rule of mpcwalk.generators.rest_transitions), and paper M's engine
then walks g1."""

import math

import numpy as np
import pytest
from conftest import get_robot, walk

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import StepTiming
from mpcwalk.footsteps.timing import FootGeometry
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.analytic import AnalyticGenerator
from mpcwalk.generators.rest_transitions import quintic_shift, start_is_capturable
from mpcwalk.models.lipm import LIPM
from mpcwalk.robot.loading import example_robot_data_dir, load_robot
from mpcwalk.robot.survey.draft import draft_preset
from mpcwalk.robot.survey.writer import preset_toml
from mpcwalk.walking.footstep_planning import plan_walk_footsteps
from mpcwalk.walking.runner import run_walk
from mpcwalk.walking.specification import WalkSpec


def _omega(z_c: float) -> float:
    return math.sqrt(9.81 / z_c)


def test_rule_keeps_the_papers_start_on_its_robot_and_not_on_g1():
    # bioloid-like (paper M Table 1): stance 0.04 m, soles 0.06 m wide, z_c 0.23 m, t_b 0.05 s
    assert start_is_capturable([0, 0], [0, 0.04], 0.06, _omega(0.23), 0.05)
    # g1: stance 0.1185 m, soles 0.07 m, z_c 0.6816 m, t_b 0.06 s
    assert not start_is_capturable([0, 0], [0, 0.1185], 0.07, _omega(0.6816), 0.06)
    # a long enough double support makes any start capturable
    assert start_is_capturable([0, 0], [0, 0.1185], 0.07, _omega(0.6816), 1.0)


def test_weak_ankle_rolls_narrow_the_cop_reach_of_the_rule():
    # the drafted human of example-robot-data: stance 0.082 m, soles 0.121 m wide, z_c
    # 0.9614 m, t_b 0.07 s; its ankle roll motors (20 N m for 74.7 kg) carry the CoP 2.7 cm
    args = ([0, 0], [0, 0.082], 0.121, _omega(0.9614), 0.07)
    assert start_is_capturable(*args)  # the sole's width alone: 0.036 m for 0.022 m
    assert not start_is_capturable(*args, cop_reach=0.0273)  # 0.027 m for 0.055 m
    # a reach beyond the sole's edge changes nothing
    g1 = ([0, 0], [0, 0.1185], 0.07, _omega(0.6816), 0.06)
    assert not start_is_capturable(*g1, cop_reach=0.5)
    assert start_is_capturable([0, 0], [0, 0.04], 0.06, _omega(0.23), 0.05, cop_reach=1.0)


def test_the_generator_takes_the_robots_cop_reach():
    atlas, g1 = get_robot("atlas-like"), get_robot("g1")
    # atlas-like's 90 N m ankle rolls hold its 150 kg 6.1 cm from a sole's centre, within
    # its 6.5 cm; g1's 35 N m for 33.3 kg reach past the edge of its 7 cm wide soles
    assert atlas.lateral_cop_reach == pytest.approx(90.0 / (150.0 * 9.81), rel=1e-3)
    assert g1.lateral_cop_reach == 0.5 * g1.sole_size[1]
    generator = AnalyticGenerator.for_robot(atlas)
    assert generator.lateral_cop_reach == atlas.lateral_cop_reach
    assert AnalyticGenerator(lateral_cop_reach=None).lateral_cop_reach is None
    with pytest.raises(ConfigurationError, match="lateral_cop_reach"):
        AnalyticGenerator(lateral_cop_reach=-0.01)


def test_quintic_shift_is_at_rest_at_both_ends():
    start, end = np.array([0.0, 0.0]), np.array([0.01, 0.09])
    for t, position in ((0.0, start), (1.0, end)):
        state = quintic_shift(start, end, t, 1.0)
        np.testing.assert_allclose(state[0], position, atol=1e-12)
        np.testing.assert_allclose(state[1:], 0.0, atol=1e-12)
    half = quintic_shift(start, end, 0.5, 1.0)
    np.testing.assert_allclose(half[0], 0.5 * (start + end))
    assert np.all(np.abs(half[1]) > 0.0)


def _generator(robot: str, start_at_rest):
    bot = get_robot(robot)
    gait = bot.gait
    timing = StepTiming(step_duration=gait.step_duration, double_support_ratio=0.2)
    plan = plan_walk_footsteps(bot, command=(0.1, 0.0, 0.0), nb_steps=6, timing=timing)
    length, width = bot.sole_size
    schedule = ContactSchedule(plan, FootGeometry(length=length, width=width))
    generator = AnalyticGenerator(lipm=LIPM(com_height=bot.com_height), start_at_rest=start_at_rest)
    generator.reset(schedule)
    return generator, schedule


@pytest.mark.parametrize("robot, at_rest", [("bioloid-like", False), ("g1", True)])
def test_the_rule_decides_and_the_walk_starts_and_ends_at_rest(robot, at_rest):
    generator, schedule = _generator(robot, None)
    assert (generator.rest_waypoints[0] is not None) == at_rest
    start, end = schedule.walk_start, schedule.walk_end
    states = generator.evaluate(np.array([start - 1e-9, start, end - 1e-9, end]))
    if at_rest:
        np.testing.assert_allclose(states[:, 1], 0.0, atol=1e-6)  # no velocity jump
        np.testing.assert_allclose(states[0, 0], states[1, 0], atol=1e-6)  # continuous
        np.testing.assert_allclose(states[2, 0], states[3, 0], atol=1e-6)
        # the standing time brings the CoM back above the feet's midpoint
        final = generator.evaluate(np.array([schedule.duration]))[0, 0]
        np.testing.assert_allclose(final, schedule.torso_waypoints[-1], atol=1e-12)
    else:  # the paper's velocity jump, lateral about 0.2 m/s
        assert abs(states[1, 1, 1]) > 0.1
    forced, _ = _generator(robot, False)
    assert forced.rest_waypoints == (None, None)


def test_paper_m_walks_g1():
    """Before the rule, g1 fell in its second step (the CoM left behind the reference's jump)."""
    result = walk("g1", "paper-m", command=(0.1, 0.0, 0.0), nb_steps=4)
    m = result.metrics
    assert result.config.state_source == "estimator"
    assert not m.fell, m.fall_reason
    assert m.steps_completed == m.steps_planned == 5


@pytest.mark.slow
@pytest.mark.skipif(example_robot_data_dir() is None, reason="example-robot-data is not installed")
def test_paper_m_walks_the_drafted_human_with_weak_ankle_rolls(tmp_path):
    """The human of example-robot-data, drafted as it is: its 20 N m ankle rolls cannot carry
    its 74.7 kg onto a sole's edge. With the paper's start, judged on the sole's width, the
    stance ankle roll stayed at its limit and paper M's engine fell at 2.60 s."""
    root = example_robot_data_dir()
    assert root is not None
    reference = "human_description/robots/human.urdf"
    preset = tmp_path / "human.toml"
    preset.write_text(preset_toml(draft_preset(root / reference, reference=reference)))
    robot = load_robot(str(preset), visual=False)
    assert robot.lateral_cop_reach == pytest.approx(20.0 / (robot.total_mass * 9.81))
    assert robot.lateral_cop_reach < 0.5 * robot.sole_size[1] - 0.03
    spec = WalkSpec.build(str(preset), controller="paper-m", command=(0.1, 0.0, 0.0), nb_steps=4)
    m = run_walk(spec, robot=robot).metrics
    assert not m.fell, m.fall_reason
    assert m.steps_completed == m.steps_planned == 5
    assert m.foot_position_error_cm_mean < 2.0
