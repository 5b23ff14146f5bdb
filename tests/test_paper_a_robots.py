"""Paper A's static gait on every shipped robot: the damped IK of the static gaits and the
ankle-imu servo stiffness rule (issue 26)."""

import numpy as np
import pytest
from conftest import get_robot, walk

from mpcwalk.control.stabilizers.ankle_imu import (
    PAPER_A_STIFFNESS_RATIO,
    AnkleImuStabilizer,
    stiffness_scale,
)
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.walking.controller_builder import STATIC_IK_DAMPING, build_controller
from mpcwalk.walking.specification import ControllerSpec, WalkSpec
from mpcwalk.walking.walk_setup import set_up_walk


def _ankle_scales(name: str) -> dict:
    robot = get_robot(name)
    stabilizer = AnkleImuStabilizer()
    stabilizer.reset(type("Inputs", (), {"robot": robot})())
    return stabilizer.scales


def test_stiffness_rule_keeps_paper_a_gains_on_atlas_and_soft_servos():
    assert stiffness_scale(4000.0, 150.0, 1.093) == 1.0  # paper A's robot
    assert stiffness_scale(300.0, 33.34, 0.6816) == 1.0  # g1: softer ankle servos
    # bioloid-like: 50 N m/rad on 2.02 kg at 0.23 m, rho = 10.97
    rho = 50.0 / (2.02 * 9.81 * 0.23)
    assert stiffness_scale(50.0, 2.02, 0.23) == pytest.approx(PAPER_A_STIFFNESS_RATIO / rho)
    assert stiffness_scale(50.0, 2.02, 0.23) == pytest.approx(0.2267, abs=1e-4)
    # the stiffer the servo, the smaller its share
    shares = [stiffness_scale(kp, 90.0, 0.877) for kp in (2000.0, 4000.0, 8000.0)]
    assert shares[0] > shares[1] > shares[2]
    for bad in ((0.0, 1.0, 1.0), (1.0, -1.0, 1.0), (1.0, 1.0, 0.0)):
        with pytest.raises(ConfigurationError, match="positive"):
            stiffness_scale(*bad)


def test_ankle_imu_scales_each_robots_ankles_by_the_rule():
    for name, share in (("atlas-like", 1.0), ("g1", 1.0), ("bioloid-like", 0.2267)):
        for scales in _ankle_scales(name).values():
            np.testing.assert_allclose(scales, share, atol=1e-4)
    off = AnkleImuStabilizer(stiffness_rule=False)
    off.reset(type("Inputs", (), {"robot": get_robot("bioloid-like")})())
    for scales in off.scales.values():
        np.testing.assert_array_equal(scales, 1.0)


def _controller(robot: str, controller: str, vx: float):
    spec = WalkSpec.build(robot, controller=controller, command=(vx, 0.0, 0.0), nb_steps=2)
    setup = set_up_walk(spec, robot=get_robot(robot))
    return build_controller(
        setup.robot,
        spec.controller,
        setup.schedule,
        control_period=spec.plan.control_period,
        step_height=setup.step_height,
    )


def test_only_the_static_gaits_get_the_damped_ik():
    assert _controller("g1", "paper-a", 0.015).ik.damping == STATIC_IK_DAMPING == 1e-4
    # its QP form holds the CoM over the support too: undamped, g1 fell in its first step
    assert _controller("g1", "static-qp", 0.015).ik.damping == STATIC_IK_DAMPING
    assert _controller("g1", "mpc", 0.1).ik.damping == 1e-6  # the IK's default, unchanged


def test_g1_static_reference_does_not_oscillate_at_its_longest_steps():
    """The kinematic reference alone (no simulator): g1's first 0.18 m step lands on a
    nearly straight knee; undamped, the IK's joint velocities alternated in sign every tick
    and reached 3.7 rad/s around the touchdown (11.1 to 12 s)."""
    walker = _controller("g1", ControllerSpec.named("paper-a").replace(stabilizers=()), 0.015)
    walker.reset()
    largest, previous, jerk = 0.0, None, 0.0
    while walker.time < 13.0:
        velocity = walker.step(None).ik.v[6:]
        if walker.time < 10.5:  # the lowering of the first step and its touchdown
            continue
        largest = max(largest, float(np.abs(velocity).max()))
        if previous is not None:
            jerk = max(jerk, float(np.abs(velocity - previous).max()) / 0.01)
        previous = velocity
    assert largest < 1.0  # [rad/s]
    assert jerk < 50.0  # [rad/s^2]; undamped: 1800


@pytest.mark.slow
def test_paper_a_walks_g1_at_its_longest_steps():
    result = walk("g1", "paper-a", command=(0.015, 0.0, 0.0), nb_steps=2, progress=False)
    metrics = result.metrics
    assert not metrics.fell  # before: fell at 12.6 s, in its first step
    assert metrics.steps_completed == metrics.steps_planned == 3
    assert abs(metrics.yaw_change_deg) < 2.0
    assert metrics.foot_position_error_cm_mean < 1.0
