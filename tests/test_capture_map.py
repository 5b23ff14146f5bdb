"""The LIPM's push-recovery map along a robot's nominal walk, and the quick run of the
experiment."""

import pytest
from conftest import get_robot

from mpcwalk.experiments.capture_map.cells import capture_map


@pytest.fixture(scope="module")
def cells():
    return capture_map(get_robot("bioloid-like"), nb_directions=8, nb_phases=6)


def test_more_steps_and_adapted_timing_never_recover_less(cells):
    assert len(cells) == 48
    for cell in cells:
        assert cell.fixed[0] <= cell.fixed[1] <= cell.fixed[2]
        for fixed, adaptive in zip(cell.fixed, cell.adaptive):
            assert adaptive >= fixed - 1e-12


def test_late_in_single_support_only_a_step_recovers_a_forward_push(cells):
    """Late in single support the DCM has left the stance sole towards the next footstep:
    standing cannot stop it, the step that is about to land can (measured 1.04 N s), and
    landing it earlier adds more (1.23 N s)."""
    late = next(c for c in cells if c.direction_deg == 0.0 and c.phase == 0.75)
    assert late.single_support
    assert late.fixed[0] == 0.0
    assert late.fixed[1] > 0.8
    assert late.adaptive[1] > late.fixed[1] + 0.1


def test_a_push_towards_the_stance_leg_is_held_by_the_ankle_alone(cells):
    """Early in single support, a push towards the stance leg: the swing leg may not cross,
    so the bound with steps is the ankle's (the same with 0, 1 and 2 steps at 0.5 s)."""
    cell = next(c for c in cells if c.phase == 0.25 and c.direction_deg == 90.0)
    assert cell.single_support
    assert cell.fixed[2] == pytest.approx(cell.fixed[0])


def test_in_double_support_the_robot_stands_on_both_soles():
    """Stepping in place, just after the right foot lands: the support is the hull of both
    soles, so a push to the left is held without a step up to the left sole's outer edge:
    ``m omega (edge - dcm_y)``, with the DCM of the nominal walk (an analytic check of the
    0-step bound; the hull of one sole only gave 0.18 N s)."""
    import numpy as np

    from mpcwalk.footsteps.footstep import FootGeometry, StepTiming
    from mpcwalk.gait.contact_schedule import ContactSchedule
    from mpcwalk.generators import make_generator, rollout
    from mpcwalk.models.lipm import LIPM
    from mpcwalk.walking.footstep_planning import plan_walk_footsteps

    robot = get_robot("bioloid-like")
    (cell,) = [
        c
        for c in capture_map(robot, nb_directions=4, nb_phases=6, speed_share=0.0)
        if c.direction_deg == 90.0 and c.phase == pytest.approx(11 / 12, abs=1e-4)
    ]
    assert not cell.single_support
    gait = robot.gait
    timing = StepTiming(gait.step_duration, gait.double_support_ratio)
    plan = plan_walk_footsteps(robot, command=(0.0, 0.0, 0.0), nb_steps=6, timing=timing)
    schedule = ContactSchedule(plan, FootGeometry(*robot.sole_size))
    lipm = LIPM(com_height=robot.com_height)
    walk = rollout(make_generator("mpc", lipm=lipm), schedule)
    t = schedule.walk_start + (2 + 11 / 12) * timing.step_duration
    i = min(int(np.searchsorted(walk.times, t)), len(walk.times) - 1)
    dcm_y = walk.com[i, 1] + walk.com_velocity[i, 1] / lipm.omega
    left = plan.stance(3)[plan.steps[3].side]  # the left foot, about to lift
    edge = left.xy[1] + 0.5 * robot.sole_size[1]
    expected = robot.total_mass * lipm.omega * (edge - dcm_y)
    assert cell.fixed[0] == pytest.approx(expected, rel=1e-6)
    assert cell.fixed[0] > 1.0  # [N s]


def test_towards_the_stance_leg_even_fast_steps_add_nothing_to_the_ankle():
    """Standing on the left foot with the DCM of the nominal walk's early single support
    (1 cm inside the sole), a push to the left: the swing (right) leg may not cross, and the
    left leg's own step after it comes too late even when both swings last 0.15 s. The
    bound is the ankle's, ``m omega (outer edge - dcm)``, with 0, 1 or 2 steps."""
    import numpy as np

    from mpcwalk.footsteps.capturability import capture_regions, largest_impulse, sole_box
    from mpcwalk.footsteps.footstep import Side
    from mpcwalk.models.lipm import LIPM

    robot = get_robot("bioloid-like")
    omega = LIPM(com_height=robot.com_height).omega
    dcm = np.array([0.0, -0.01])  # stance frame
    regions = capture_regions(
        2,
        omega=omega,
        sole=sole_box(*robot.sole_size),
        reach=robot.leg_limits.rectangle(),
        first_swing=Side.RIGHT,
        first_step_time=0.15,
        step_time=0.15,
    )
    ankle = robot.total_mass * omega * (0.5 * robot.sole_size[1] - dcm[1])
    for n in range(3):
        impulse = largest_impulse(
            regions[: n + 1], dcm, np.pi / 2, mass=robot.total_mass, omega=omega
        )
        assert impulse == pytest.approx(ankle, rel=1e-9)
    # the same push to the right is where the swing leg's step helps
    right = [
        largest_impulse(regions[: n + 1], dcm, -np.pi / 2, mass=robot.total_mass, omega=omega)
        for n in range(3)
    ]
    assert right[1] > right[0] + 0.1


@pytest.mark.slow
def test_the_quick_capture_map(tmp_path):
    """`mpcwalk experiment run capture_map --quick`: bioloid-like's map on 4 directions and
    2 phases in one row, its table (the medians of the cells) and its figure."""
    import statistics

    from mpcwalk.cli import main as cli_main
    from mpcwalk.sweep import read_rows

    out = tmp_path / "capture_map"
    command = ["experiment", "run", "capture_map", "--quick", "--out", str(out), "--no-progress"]
    assert cli_main(command) == 0
    (row,) = read_rows(out / "results.csv")
    assert row["robot"] == "bioloid-like" and len(row["cells"]) == 4 * 2
    expected = capture_map(get_robot("bioloid-like"), nb_directions=4, nb_phases=2)
    assert [c["fixed"] for c in row["cells"]] == [list(c.fixed) for c in expected]
    report = (out / "report.md").read_text()
    one_step = statistics.median(c.fixed[1] for c in expected)
    assert f"| bioloid-like | 1 | {one_step:.2f} |" in report
    assert "mpcwalk experiment run capture_map --quick" in report
    assert (out / "capture_map_bioloid-like.png").stat().st_size > 1000
