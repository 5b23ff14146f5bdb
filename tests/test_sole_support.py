"""The CoP's share of a sole that rocks: narrowed at once, grown back over time, whole again
at touch-down; and the inverse dynamics keeping a rocking sole's CoP inside that share."""

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot
from test_inverse_dynamics import _targets

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.contact_wrench import wrench_cone
from mpcwalk.ik.inverse_dynamics import InverseDynamicsQP
from mpcwalk.ik.sole_support import SoleSupport

SOLE = (0.2, 0.1)


def _half_length(cone: np.ndarray) -> float:
    """The CoP's reach along the sole's length in a cone's rows (|ty| <= r fz)."""
    return float(-cone[8, 2])


def test_a_rocking_sole_narrows_its_cop_at_once_and_grows_it_back_over_time():
    support = SoleSupport(SOLE, 0.7, 0.9, rocking_rate=1.0, min_share=0.5, recovery_rate=2.0)
    full = wrench_cone(SOLE, 0.7, 0.9)
    assert np.array_equal(support.cone(0, 0.8, False, 0.01), full)  # below the rate
    cone = support.cone(0, 1.5, False, 0.01)  # 0.9 * 1 / 1.5
    assert support.shares == pytest.approx([0.6, 0.9])
    assert np.allclose(cone, wrench_cone(SOLE, 0.7, 0.6))
    assert _half_length(cone) == pytest.approx(0.5 * 0.6 * 0.2)
    support.cone(0, 9.0, False, 0.01)
    assert support.shares[0] == pytest.approx(0.5)  # never below min_share
    for _ in range(10):  # still: 2 per second back
        support.cone(0, 0.0, False, 0.01)
    assert support.shares[0] == pytest.approx(0.7)
    support.cone(0, 1.5, False, 0.01)  # rocking again: the smaller of the two
    assert support.shares[0] == pytest.approx(0.6)
    assert np.array_equal(support.cone(0, 0.0, True, 0.01), full)  # a new touch-down
    assert support.shares == [0.9, 0.9]


def test_a_zero_rate_never_narrows_and_bad_values_are_refused():
    support = SoleSupport(SOLE, 0.7, 0.9, rocking_rate=0.0)
    assert np.array_equal(support.cone(1, 50.0, False, 0.01), wrench_cone(SOLE, 0.7, 0.9))
    for bad in ({"rocking_rate": -1.0}, {"min_share": 0.95}, {"recovery_rate": 0.0}):
        with pytest.raises(ConfigurationError):
            SoleSupport(SOLE, 0.7, 0.9, **bad)


@pytest.mark.parametrize("rate", [0.0, 3.0])
def test_the_inverse_dynamics_keeps_a_rocking_soles_cop_inside_its_share(rate):
    """The small humanoid on its left sole, pushed hard forward so that the CoP goes to its
    bound: still, the bound is 0.9 of the half sole; rolling at 3 rad/s, 0.5."""
    robot = get_robot("bioloid-like")
    q = robot.q0
    solver = InverseDynamicsQP(robot, solver="daqp", rocking_rate=1.0)
    model, data = robot.model, robot.model.createData()
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    left = pin.getFrameJacobian(
        model, data, robot.frame_id(robot.foot_frames[0]), pin.ReferenceFrame.LOCAL
    )
    v = np.linalg.pinv(left[3:5]) @ np.array([0.0, rate])  # the sole pitching
    assert np.hypot(*(left[3:5] @ v)) == pytest.approx(rate)
    targets = _targets(
        robot, q, com_acceleration=np.array([8.0, 0.0, 0.0]), contact_weights=(1.0, 0.0)
    )
    solver.solve(q, np.zeros(model.nv), targets)  # the touch-down tick: the whole sole
    result = solver.solve(q, v, targets)
    assert result.success
    share = 0.9 if rate == 0.0 else 0.5
    assert solver.support.shares[0] == pytest.approx(share)
    reach = abs(result.cops[0, 0]) / (0.5 * robot.sole_size[0])
    assert reach == pytest.approx(share, abs=1e-6)  # at the bound, not beyond


def test_a_walk_sets_the_rocking_rate_on_motors_only():
    import dataclasses

    from mpcwalk.control.torque_controller import TorqueController
    from mpcwalk.footsteps import VelocityCommand, VelocityPlanner
    from mpcwalk.gait.contact_schedule import ContactSchedule
    from mpcwalk.walking.controller_builder import check_controller
    from mpcwalk.walking.specification import ControllerSpec

    spec = ControllerSpec(generator="mpc", controller_options={"rocking_rate": 2.0})
    check_controller(spec, "torque")
    with pytest.raises(ConfigurationError, match="rocking_rate drive.*actuation is 'position'"):
        check_controller(spec, "position")
    negative = dataclasses.replace(spec, controller_options={"rocking_rate": -1.0})
    with pytest.raises(ConfigurationError, match="rocking_rate"):
        check_controller(negative, "torque")
    robot = get_robot("bioloid-like")
    schedule = ContactSchedule(VelocityPlanner().plan(VelocityCommand(0.1, 0.0, 0.0), nb_steps=2))
    walker = TorqueController.for_robot(robot, "mpc", schedule, rocking_rate=2.0, state_delay=0.01)
    assert walker.inverse_dynamics.support.rocking_rate == 2.0
    with pytest.raises(ConfigurationError, match="rocking_rate given with inverse_dynamics"):
        TorqueController.for_robot(
            robot,
            "mpc",
            schedule,
            rocking_rate=2.0,
            inverse_dynamics=InverseDynamicsQP(robot, solver="daqp"),
        )
