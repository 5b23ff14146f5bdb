"""The hip-strategy MPC (``mpc-hip``): the flywheel's columns of the footstep QP, used only
when the ZMP would leave the support, within the upper body's limits."""

import numpy as np
import pytest
from plans import kicked_walk

from mpcwalk import LIPM, ContactSchedule, VelocityCommand, VelocityPlanner, make_generator
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.models.flywheel import FlywheelLimits

LIMITS = FlywheelLimits.small_humanoid()


def _schedule(nb_steps=6):
    plan = VelocityPlanner().plan(VelocityCommand(vx=0.1, vy=0.0, vyaw=0.0), nb_steps=nb_steps)
    return ContactSchedule(plan)


def _walk(name="mpc-hip", kick=(0.0, 0.0), at=1.5, **options):
    """The outputs of a walk on the LIPM whose CoM velocity is kicked at ``at`` [s]."""
    return kicked_walk(name, _schedule(), kick, at, **options)


def test_without_torque_it_is_the_footstep_mpc():
    """flywheel_scale=0: the torque columns are bounded to zero, the plans are mpc-steps'."""
    _, steps = _walk("mpc-steps", kick=(0.2, 0.05))
    _, hip = _walk(kick=(0.2, 0.05), flywheel_scale=0.0)
    com = np.array([o.com for o in hip])
    np.testing.assert_allclose(com, np.array([o.com for o in steps]), atol=1e-6)
    assert max(np.abs(o.flywheel.lean).max() for o in hip) < 1e-9


def test_undisturbed_the_flywheel_rests_and_pushed_it_leans_within_its_limits():
    _, calm = _walk()
    assert max(np.abs(o.flywheel.torque).max() for o in calm) < 0.02 * max(LIMITS.max_torque)
    steps_generator, steps = _walk("mpc-steps", kick=(0.35, 0.0), at=1.4)
    assert any(not o.solve.success for o in steps[1:])  # the ZMP cannot hold this kick
    generator, pushed = _walk(kick=(0.35, 0.0), at=1.4)
    torque = np.array([o.flywheel.torque for o in pushed])
    lean = np.array([o.flywheel.lean for o in pushed])
    momentum = np.array([o.flywheel.momentum for o in pushed])
    assert torque[:, 0].max() > 0.5 * LIMITS.max_torque[0]  # forward push: lean forward
    assert np.all(np.abs(torque) <= np.array(LIMITS.max_torque) + 1e-6)
    assert np.all(np.abs(momentum) <= np.array(LIMITS.max_momentum) * 1.05)
    assert np.all(np.abs(lean) <= np.array(LIMITS.max_angle) * 1.05)
    assert lean[:, 0].max() > 0.02
    assert np.abs(lean[-1]).max() < 0.1 * lean[:, 0].max()  # back upright
    assert all(o.solve.success for o in pushed[1:])
    # the ZMP stays in the support (constrained twice per sampling period: between those
    # points it leaves it by a few mm, less than mpc-steps' after its failed solves) while
    # the CMP the CoM accelerates from leaves it
    omega2 = LIPM(com_height=0.23).omega ** 2
    times = np.array([o.time for o in pushed[1:]])
    zmp = np.array([o.zmp for o in pushed[1:]])
    cmp = np.array([o.com - o.com_acceleration / omega2 for o in pushed[1:]])
    margin = support_margins(generator.schedule, times, zmp).min()
    assert margin > -0.01
    steps_zmp = np.array([o.zmp for o in steps[1:]])
    assert margin > support_margins(steps_generator.schedule, times, steps_zmp).min()
    assert support_margins(generator.schedule, times, cmp).min() < margin - 0.01


@pytest.mark.parametrize("solver", ["daqp", "proxqp"])
def test_the_back_ends_that_take_the_dense_qp_agree(solver):
    _, reference = _walk(kick=(0.35, 0.0), at=0.9)
    _, other = _walk(kick=(0.35, 0.0), at=0.9, solver=solver)
    lean = np.array([o.flywheel.lean for o in reference])
    np.testing.assert_allclose(np.array([o.flywheel.lean for o in other]), lean, atol=2e-4)


def test_bad_flywheel_options_are_named():
    with pytest.raises(ConfigurationError, match="flywheel_scale"):
        make_generator("mpc-hip", flywheel_scale=-1.0)
    with pytest.raises(ConfigurationError, match="flywheel_limits"):
        make_generator("mpc-hip", flywheel_limits=3.0)
    with pytest.raises(ConfigurationError, match="samples"):
        make_generator("mpc-hip", flywheel_samples=0)
    generator = make_generator("mpc-hip", flywheel_limits={**LIMITS.__dict__})
    assert generator.flywheel_limits == LIMITS
