"""The bridge between the closed forms and their QP reformulation.

With no active constraint, Wieber's MPC is a linear feedback on the state and
the previewed ZMP reference, like Kajita's preview controller; paper M's
closed-form CoM solves the same LIPM for the same polygonal ZMP reference with
boundary conditions at every step instead of a preview. Measured on a 10-step
straight walk with paper M's Table 1 parameters (T = 0.5 s, r_ds = 0.2,
z_c = 0.23 m), 1.6 s preview/horizon at 5 ms, ZMP weight 1, jerk weight 1e-6:

- unconstrained MPC vs Kajita preview (no integral action): 0.047 mm max CoM difference;
- unconstrained MPC vs Kajita preview with integral action: 1.1 mm;
- unconstrained MPC vs the closed form: 20 mm at the start of the walk (the closed
  form keeps the CoM at rest until the first step and then jumps in velocity,
  the preview starts moving it earlier), 1.0 mm once walking (steps 2 to 8).
"""

import functools

import numpy as np
import pytest

from mpcwalk import (
    AnalyticGenerator,
    ContactSchedule,
    PreviewGenerator,
    VelocityCommand,
    VelocityPlanner,
    rollout,
)
from mpcwalk.generators.mpc import MpcGenerator

PERIOD = 0.005  # [s]


@functools.cache
def walks():
    plan = VelocityPlanner().plan(VelocityCommand(0.1, 0.0, 0.0), 10)
    schedule = ContactSchedule(plan)
    mpc = MpcGenerator(
        solver="kkt",
        control_period=PERIOD,
        sampling_period=PERIOD,
        horizon=320,
        constrained=False,
        zmp_weight=1.0,
        jerk_weight=1e-6,
        velocity_weight=0.0,
    )
    return schedule, {
        "mpc": rollout(mpc, schedule),
        "preview": rollout(
            PreviewGenerator(
                control_period=PERIOD, integral_action=False, zmp_weight=1.0, jerk_weight=1e-6
            ),
            schedule,
        ),
        "preview-integral": rollout(PreviewGenerator(control_period=PERIOD), schedule),
        "analytic": rollout(AnalyticGenerator(control_period=PERIOD), schedule),
    }


def max_com_difference(a, b, selection=slice(None)):
    return float(np.linalg.norm(a.com[selection] - b.com[selection], axis=1).max())


def test_unconstrained_mpc_reproduces_kajita_preview_control():
    _, w = walks()
    assert max_com_difference(w["mpc"], w["preview"]) < 1e-4  # measured 4.7e-5 m
    assert max_com_difference(w["mpc"], w["preview-integral"]) < 2e-3  # measured 1.1e-3 m


def test_unconstrained_mpc_reproduces_the_closed_form_once_walking():
    schedule, w = walks()
    times = w["mpc"].times
    T = schedule.step_duration
    walking = (times > schedule.walk_start + 2 * T) & (times < schedule.walk_end - 2 * T)
    assert max_com_difference(w["mpc"], w["analytic"], walking) < 2e-3  # measured 1.0e-3 m
    # Start and stop differ by the closed form's velocity jumps (measured 20 mm).
    assert max_com_difference(w["mpc"], w["analytic"]) == pytest.approx(0.020, abs=0.003)


def test_all_three_track_the_same_zmp_reference():
    schedule, w = walks()
    for name in ("mpc", "preview", "analytic"):
        reference = schedule.zmp_reference(w[name].times)
        assert np.abs(w[name].zmp - reference).max() < 0.02, name  # measured 17 mm (mpc)
