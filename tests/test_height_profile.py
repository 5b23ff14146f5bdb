"""The CoM height and the ZMP plane off the flat floor, and the time-varying LIPM of the
walking MPCs."""

import numpy as np
import pytest

from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, StepTiming
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.height_profile import HeightProfile, height_profile
from mpcwalk.generators.mpc import MpcGenerator
from mpcwalk.generators.mpc_steps import FootstepMpcGenerator
from mpcwalk.models.lipm import LIPM

H = 0.2  # [m] CoM height above the ground reference


def climbing_schedule(rise=0.05, nb_steps=8, top=6, timing=StepTiming(0.6, 0.2, 0.6, 0.8)):
    """Step-over stairs: step k lands on tread min(k + 1, top)."""
    steps = [
        Footstep(side, (0.08 * (k + 1), side.sign * 0.05, min(k + 1, top) * rise))
        for k, side in ((k, Side.LEFT if k % 2 == 0 else Side.RIGHT) for k in range(nb_steps))
    ]
    plan = FootstepPlan(
        Footstep(Side.LEFT, (0, 0.05, 0)), Footstep(Side.RIGHT, (0, -0.05, 0)), steps, timing
    )
    return ContactSchedule(plan)


def test_level_footsteps_keep_the_constant_lipm():
    schedule = climbing_schedule(rise=0.0)
    profile = HeightProfile(schedule, H)
    assert profile.is_level
    times = np.linspace(0.0, schedule.duration, 50)
    np.testing.assert_array_equal(profile.eta(times, 9.81), np.full(50, H / 9.81))


def test_the_ground_reference_meets_its_knots_and_is_twice_differentiable():
    schedule = climbing_schedule()
    profile = HeightProfile(schedule, H, lean=0.3)
    for phase in schedule.phases:
        middle = 0.5 * (phase.start + phase.end)
        heights = [float(f.position[2]) for f in phase.feet.values()]
        if phase.single_support:
            assert profile.ground(middle) == pytest.approx(heights[0])
            assert profile.zmp_plane(middle)[0] == pytest.approx(heights[0])
    # a double support between soles 5 cm apart in height: 30 % above the lower one
    first_ds = next(p for p in schedule.phases if p.step_index == 1 and not p.single_support)
    t = first_ds.start  # the middle of the double support around the boundary of steps 0, 1
    assert profile.ground(t) == pytest.approx(0.0 + 0.3 * 0.05)
    times = np.linspace(0.0, schedule.duration, 20001)
    z, dz, ddz = profile.com(times)
    dt = times[1] - times[0]
    np.testing.assert_allclose(np.gradient(z, dt)[2:-2], dz[2:-2], atol=2e-3)
    np.testing.assert_allclose(np.gradient(dz, dt)[2:-2], ddz[2:-2], atol=2e-2)
    assert np.max(np.abs(np.diff(ddz))) < 0.05  # no jump of the vertical acceleration
    assert z[-1] == pytest.approx(0.3 + H)


@pytest.mark.parametrize("formulation", ["dense", "sparse"])
def test_the_mpc_plans_with_the_time_varying_lipm(formulation):
    schedule = climbing_schedule()
    profile = height_profile(schedule, H)
    generator = MpcGenerator(lipm=LIPM(com_height=H), formulation=formulation)
    generator.reset(schedule)
    worst, gap = np.inf, 0.0
    for _ in range(120):
        out = generator.step()
        # the ZMP of the output is the one of the varying height, computed here anew
        z, _, ddz = profile.com(out.time)
        eta = (z[0] - profile.zmp_plane(out.time)[0]) / (9.81 + ddz[0])
        np.testing.assert_allclose(out.zmp, out.com - eta * out.com_acceleration, atol=1e-12)
        worst = min(worst, float(schedule.support_polygon(out.time).signed_distance(out.zmp)))
        constant = out.com - H / 9.81 * out.com_acceleration
        gap = max(gap, float(np.linalg.norm(constant - out.zmp)))
    assert worst > 0.0  # the constrained ZMP stays in the support polygons
    assert gap > 1e-3  # and it is not the constant-height one
    # its predicted horizon obeys the same law sample by sample
    qp = generator.qp
    prediction = qp.predict(qp.jerks(generator.last_result.x))
    z, _, ddz = profile.com(prediction.times)
    eta = (z - profile.zmp_plane(prediction.times)) / (9.81 + ddz)
    np.testing.assert_allclose(
        prediction.zmp, prediction.com - eta[:, None] * prediction.com_acceleration, atol=1e-9
    )


def test_the_footstep_mpc_plans_with_the_time_varying_lipm():
    schedule = climbing_schedule()
    generator = FootstepMpcGenerator(lipm=LIPM(com_height=H))
    generator.reset(schedule)
    worst = np.inf
    for _ in range(150):
        out = generator.step()
        current = out.schedule or generator.schedule
        worst = min(worst, float(current.support_polygon(out.time).signed_distance(out.zmp)))
    assert worst > -1e-3
