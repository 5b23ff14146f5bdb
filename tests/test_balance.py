"""The balance stabilizer on its own: integral action and CoM offset estimate on the LIPM, foot
damping signs on every robot, ZMP distribution, a hand-built input, the controller's option."""

import math

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot, walk_outputs
from stabilizer_inputs import estimated_state, foot, stabilizer_input

from mpcwalk.control.controller import WalkingController
from mpcwalk.control.stabilizers.balance import BALANCED_GENERATORS, BalanceStabilizer
from mpcwalk.control.stabilizers.balance_options import BalanceOptions
from mpcwalk.control.stabilizers.com_offset import ComOffsetEstimator, anchored_cop
from mpcwalk.control.stabilizers.dcm_integrator import DcmIntegrator
from mpcwalk.control.stabilizers.foot_damping import FootDamping
from mpcwalk.control.stabilizers.zmp_distribution import ZmpDistribution
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps import FootGeometry
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.swing_foot import FeetState
from mpcwalk.generators import ComState
from mpcwalk.robot.sensors import ForceTorqueReading
from mpcwalk.walking.footstep_planning import plan_walk_footsteps

OMEGA = math.sqrt(9.81 / 0.23)  # [1/s] bioloid-like's LIPM
DT = 0.01  # [s]
KP = 3.0  # the controller's default DCM gain
DEFAULTS = BalanceOptions().resolved(get_robot("bioloid-like").sole_size)


def lipm_step(c: np.ndarray, cd: np.ndarray, zmp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Exact LIPM step of ``DT`` with a constant ZMP."""
    x0, ch, sh = c - zmp, math.cosh(OMEGA * DT), math.sinh(OMEGA * DT)
    return zmp + x0 * ch + cd / OMEGA * sh, x0 * OMEGA * sh + cd * ch


def integrator(**options) -> DcmIntegrator:
    values = dict(gain=DEFAULTS.integral_gain, limit=DEFAULTS.integral_limit) | options
    return DcmIntegrator(**values)


def estimator() -> ComOffsetEstimator:
    return ComOffsetEstimator(
        time_constant=DEFAULTS.com_offset_time_constant,
        limit=DEFAULTS.com_offset_limit,
        dcm_threshold=DEFAULTS.com_offset_dcm_threshold,
    )


# ---------------------------------------------------------------- LIPM
def dcm_error_with_zmp_bias(integral: DcmIntegrator | None, bias, duration=10.0) -> np.ndarray:
    """Standing LIPM whose real ZMP is the commanded one plus ``bias``: the DCM error at the
    end of ``duration`` [s] under ``KP`` feedback (and the integral)."""
    c, cd = np.zeros(2), np.zeros(2)
    for _ in range(int(round(duration / DT))):
        error = c + cd / OMEGA  # the reference stands at the origin
        shift = np.zeros(2) if integral is None else integral.update(error, DT)
        c, cd = lipm_step(c, cd, KP * error + shift + bias)
    return c + cd / OMEGA


def test_integral_action_removes_a_constant_zmp_bias():
    bias = np.array([0.01, -0.005])  # [m]
    without = dcm_error_with_zmp_bias(None, bias)
    np.testing.assert_allclose(without, -bias / (KP - 1.0), atol=1e-9)  # -5 and 2.5 mm stay
    exact = dcm_error_with_zmp_bias(integrator(leak_time=math.inf), bias)
    assert np.abs(exact).max() < 1e-6  # measured 1.2e-7 m after 10 s
    leaky = dcm_error_with_zmp_bias(integrator(leak_time=DEFAULTS.integral_leak_time), bias)
    # the leak keeps (k_p - 1) / (k_p - 1 + k_i T) = 1/11 of the error: 0.45 mm of 5 mm
    ratio = (KP - 1.0) / (KP - 1.0 + DEFAULTS.integral_gain * DEFAULTS.integral_leak_time)
    np.testing.assert_allclose(leaky, -bias / (KP - 1.0) * ratio, rtol=0.02)
    # the anti-windup bound: a bias beyond the limit is only partly removed
    bounded = dcm_error_with_zmp_bias(integrator(leak_time=math.inf, limit=0.004), bias)
    assert bounded[0] == pytest.approx(-(0.01 - 0.004) / (KP - 1.0), abs=1e-6)


def test_com_offset_estimate_converges_to_the_true_offset_on_the_lipm():
    """The robot's CoM is the model's plus ``delta``. Position-controlled plant: the model's
    CoM follows the IK target (the walking reference minus the estimate); the measured CoP
    is the real CoM's LIPM ZMP. The estimate converges to ``delta`` and the real CoM onto the
    reference."""
    delta = np.array([0.008, -0.005])  # [m]
    part = estimator()
    period = 1.0  # [s] a lateral sway of two 0.5 s steps, walking forward at 0.1 m/s
    errors = []
    for k in range(int(30.0 / DT)):
        t = k * DT
        reference = np.array([0.1 * t, 0.02 * math.sin(2 * math.pi * t / period)])
        acceleration = np.array([0.0, -0.02 * (2 * math.pi / period) ** 2])
        acceleration *= math.sin(2 * math.pi * t / period)
        zmp = reference - acceleration / OMEGA**2
        real_com = reference - part.offset + delta  # the estimate moves slowly: no dynamics
        cop = real_com - acceleration / OMEGA**2
        part.update(cop, zmp, np.zeros(2), DT)
        errors.append(real_com - reference)
    np.testing.assert_allclose(part.offset, delta, atol=1e-6)  # measured 4e-8 m after 30 s
    assert np.abs(errors[0]).max() == pytest.approx(0.008)
    assert np.abs(errors[-1]).max() < 1e-6  # measured 4e-8 m


def test_com_offset_estimate_and_integral_share_the_work_on_a_zmp_controlled_lipm():
    """ZMP-controlled plant (the real CoM follows the LIPM of the commanded ZMP; the estimator
    sees the model's CoM, ``delta`` off): the integral takes the bias first and hands it over
    to the CoM offset estimate, which ends at ``delta``; the real CoM ends on the reference."""
    delta = np.array([0.008, -0.005])
    integral, part = integrator(leak_time=DEFAULTS.integral_leak_time), estimator()
    c, cd = delta.copy(), np.zeros(2)
    for _ in range(int(40.0 / DT)):
        error = c - delta + part.offset + cd / OMEGA  # the controller's DCM error
        shift = integral.update(error, DT)
        zmp = KP * error + shift
        part.update(zmp, np.zeros(2), error, DT)  # the CoP vs the plan's ZMP
        c, cd = lipm_step(c, cd, zmp)
    np.testing.assert_allclose(part.offset, delta, atol=1e-6)  # measured 6e-8 m after 40 s
    assert np.abs(c).max() < 1e-6 and np.abs(integral.shift).max() < 1e-6  # 5e-8, 1e-7 m
    # without the estimate, the real CoM stays off the reference by delta, the integral
    # holding the bias (with the leak: a fraction of it more)
    integral = integrator(leak_time=DEFAULTS.integral_leak_time)
    c, cd = delta.copy(), np.zeros(2)
    for _ in range(int(40.0 / DT)):
        error = c - delta + cd / OMEGA
        c, cd = lipm_step(c, cd, KP * error + integral.update(error, DT))
    assert np.abs(c).min() > 0.9 * np.abs(delta).min()


def test_com_offset_estimate_waits_while_the_dcm_error_is_large():
    """A push (a 5 cm DCM error for 3 s, the CoP 1 cm off) moves the estimate by what passes
    before the filtered DCM error crosses the threshold only; the estimate is bounded."""
    gated = estimator()
    free = ComOffsetEstimator(
        time_constant=DEFAULTS.com_offset_time_constant, limit=DEFAULTS.com_offset_limit
    )
    for _ in range(300):
        for part in (gated, free):
            part.update(np.array([0.01, 0.0]), np.zeros(2), np.array([0.05, 0.0]), DT)
    assert free.offset[0] > 0.005  # measured 5.1 mm
    assert gated.offset[0] < 0.03 * free.offset[0]  # measured 0.14 mm
    for _ in range(100000):
        gated.update(np.array([0.5, -0.5]), np.zeros(2), np.zeros(2), DT)
    np.testing.assert_allclose(np.abs(gated.offset), DEFAULTS.com_offset_limit)  # bounded


# ---------------------------------------------------------------- foot damping
def sole_rotation_in_base(robot, q, index):
    sole = robot.compute_sole_placements(q)[index]
    base = pin.Quaternion(q[3:7]).normalized().matrix()
    return base.T @ sole.rotation


@pytest.mark.parametrize("robot_name", ["bioloid-like", "atlas-like", "g1", "talos"])
def test_foot_damping_turns_the_foot_against_the_torque_error(robot_name):
    """Left foot pressing 2 cm ahead of its desired CoP: the toes go up (a negative turn about
    the sole's y axis, relative to the leg); 2 cm to the left of it: the left edge goes up (a
    positive turn about the sole's x axis). Checked with the forward kinematics of each robot
    (ankle joint axes and signs differ), the right foot and the other axis left alone."""
    robot = get_robot(robot_name)
    damping = FootDamping(gain=4.0, time_constant=math.inf, max_offset=0.5)
    damping.calibrate(robot)
    force = 0.5 * damping.weight
    for axis, cop in ((1, (0.02, 0.0)), (0, (0.0, 0.02))):
        damping.reset()
        torque = np.array([cop[1] * force, -cop[0] * force, 0.0])  # r x f
        left = ForceTorqueReading(np.array([0.0, 0.0, force]), torque)
        right = ForceTorqueReading(np.array([0.0, 0.0, force]), np.zeros(3))
        rotation = damping.update((left, right), np.zeros((2, 2)), (True, True), 0.1)
        expected = 0.1 * 4.0 * 0.02 * 0.5  # dt K |CoP error| share = 4 mrad
        assert rotation[0, axis] == pytest.approx(expected if axis == 0 else -expected)
        assert rotation[0, 1 - axis] == 0.0 and np.all(rotation[1] == 0.0)
        q = robot.q0.copy()
        for index, offsets in zip(damping.joint_indices.ravel(), damping.joint_offsets().ravel()):
            q[7 + index] += offsets
        before, after = (sole_rotation_in_base(robot, x, 0) for x in (robot.q0, q))
        turn = pin.log3(before.T @ after)  # in the sole frame
        assert turn[axis] == pytest.approx(rotation[0, axis], rel=0.02), (robot_name, turn)
        assert abs(turn[1 - axis]) < 0.05 * abs(turn[axis])
        right_before, right_after = (sole_rotation_in_base(robot, x, 1) for x in (robot.q0, q))
        np.testing.assert_allclose(right_before, right_after, atol=1e-12)


def test_foot_damping_leaks_bounds_and_skips_unloaded_feet():
    damping = FootDamping(gain=4.0, time_constant=1.0, max_offset=0.01)
    damping.calibrate(get_robot("bioloid-like"))
    force = damping.weight
    pressing = ForceTorqueReading(np.array([0.0, 0.0, force]), np.array([0.0, -0.02 * force, 0]))
    for _ in range(1000):
        rotation = damping.update((pressing, pressing), np.zeros((2, 2)), (True, False), DT)
    assert rotation[0, 1] == pytest.approx(-0.01)  # bounded (the steady value K T e = 0.08)
    assert np.all(rotation[1] == 0.0)  # not in contact
    light = ForceTorqueReading(np.array([0.0, 0.0, 0.01 * force]), np.zeros(3))
    rotation = damping.update((light, light), np.zeros((2, 2)), (True, True), 1.0)
    assert rotation[0, 1] == pytest.approx(-0.01 * math.exp(-1.0))  # leaks, no update
    with pytest.raises(ConfigurationError, match="time_constant must be a positive"):
        FootDamping(gain=1.0, time_constant=0.0, max_offset=0.1)


# ---------------------------------------------------------------- ZMP distribution
def test_zmp_distribution_shares_the_weight_and_keeps_the_zmp():
    distribution = ZmpDistribution((0.1, 0.06), margin=0.005)
    feet = FeetState(0.0, 0, foot([0.0, 0.05, 0.0]), foot([0.02, -0.05, 0.0], yaw=0.3))
    zmp = np.array([0.01, 0.02])
    targets = distribution.distribute(zmp, feet, 20.0)
    assert targets.weights.sum() == pytest.approx(1.0) and targets.forces.sum() == 20.0
    np.testing.assert_allclose(targets.weights @ targets.cops, zmp, atol=1e-12)
    assert targets.weights[0] > targets.weights[1]  # the ZMP is nearer the left foot
    single = FeetState(0.0, 0, foot([0.0, 0.05, 0.0]), foot([0.1, -0.05, 0.03], False))
    targets = distribution.distribute(np.array([0.2, 0.05]), single, 20.0)
    np.testing.assert_allclose(targets.weights, [1.0, 0.0])
    np.testing.assert_allclose(targets.cops[0], [0.045, 0.05])  # clamped 5 mm inside the sole
    with pytest.raises(ConfigurationError, match="margin"):
        ZmpDistribution((0.1, 0.06), margin=0.03)


def test_anchored_cop_places_each_foot_cop_on_its_planned_pose():
    feet = FeetState(0.0, 0, foot([0.0, 0.05, 0.0]), foot([0.1, -0.05, 0.0], yaw=math.pi / 2))
    left = ForceTorqueReading(np.array([0.0, 0.0, 30.0]), np.array([0.0, -0.01 * 30.0, 0.0]))
    right = ForceTorqueReading(np.array([0.0, 0.0, 10.0]), np.array([0.02 * 10.0, 0.0, 0.0]))
    cop = anchored_cop((left, right), (True, True), feet)
    # left: 1 cm ahead; right: 2 cm along its sole's y axis, i.e. -x in the world
    expected = (30.0 * np.array([0.01, 0.05]) + 10.0 * np.array([0.1 - 0.02, -0.05])) / 40.0
    np.testing.assert_allclose(cop, expected, atol=1e-12)
    assert anchored_cop((left, right), (False, False), feet) is None


# ---------------------------------------------------------------- the stabilizer
def schedule_for(robot, nb_steps=2):
    plan = plan_walk_footsteps(robot, command=(0.1, 0.0, 0.0), nb_steps=nb_steps)
    return ContactSchedule(plan, FootGeometry(*robot.sole_size))


def test_balance_stabilizer_works_from_a_hand_built_input():
    """No controller: the estimated CoP 1 cm ahead of the desired ZMP moves the CoM offset
    estimate forward and the IK's CoM target back; the left foot pressing on its toes gets a
    toes-up ankle offset; the servo targets given are not modified in place."""
    robot = get_robot("bioloid-like")
    schedule = schedule_for(robot)
    stabilizer = BalanceStabilizer()
    stabilizer.reset(stabilizer_input(robot, schedule))
    inputs = stabilizer_input(robot, schedule)
    feet = inputs.targets.feet
    weight = stabilizer.damping.weight
    zmp = 0.5 * (feet.left.position[:2] + feet.right.position[:2])
    wrenches = [
        ((0.0, 0.0, 0.5 * weight), (0.0, -0.01 * 0.5 * weight, 0.0)),  # CoP 1 cm ahead
        ((0.0, 0.0, 0.5 * weight), (0.0, -0.01 * 0.5 * weight, 0.0)),
    ]
    state = estimated_state(wrenches=wrenches, q=robot.q0)
    inputs = stabilizer_input(robot, schedule, state=state, zmp_reference=zmp)
    for _ in range(100):
        targets = stabilizer.adjust_targets(inputs)
    offset = stabilizer.com_offset
    assert offset[0] > 0.0 and abs(offset[1]) < 1e-12
    np.testing.assert_allclose(targets.com_xy, inputs.targets.com_xy - offset, atol=1e-15)
    joint_targets = np.zeros(len(robot.joint_names))
    out = stabilizer.adjust_joint_targets(inputs, joint_targets)
    assert np.all(joint_targets == 0.0)
    pitch = robot.joint_names.index("left_foot_pitch")
    changed = {robot.joint_names[i] for i in np.flatnonzero(out)}
    assert changed <= {f"{s}_foot_{a}" for s in ("left", "right") for a in ("pitch", "roll")}
    q = robot.q0.copy()
    q[7:] += out
    turn = pin.log3(
        sole_rotation_in_base(robot, robot.q0, 0).T @ sole_rotation_in_base(robot, q, 0)
    )
    assert turn[1] < 0.0 and out[pitch] != 0.0  # toes up
    # without an estimated state the rotations leak and the CoM offset stays
    quiet = stabilizer_input(robot, schedule, zmp_reference=zmp)
    before = stabilizer.damping.rotation.copy()
    stabilizer.adjust_joint_targets(quiet, joint_targets)
    np.testing.assert_allclose(stabilizer.damping.rotation, before * math.exp(-DT / 1.0))
    np.testing.assert_array_equal(stabilizer.adjust_targets(quiet).com_xy, targets.com_xy)


@pytest.mark.parametrize(
    "options, message",
    [
        ({"integral_gain": -1.0}, "integral_gain must be a non-negative"),
        ({"damping_gain": float("nan")}, "damping_gain must be a non-negative"),
        ({"com_offset_limit": float("inf")}, "com_offset_limit must be finite"),
        ({"integral_leak_time": 0.0}, "leak times must be positive"),
        ({"damping_max_offset": True}, "damping_max_offset must be a non-negative"),
    ],
)
def test_bad_balance_options_are_named_errors(options, message):
    with pytest.raises(ConfigurationError, match=message):
        BalanceOptions(**options)


def test_balance_options_resolve_their_lengths_from_the_sole():
    resolved = BalanceOptions(integral_limit=0.002).resolved((0.2, 0.08))
    assert resolved.integral_limit == 0.002  # given: kept
    assert resolved.com_offset_limit == pytest.approx(0.02)  # a quarter of 8 cm
    assert resolved.com_offset_dcm_threshold == pytest.approx(0.02)


# ---------------------------------------------------------------- in the controller
@pytest.mark.parametrize("generator", ["analytic", "static", "preview", "mpc"])
def test_balance_is_the_default_closed_loop_of_the_qp_generators(generator):
    robot = get_robot()
    schedule = schedule_for(robot, nb_steps=1)
    controller = WalkingController.for_robot(robot, generator, schedule)
    assert (controller.balance is not None) is (generator in BALANCED_GENERATORS)
    forced = WalkingController.for_robot(robot, generator, schedule, balance=True)
    assert isinstance(forced.balance, BalanceStabilizer)
    options = BalanceOptions(integral_gain=1.0)
    assert (
        WalkingController.for_robot(robot, generator, schedule, balance=options).balance.options
        is options
    )
    open_loop = WalkingController.for_robot(
        robot, generator, schedule, feedback=False, balance=True
    )
    assert open_loop.balance is None
    with pytest.raises(ConfigurationError, match="balance must be BalanceOptions"):
        WalkingController.for_robot(robot, generator, schedule, balance="on")


def test_integral_action_enters_the_desired_zmp_of_the_controller():
    robot = get_robot()
    schedule = schedule_for(robot)
    controller = WalkingController.for_robot(robot, "mpc", schedule, observer_gain=0.0)
    out = controller.reset()
    for _ in range(30):
        out = controller.step(out.generator.state)
    reference = out.generator
    offset = np.array([0.004, -0.002])
    pushed = controller.step(ComState(reference.com + offset, reference.com_velocity))
    integral = DEFAULTS.integral_gain * DT * offset * math.exp(-DT / DEFAULTS.integral_leak_time)
    np.testing.assert_allclose(pushed.zmp_integral, integral, atol=1e-15)
    shift = pushed.zmp_command - pushed.generator.zmp
    np.testing.assert_allclose(shift, KP * offset + integral, atol=1e-12)


def test_open_loop_walks_are_unchanged_by_the_balance_option():
    robot = get_robot()
    schedule = schedule_for(robot)
    outputs = [
        walk_outputs(
            WalkingController.for_robot(robot, "mpc", schedule, feedback=False, balance=b),
            measured=lambda out: out.generator.state,
        )
        for b in (None, True)
    ]
    for a, b in zip(*outputs):
        np.testing.assert_array_equal(a.joint_targets, b.joint_targets)
        np.testing.assert_array_equal(a.com_offset, 0.0)
