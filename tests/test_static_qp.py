"""Paper A's static gait as a QP: CoM projection inside the support polygon."""

import functools

import numpy as np
import pytest
from conftest import walk_outputs
from plans import velocity_schedule as arc_schedule

from mpcwalk.exceptions import NoSolutionFound
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.generators import make_generator
from mpcwalk.generators.static_qp import StaticQPGenerator

SLOW = dict(step_duration=4.0, r_ds=0.5)  # paper A walks slowly (12 s per step)
COMMANDS = {  # (vx [m/s], vy [m/s], yaw rate [rad/s]) at T = 4 s
    "straight": (0.025, 0.0, 0.0),
    "turning": (0.0125, 0.0, np.deg2rad(2.5)),
    "sideways": (0.0, 0.0125, 0.0),
}


@functools.cache
def slow_walk(name):
    schedule = arc_schedule(COMMANDS[name], **SLOW)
    generator = StaticQPGenerator()
    return schedule, generator, walk_outputs(generator, schedule)


@pytest.mark.slow
@pytest.mark.parametrize("name", COMMANDS)
def test_com_projection_keeps_its_margin_at_every_planned_sample(name, record_property):
    schedule, generator, outs = slow_walk(name)
    margin = generator.parameters.com_margin
    assert margin == 0.01
    assert all(o.solve.success for o in outs[1:])
    planned_com = min(
        support_margins(schedule, o.horizon.times, o.horizon.com).min() for o in outs[1:]
    )
    planned_zmp = min(
        support_margins(schedule, o.horizon.times, o.horizon.zmp).min() for o in outs[1:]
    )
    times = np.array([o.time for o in outs])
    executed_com = support_margins(schedule, times, np.array([o.com for o in outs])).min()
    executed_zmp = support_margins(schedule, times, np.array([o.zmp for o in outs])).min()
    for key, value in (
        ("planned_com", planned_com),
        ("planned_zmp", planned_zmp),
        ("executed_com", executed_com),
        ("executed_zmp", executed_zmp),
    ):
        record_property(f"min_{key}_margin_m", value)
    print(
        f"{name}: CoM margin planned {planned_com * 1e3:.2f} mm, executed "
        f"{executed_com * 1e3:.2f} mm; ZMP planned {planned_zmp * 1e3:.2f} mm, executed "
        f"{executed_zmp * 1e3:.2f} mm"
    )
    assert planned_com >= margin - 1e-6
    assert planned_zmp >= -1e-6
    # Between samples too (the CoM rows use the coming single-support foot).
    assert executed_com >= margin - 1e-6
    assert executed_zmp >= -1e-6


@pytest.mark.slow
@pytest.mark.parametrize("name", COMMANDS)
def test_com_is_over_the_support_foot_in_single_support_and_ends_at_rest(name):
    schedule, _generator, outs = slow_walk(name)
    times = np.array([o.time for o in outs])
    com = np.array([o.com for o in outs])
    single = schedule.is_single_support(times)
    distance = np.linalg.norm(com - schedule.support_center(times), axis=1)
    assert np.max(distance[single]) < 0.012  # [m], measured 7-11 mm
    # Quasi-static: the ZMP stays within a few millimetres of the CoM.
    zmp = np.array([o.zmp for o in outs])
    assert np.max(np.linalg.norm(zmp - com, axis=1)) < 0.010  # [m], measured 4.8-8.6 mm
    assert np.linalg.norm(outs[-1].com_velocity) < 1e-3


@pytest.mark.slow
def test_the_qp_decides_when_to_move_in_double_support():
    schedule, generator, outs = slow_walk("straight")
    first_single = schedule.walk_start + schedule.t_b  # 3 s
    horizon = generator.parameters.duration  # 1.6 s
    com = np.array([o.com for o in outs])
    times = np.array([o.time for o in outs])
    # Nothing pulls the CoM before single support enters the horizon...
    still = times < first_single - horizon - 0.1
    assert np.max(np.abs(com[still] - com[0])) < 1e-9
    # ... and it is over the support foot when single support begins.
    k = int(np.searchsorted(times, first_single))
    assert np.linalg.norm(com[k] - schedule.support_center(times[k])) < 0.012
    # CoM weights are switched by phase: P was rewritten as phases passed.
    assert generator.qp.P_version >= 2 * schedule.plan.nb_steps


def test_fast_timing_is_infeasible_for_a_static_gait():
    schedule = arc_schedule(COMMANDS["straight"], step_duration=0.5, r_ds=0.2)
    generator = make_generator("static-qp", solver="daqp", max_fallback_ticks=5)
    generator.reset(schedule)
    with pytest.raises(NoSolutionFound, match="daqp"):
        while not generator.done:
            out = generator.step()
            if not out.solve.success:
                assert out.solve.fallback
