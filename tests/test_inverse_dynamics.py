"""The whole-body inverse-dynamics QP: equations of motion, contact forces, limits, CoP, ramp."""

import itertools

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.contact_wrench import CONE_ROWS, wrench_cone
from mpcwalk.ik.dynamics_targets import DynamicsTargets
from mpcwalk.ik.inverse_dynamics import InverseDynamicsQP, torque_limits


def _targets(robot, q, **changes) -> DynamicsTargets:
    """Targets that ``q`` reaches at rest (both soles loaded), with ``changes``."""
    left, right = robot.compute_sole_placements(q)
    torso = robot.compute_frame_placement(q, robot.torso_frame)
    fields = dict(
        com=robot.compute_com(q),
        com_velocity=np.zeros(3),
        com_acceleration=np.zeros(3),
        left_sole=left,
        right_sole=right,
        torso_rotation=torso.rotation,
        posture=q,
    )
    fields.update(changes)
    return DynamicsTargets(**fields)


def _random_state(robot, seed):
    rng = np.random.default_rng(seed)
    model = robot.model
    q = robot.q0.copy()
    q[7:] += rng.uniform(-0.2, 0.2, model.nq - 7)
    q[7:] = np.clip(q[7:], model.lowerPositionLimit[7:], model.upperPositionLimit[7:])
    q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(rng.uniform(-0.1, 0.1, 3))).coeffs()
    v = rng.normal(0.0, 0.3, model.nv)
    return q, v, rng


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_solution_satisfies_the_equations_of_motion(seed):
    robot = get_robot("bioloid-like")
    q, v, rng = _random_state(robot, seed)
    solver = InverseDynamicsQP(robot, solver="daqp", torque_limit=np.inf)
    targets = _targets(robot, robot.q0, com_acceleration=rng.uniform(-0.3, 0.3, 3))
    result = solver.solve(q, v, targets)
    assert result.success
    model, data = robot.model, robot.model.createData()
    generalized = pin.rnea(model, data, q, v, result.acceleration)
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    for i, frame in enumerate(robot.foot_frames):
        J = pin.getFrameJacobian(model, data, robot.frame_id(frame), pin.ReferenceFrame.LOCAL)
        generalized -= J.T @ result.wrenches[i]
    assert np.abs(generalized[:6]).max() < 1e-8  # the floating base: no actuator
    assert np.abs(generalized[6:] - result.torques).max() < 1e-8  # S^T tau
    assert result.dynamics_residual < 1e-8
    # the soles in contact do not accelerate away: J a + J_dot v = -k J v
    pin.forwardKinematics(model, data, q, v, result.acceleration)
    pin.updateFramePlacements(model, data)
    for frame in robot.foot_frames:
        frame_id = robot.frame_id(frame)
        J = pin.getFrameJacobian(model, data, frame_id, pin.ReferenceFrame.LOCAL)
        acceleration = pin.getFrameClassicalAcceleration(
            model, data, frame_id, pin.ReferenceFrame.LOCAL
        ).vector
        assert np.allclose(acceleration, -solver.gains.contact * (J @ v), atol=1e-7)


@pytest.mark.parametrize("name", ["bioloid-like", "g1"])
def test_standing_forces_carry_the_weight_and_torques_match_rnea(name):
    robot = get_robot(name)
    q, v = robot.q0, np.zeros(robot.model.nv)
    solver = InverseDynamicsQP(robot, solver="daqp")
    result = solver.solve(q, v, _targets(robot, q))
    assert result.success and result.contacts == (True, True)
    model, data = robot.model, robot.model.createData()
    weight = pin.computeTotalMass(model) * 9.81
    rotations = [p.rotation for p in robot.compute_sole_placements(q)]
    world_forces = sum(R @ w[:3] for R, w in zip(rotations, result.wrenches))
    assert np.allclose(world_forces, [0.0, 0.0, weight], rtol=0.0, atol=1e-6 * weight)
    # the same torques from the recursive Newton-Euler algorithm with those external forces
    pin.framesForwardKinematics(model, data, q)
    external = pin.StdVec_Force()
    for _ in range(model.njoints):
        external.append(pin.Force.Zero())
    for frame, wrench in zip(robot.foot_frames, result.wrenches):
        frame_ = model.frames[robot.frame_id(frame)]
        external[frame_.parentJoint] += frame_.placement.act(pin.Force(wrench))
    generalized = pin.rnea(model, data, q, v, result.acceleration, external)
    assert np.abs(generalized[:6]).max() < 1e-6 * weight
    assert np.allclose(generalized[6:], result.torques, atol=1e-8)
    assert np.abs(result.acceleration).max() < 1e-6  # standing still


def test_torques_stay_within_their_limits():
    robot = get_robot("bioloid-like")
    q, v = robot.q0, np.zeros(robot.model.nv)
    free = InverseDynamicsQP(robot, solver="daqp", torque_limit=np.inf)
    demanding = _targets(robot, q, com_acceleration=np.array([0.0, 0.0, 6.0]))  # jump
    unlimited = free.solve(q, v, demanding).torques
    limit = 0.5 * np.abs(unlimited).max()
    limited = InverseDynamicsQP(robot, solver="daqp", torque_limit=limit)
    result = limited.solve(q, v, demanding)
    assert result.success
    assert np.abs(result.torques).max() <= limit + 1e-9
    assert np.abs(result.torques).max() > limit - 1e-6  # a limit is active
    assert result.dynamics_residual < 1e-8
    assert np.all(torque_limits(robot) == robot.servo_gains.torque_limit)


def test_cop_stays_in_the_sole():
    robot = get_robot("bioloid-like")
    q, v = robot.q0, np.zeros(robot.model.nv)
    solver = InverseDynamicsQP(robot, solver="daqp", cop_margin=0.8)
    length, width = robot.sole_size
    for acceleration in ([8.0, 0.0, 0.0], [0.0, 8.0, 0.0], [-8.0, -8.0, 0.0]):
        targets = _targets(robot, q, com_acceleration=np.array(acceleration))
        result = solver.solve(q, v, targets)
        assert result.success
        cops = result.cops[result.normal_forces > 1e-6 * solver.weight]  # loaded soles
        assert len(cops) > 0
        assert np.all(np.abs(cops[:, 0]) <= 0.4 * length + 1e-9)
        assert np.all(np.abs(cops[:, 1]) <= 0.4 * width + 1e-9)
        bound = np.abs(cops) / (0.4 * np.array([length, width]))
        assert bound.max() > 1.0 - 1e-6  # the CoP is at the edge: the cone is active
        friction = np.abs(result.wrenches[:, :2]).max(axis=1)
        assert np.all(friction <= 0.7 / np.sqrt(2.0) * result.wrenches[:, 2] + 1e-9)


def test_force_ramp_keeps_the_torques_continuous_at_lift_off():
    robot = get_robot("bioloid-like")
    q, v = robot.q0, np.zeros(robot.model.nv)
    solver = InverseDynamicsQP(robot, solver="daqp")
    weight = solver.weight
    capped = solver.solve(q, v, _targets(robot, q, contact_weights=(1.0, 0.05)))
    assert capped.wrenches[1, 2] <= 0.05 * solver.max_normal_force + 1e-9
    assert capped.wrenches[1, 2] < 0.4 * weight  # the cap is below the even share
    assert abs(capped.normal_forces.sum() - weight) < 1e-2 * weight  # the CoM sways a little

    def largest_jump(loads):
        torques = [
            solver.solve(q, v, _targets(robot, q, contact_weights=(1.0, w))).torques for w in loads
        ]
        return max(np.abs(b - a).max() for a, b in itertools.pairwise(torques))

    abrupt = largest_jump([1.0, 0.0])
    ramped = largest_jump([1.0, 0.8, 0.6, 0.4, 0.2, 0.1, 0.05, 0.0])
    assert ramped < 0.5 * abrupt


@pytest.mark.parametrize("name", ["proxqp", "quadprog", "osqp-direct", "piqp", "daqp-direct"])
def test_backends_of_the_registry_agree(name):
    robot = get_robot("bioloid-like")
    q, v, _ = _random_state(robot, 3)
    targets = _targets(robot, robot.q0, contact_weights=(1.0, 0.0))
    reference = InverseDynamicsQP(robot, solver="daqp").solve(q, v, targets)
    result = InverseDynamicsQP(robot, solver=name).solve(q, v, targets)
    assert result.success and result.contacts == (True, False)
    assert np.allclose(
        result.torques, reference.torques, atol=2e-3 * robot.servo_gains.torque_limit
    )


def test_backends_that_cannot_take_the_qp_are_refused():
    robot = get_robot("bioloid-like")
    with pytest.raises(ConfigurationError, match="inequality"):
        InverseDynamicsQP(robot, solver="kkt")
    assert InverseDynamicsQP(robot).solver_name == "daqp-direct"  # takes the equalities
    with pytest.raises(ConfigurationError, match="contact_weights"):
        _targets(robot, robot.q0, contact_weights=(1.5, 0.0))


def test_wrench_cone_rows():
    C = wrench_cone((0.2, 0.1), 1.0, cop_margin=1.0)
    assert C.shape == (CONE_ROWS, 6)
    inside = np.array([0.1, -0.1, 10.0, 0.4, -0.9, 0.1])  # CoP (0.09, 0.04) in the sole
    outside = np.array([0.0, 0.0, 10.0, 0.0, -1.1, 0.0])  # CoP x = 0.11 > 0.1
    d = np.zeros(CONE_ROWS)
    d[1] = 20.0
    assert np.all(C @ inside <= d)
    assert np.any(C @ outside > d)
    with pytest.raises(ConfigurationError, match="friction"):
        wrench_cone((0.2, 0.1), 0.0)


def _swept_margin(omega, beta, delay):
    """Phase margin [deg] of (2 omega s + omega^2) e^(-s delay) / (s (s + beta)), by a sweep."""
    w = np.logspace(-1, 3, 400001)
    s = 1j * w
    loop = (2.0 * omega * s + omega**2) * np.exp(-s * delay) / (s * (s + beta))
    crossover = np.argmax(np.abs(loop) < 1.0)
    return 180.0 + np.degrees(np.unwrap(np.angle(loop))[crossover])


def test_posture_frequency_keeps_a_60_degree_margin_on_a_late_state():
    from mpcwalk.ik.delay_margin import delay_limited_frequency

    delay = 0.0306  # 10 ms latency, 10 ms period, the 15 Hz low-pass's 10.6 ms
    rates = np.array([0.0, 0.87, 16.0, 40.0])  # g1, atlas-like, bioloid-like's servos (1/s)
    omega = delay_limited_frequency(15.0, rates, delay)
    assert omega[0] == pytest.approx(4.53, abs=0.01)  # no damping: 0.139 / delay
    assert omega[2] == pytest.approx(14.73, abs=0.01)  # a damped servo keeps nearly 15
    assert omega[3] == 15.0  # the bound
    for w, beta in zip(omega[:3], rates[:3]):
        assert _swept_margin(w, beta, delay) == pytest.approx(60.0, abs=0.05)
    assert _swept_margin(15.0, 0.0, delay) < 25.0  # the default on a late state: 22 deg
    assert np.all(delay_limited_frequency(15.0, np.zeros(2), 0.001) == 15.0)
    with pytest.raises(ConfigurationError, match="delay"):
        delay_limited_frequency(15.0, rates, 0.0)


def test_inverse_dynamics_caps_the_posture_of_a_late_state():
    g1 = get_robot("g1")
    assert np.all(InverseDynamicsQP(g1).posture_frequencies == 15.0)
    late = InverseDynamicsQP(g1, state_delay=0.0306).posture_frequencies
    assert np.allclose(late, 4.53, atol=0.01)  # g1's joints have no damping
    # the small humanoid's servos are damped (b / M_jj from 3.7 /s): its least damped joint
    # sets one frequency for all
    servo = InverseDynamicsQP(get_robot("bioloid-like"), state_delay=0.0306)
    assert np.allclose(servo.posture_frequencies, 8.18, atol=0.01)


def _delayed_pd_response(omega, delay, *, dt=1e-4, duration=2.0):
    """Largest |error| [m] over the last second of a double integrator closed by the PD of
    natural frequency ``omega`` [rad/s] on its state ``delay`` [s] old, from a 1 m error."""
    lag = round(delay / dt)
    x, v = np.zeros(round(duration / dt) + lag), np.zeros(round(duration / dt) + lag)
    x[: lag + 1] = 1.0
    for k in range(lag, len(x) - 1):
        a = -(omega**2) * x[k - lag] - 2.0 * omega * v[k - lag]
        v[k + 1] = v[k] + a * dt
        x[k + 1] = x[k] + v[k + 1] * dt
    return float(np.abs(x[-round(1.0 / dt) :]).max())


def test_swing_and_torso_frequencies_keep_a_margin_on_a_late_state():
    from mpcwalk.ik.delay_margin import TASK_MARGIN

    delay = 0.0306  # the estimator's state (talos mpc-steps and atlas-like mpc-steps fell)
    talos = get_robot("talos")
    late = InverseDynamicsQP(talos, state_delay=delay)
    assert late.swing_frequency == pytest.approx(17.0, abs=0.01)  # from 25 rad/s
    assert late.torso_frequency == 15.0  # 22 deg of margin already
    assert _swept_margin(late.swing_frequency, 0.0, delay) == pytest.approx(
        np.degrees(TASK_MARGIN), abs=0.05
    )
    assert _swept_margin(25.0, 0.0, delay) < 0.0  # the swing's default: -14 deg
    # the default rings up (the swing foot shook the stance foot loose), the capped one settles
    assert _delayed_pd_response(25.0, delay) > 1.0  # measured 2.6e3 m (from 1 m)
    assert _delayed_pd_response(late.swing_frequency, delay) < 1e-2  # measured 7.2e-4 m
    exact = InverseDynamicsQP(talos, state_delay=0.01)  # the simulator's exact state
    assert (exact.swing_frequency, exact.torso_frequency) == (25.0, 15.0)
    default = InverseDynamicsQP(talos)
    assert (default.swing_frequency, default.torso_frequency) == (25.0, 15.0)
