"""Every generator on 20-step plans from the velocity planner: the ZMP (CoM for
the static gaits) stays inside the support polygon."""

import functools

import numpy as np
import pytest

from mpcwalk import (
    ContactSchedule,
    StepTiming,
    VelocityCommand,
    VelocityPlanner,
    make_generator,
    rollout,
)
from mpcwalk.exceptions import GeneratorNotFound
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.generators import generator_names

#: Paper M's commands; sideways at the planner's lateral limit region.
COMMANDS = {
    "straight": VelocityCommand(0.1, 0.0, 0.0),
    "turning": VelocityCommand(0.1, 0.0, np.deg2rad(20.0)),
    "sideways": VelocityCommand(0.0, 0.05, 0.0),
}
FAST = StepTiming(step_duration=0.5, double_support_ratio=0.2)  # paper M, Table 1
SLOW = StepTiming(step_duration=2.0, double_support_ratio=0.5)  # static gaits

#: Smallest margins measured (ZMP for dynamic generators, CoM for static ones), [m].
MEASURED = {
    ("analytic", "straight"): 0.030,
    ("analytic", "turning"): 0.030,
    ("analytic", "sideways"): 0.030,
    ("preview", "straight"): 0.021,
    ("preview", "turning"): 0.021,
    ("preview", "sideways"): 0.021,
    ("mpc", "straight"): 0.011,
    ("mpc", "turning"): 0.010,
    ("mpc", "sideways"): 0.0057,
}


@functools.cache
def planned(generator, command):
    static = generator in ("static", "static-qp")
    timing = SLOW if static else FAST
    scale = FAST.step_duration / timing.step_duration  # same step lengths
    c = COMMANDS[command]
    plan = VelocityPlanner(timing=timing).plan(
        VelocityCommand(c.vx * scale, c.vy * scale, c.vyaw * scale), 20
    )
    schedule = ContactSchedule(plan)
    traj = rollout(make_generator(generator), schedule)
    return schedule, traj


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize("generator", ["analytic", "preview", "mpc"])
def test_dynamic_generators_keep_the_zmp_inside(generator, command):
    schedule, traj = planned(generator, command)
    assert traj.times[-1] == pytest.approx(schedule.duration)
    assert schedule.plan.nb_steps == 21  # 20 steps and the closing one
    margins = support_margins(schedule, traj.times, traj.zmp)
    assert margins.min() > 0.004
    assert margins.min() == pytest.approx(MEASURED[generator, command], abs=0.004)
    assert traj.nb_failures == 0
    # The walk ends at rest above the middle of the final feet.
    np.testing.assert_allclose(traj.com[-1], schedule.torso_waypoints[-1], atol=2e-3)


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize("generator", ["static", "static-qp"])
def test_static_generators_keep_the_com_inside(generator, command):
    schedule, traj = planned(generator, command)
    com = support_margins(schedule, traj.times, traj.com)
    zmp = support_margins(schedule, traj.times, traj.zmp)
    assert com.min() > 0.009  # static-qp's margin is 0.01 m; static: CoM on the foot centre
    assert zmp.min() > 0.0
    assert traj.nb_failures == 0


def test_all_names_are_registered():
    assert generator_names() == [
        "analytic",
        "static",
        "preview",
        "mpc",
        "static-qp",
        "mpc-steps",
        "mpc-nlp",
        "mpc-hip",
    ]
    with pytest.raises(
        GeneratorNotFound,
        match="available: analytic, static, preview, mpc, static-qp, mpc-steps, mpc-nlp, mpc-hip. "
        "\\(mpcwalk generators",
    ):
        make_generator("zmp-magic")
