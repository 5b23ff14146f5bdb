"""The terrain cadence: steps lengthened where a terrain lengthens the strides."""

import numpy as np
import pytest

from mpcwalk.cli.walk_options import spec_from_args
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.cadence import TERRAIN_CADENCE_SHARE, cadence_stretch, largest_advance
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side
from mpcwalk.robot import load_robot
from mpcwalk.terrain import Stairs, Terrain
from mpcwalk.walking.runner import run_walk
from mpcwalk.walking.specification import WalkSpec, read_spec, write_spec
from mpcwalk.walking.walk_setup import set_up_walk

#: The robustness matrix's stairs of the small humanoid (run of 1.5 soles), the way up.
STAIRS = Terrain([Stairs(0.3, 0.012, 0.15, 3)])


def _foot(side: Side, x: float, y: float, yaw: float = 0.0) -> Footstep:
    return Footstep(side, np.array([x, y, 0.0]), yaw)


def test_the_stretch_keeps_the_largest_advance_within_the_share_of_the_flat_step():
    left, right = _foot(Side.LEFT, 0.0, 0.05), _foot(Side.RIGHT, 0.0, -0.05)
    steps = (
        _foot(Side.RIGHT, 0.05, -0.05),
        _foot(Side.LEFT, 0.10, 0.05),  # 0.05 ahead of the right foot
        _foot(Side.RIGHT, 0.40, -0.05),  # 0.30 ahead of the left foot (a tread's run)
        _foot(Side.LEFT, 0.40, 0.05),
    )
    plan = FootstepPlan(left, right, steps)
    assert largest_advance(plan) == pytest.approx(0.30)
    assert cadence_stretch(plan, 0.2) == pytest.approx(0.30 / (TERRAIN_CADENCE_SHARE * 0.2))
    assert cadence_stretch(plan, 0.2, share=1.0) == pytest.approx(1.5)
    assert cadence_stretch(plan, 1.0) == 1.0  # within the share: nothing changes
    # the advance is along the support foot's heading: a step to the side advances nothing
    turned = FootstepPlan(left, right, (_foot(Side.RIGHT, 0.0, -0.35, yaw=np.pi / 2),))
    assert largest_advance(turned) == pytest.approx(0.0, abs=1e-12)
    assert largest_advance(FootstepPlan(left, right, ())) == 0.0


@pytest.mark.parametrize("reach, share", [(0.0, 0.75), (0.2, 0.0), (0.2, 1.5), (float("nan"), 1)])
def test_a_bad_reach_or_share_is_a_named_error(reach, share):
    plan = FootstepPlan(_foot(Side.LEFT, 0.0, 0.05), _foot(Side.RIGHT, 0.0, -0.05), ())
    with pytest.raises(ConfigurationError, match="max_step_forward|share"):
        cadence_stretch(plan, reach, share=share)


def test_the_option_is_a_checked_boolean_of_the_plan_and_of_the_command_line(tmp_path):
    with pytest.raises(ConfigurationError, match="terrain_cadence must be true or false"):
        WalkSpec.build("bioloid-like", terrain_cadence="yes")
    spec = WalkSpec.build("bioloid-like", nb_steps=4, terrain=STAIRS, terrain_cadence=True)
    assert "--terrain-cadence" in spec.command_line()
    path = write_spec(spec, tmp_path / "spec.toml")
    assert read_spec(path).plan.terrain_cadence is True
    assert "--terrain-cadence" not in WalkSpec.build("bioloid-like", nb_steps=4).command_line()

    class Args:  # what argparse gives for `mpcwalk walk --steps 4 --terrain-cadence`
        spec = None

    given = Args()
    given.__dict__.update(nb_steps=4, terrain_cadence=True)
    assert spec_from_args(given, out=tmp_path).plan.terrain_cadence is True


def test_the_cadence_stretches_the_clock_and_keeps_the_footsteps():
    robot = load_robot("bioloid-like", visual=False)
    base = WalkSpec.build("bioloid-like", controller="mpc", command=(0.1, 0.0, 0.0), nb_steps=16)
    plain = set_up_walk(base.replace(terrain=STAIRS), robot)
    slow = set_up_walk(base.replace(terrain=STAIRS, terrain_cadence=True), robot)
    T = plain.timing.step_duration
    k = 0.15 / (TERRAIN_CADENCE_SHARE * robot.leg_limits.max_step_forward)  # a run a step
    assert slow.timing.step_duration == pytest.approx(k * T)
    assert slow.timing.double_support_ratio == plain.timing.double_support_ratio
    assert slow.schedule.duration > plain.schedule.duration + (k - 1) * T * 16
    for a, b in zip(slow.plan.steps, plain.plan.steps, strict=True):
        assert np.array_equal(a.position, b.position) and a.yaw == b.yaw
    # the resolved walk is the walk as it steps: walking it again plans the same steps
    resolved = slow.spec
    assert not resolved.plan.terrain_cadence and resolved.plan.nb_steps == 16
    assert resolved.plan.step_duration == pytest.approx(k * T)
    assert resolved.plan.command == pytest.approx((0.1 / k, 0.0, 0.0))
    again = set_up_walk(resolved, robot)
    assert again.timing == slow.timing
    for a, b in zip(again.plan.steps, slow.plan.steps, strict=True):
        assert np.allclose(a.position, b.position, atol=1e-12)
    # on the flat floor the option changes nothing
    flat = set_up_walk(base.replace(terrain_cadence=True), robot)
    assert flat.timing.step_duration == T and flat.spec.plan.command == (0.1, 0.0, 0.0)


def test_a_cadence_beyond_the_longest_step_duration_is_a_named_error():
    robot = load_robot("bioloid-like", visual=False)
    spec = WalkSpec.build(
        "bioloid-like", command=(0.002, 0.0, 0.0), nb_steps=16, terrain=STAIRS, step_duration=30.0
    )
    set_up_walk(spec, robot)  # 30 s steps are a walk
    with pytest.raises(ConfigurationError, match="terrain cadence would lengthen the steps"):
        set_up_walk(spec.replace(terrain_cadence=True), robot)


@pytest.mark.slow
def test_the_small_humanoid_climbs_the_stairs_it_falls_on_at_its_own_cadence():
    """At the preset's 0.5 s a step the robot climbs a tread (0.15 m) a step, 0.3 m/s for a
    command of 0.1 m/s, and falls on the first tread; lengthened by the cadence (2.5 x) it
    climbs the three treads and lands within 2 cm of its footsteps on the sensors."""
    spec = WalkSpec.build(
        "bioloid-like", controller="mpc", command=(0.1, 0.0, 0.0), nb_steps=16, terrain=STAIRS
    )
    climbed = run_walk(spec.replace(terrain_cadence=True))
    assert not climbed.fall.fell
    assert climbed.metrics.steps_completed == climbed.metrics.steps_planned == 17
    assert climbed.metrics.landing_error_3d_cm_mean < 2.0
    fallen = run_walk(spec)
    assert fallen.fall.fell and fallen.metrics.steps_completed < 12
