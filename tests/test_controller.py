"""WalkingController on a kinematic robot (no MuJoCo): tracking, feedback, failures, errors."""

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot, walk_outputs
from stabilizer_inputs import estimated_state

from mpcwalk.control.controller import ControlOutput, WalkingController
from mpcwalk.control.dcm_feedback import DcmFeedback, project_into_polygon, shrink_polygon
from mpcwalk.control.servo_feedforward import ServoFeedforward
from mpcwalk.control.stabilizers.base import Stabilizer, StabilizerInput
from mpcwalk.exceptions import ConfigurationError, NoSolutionFound, NotReset
from mpcwalk.footsteps import FootGeometry, Side, StepTiming
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators import ComState, GeneratorOutput, SolveInfo, make_generator
from mpcwalk.generators.pattern_generator import PatternGenerator
from mpcwalk.ik import IKTargets, WholeBodyIK
from mpcwalk.models.lipm import LIPM
from mpcwalk.models.support_polygon import SupportPolygon
from mpcwalk.walking.footstep_planning import plan_walk_footsteps


def make_schedule(robot, command=(0.1, 0.0, 0.0), nb_steps=4, step_duration=0.5):
    timing = StepTiming(step_duration=step_duration, initial_duration=0.5, final_duration=0.5)
    plan = plan_walk_footsteps(robot, command=command, nb_steps=nb_steps, timing=timing)
    return ContactSchedule(plan, FootGeometry(*robot.sole_size))


def walk_kinematically(controller, measurement=None):
    return walk_outputs(controller, measured=None if measurement is None else lambda _: measurement)


@pytest.mark.parametrize("generator", ["analytic", "mpc"])
def test_feet_land_on_the_footsteps_and_com_follows_the_generator(generator):
    robot = get_robot()
    schedule = make_schedule(robot, command=(0.1, 0.0, 0.3))
    controller = WalkingController.for_robot(robot, generator, schedule)
    outputs = walk_kinematically(controller)
    assert outputs[-1].time == pytest.approx(schedule.duration)
    stance_errors, swing_errors, com_errors = [], [], []
    for out in outputs[1:]:
        soles = robot.compute_sole_placements(out.q_ref)
        for foot, sole in zip((out.feet.left, out.feet.right), soles):
            error = np.linalg.norm(sole.translation - foot.position)
            (stance_errors if foot.in_contact else swing_errors).append(error)
            yaw = np.arctan2(sole.rotation[1, 0], sole.rotation[0, 0])
            assert abs(np.sin(yaw - foot.yaw)) < 5e-3
        com = robot.compute_com(out.q_ref)
        com_errors.append(np.linalg.norm(com - out.com_target))
        np.testing.assert_allclose(out.com_target[:2], out.generator.com, atol=1e-12)
        assert out.com_target[2] == pytest.approx(robot.com_height)
    # Feet on the ground stay on their footsteps to IK precision; the swing foot may lag by a
    # few millimetres where a joint reaches its 6 rad/s velocity limit (servo speed), and
    # catches up within a few ticks of touchdown.
    assert np.median(stance_errors) < 5e-5 and max(stance_errors) < 1e-3
    assert max(swing_errors) < 5e-3
    plan, period = schedule.plan, schedule.step_duration
    for k, step in enumerate(plan.steps):  # end of each step: the landed foot is on its footstep
        out = min(outputs, key=lambda o: abs(o.time - (schedule.walk_start + (k + 1) * period)))
        sole = robot.compute_sole_placements(out.q_ref)[0 if step.side is Side.LEFT else 1]
        np.testing.assert_allclose(sole.translation, step.position, atol=5e-5)
    assert np.median(com_errors) < 1e-4 and max(com_errors) < 5e-3
    final = robot.compute_sole_placements(outputs[-1].q_ref)
    last = schedule.plan.stance(schedule.plan.nb_steps)
    for side, sole in zip((Side.LEFT, Side.RIGHT), final):
        np.testing.assert_allclose(sole.translation, last[side].position, atol=1e-5)
    assert controller.nb_generator_failures == 0


def test_open_loop_joint_targets_hold_the_reference_with_the_servo_feedforward():
    robot = get_robot()
    schedule = make_schedule(robot, nb_steps=2)
    plain = WalkingController.for_robot(robot, "analytic", schedule, servo_feedforward=False)
    compensated = WalkingController.for_robot(robot, "analytic", schedule)
    for a, b in zip(walk_kinematically(plain), walk_kinematically(compensated)):
        np.testing.assert_allclose(a.joint_targets, a.q_ref[7:], atol=0.0)
        np.testing.assert_allclose(a.q_ref, b.q_ref, atol=1e-12)
        offsets = b.joint_targets - b.q_ref[7:]
        limits = compensated.feedforward.torque_limit / compensated.feedforward.stiffness
        assert np.all(np.abs(offsets) <= limits + 1e-12)
    knee = robot.joint_names.index("left_knee")
    # the knees carry the robot: tenths of a N m (0.25 N m measured), whatever the stiffness
    assert abs(offsets[knee]) * compensated.feedforward.stiffness[knee] > 0.1  # [N m]


def test_feedforward_wrench_puts_the_cop_at_the_lipm_zmp():
    robot = get_robot()
    feedforward = ServoFeedforward(robot)
    left, right = robot.compute_sole_placements(robot.q0)
    com = robot.compute_com(robot.q0)
    com[:2] = left.translation[:2] + [0.01, -0.005]
    lifted = right.copy()
    lifted.translation[2] += 0.02
    q = WholeBodyIK(robot).solve_pose(robot.q0, IKTargets(com, left, lifted, np.eye(3))).q_next
    sole = robot.compute_sole_placements(q)[0]
    c = robot.compute_com(q)
    gravity = -robot.model.gravity.linear[2]
    for acceleration in ([0.0, 0.0], [0.5, -0.3]):
        a = np.zeros(robot.model.nv)
        rotation = pin.Quaternion(q[3:7]).normalized().matrix()
        a[:3] = rotation.T @ np.array([*acceleration, 0.0])
        _, wrenches = feedforward.compute_torques_and_wrenches(q, (1.0, 0.0), None, a)
        force, moment = wrenches[0, :3], wrenches[0, 3:]
        assert force[2] == pytest.approx(robot.total_mass * gravity, rel=1e-9)
        cop = sole.act(np.array([-moment[1] / force[2], moment[0] / force[2], 0.0]))
        expected = c[:2] - c[2] / gravity * np.array(acceleration)
        np.testing.assert_allclose(cop[:2], expected, atol=1e-9)
        np.testing.assert_allclose(wrenches[1], 0.0, atol=0.0)


def test_a_measurement_on_the_reference_changes_nothing_and_an_offset_shifts_the_zmp():
    robot = get_robot()
    schedule = make_schedule(robot, nb_steps=2)
    open_loop = WalkingController.for_robot(robot, "mpc", schedule)
    closed = WalkingController.for_robot(
        robot, "mpc", schedule, observer_gain=0.5, dcm_gain=3.0, balance=False
    )  # the proportional DCM feedback alone
    open_loop.reset()
    out = closed.reset()
    for _ in range(30):  # standing: the measurement sits exactly on the reference
        expected = open_loop.step()
        out = closed.step(out.generator.state)
        np.testing.assert_allclose(out.q_ref, expected.q_ref, atol=1e-9)
        np.testing.assert_allclose(out.dcm_error, 0.0, atol=1e-12)
    reference = out.generator
    offset = np.array([0.004, -0.002])
    measured = ComState(reference.com + offset, reference.com_velocity)
    pushed = closed.step(measured)
    np.testing.assert_allclose(pushed.dcm_error, offset, atol=1e-12)
    np.testing.assert_allclose(pushed.zmp_command - pushed.generator.zmp, 3.0 * offset, atol=1e-9)
    # a DCM error beyond the feet saturates the desired ZMP inside the support polygon
    far = closed.step(ComState(pushed.generator.com + [0.5, 0.0], pushed.generator.com_velocity))
    polygon = schedule.support_polygon(far.time)
    margin = closed.dcm_feedback.zmp_margin
    assert polygon.signed_distance(far.zmp_command[None])[0] == pytest.approx(margin)


def test_observer_gain_sets_what_the_generator_receives():
    robot = get_robot()
    schedule = make_schedule(robot, nb_steps=2)

    class Spy(PatternGenerator):
        name = "spy"

        def _reset(self, schedule, initial_state):
            self.received = []
            self.state = initial_state.as_cart_table()
            return self._output(0.0, self.state)

        def _step(self, measured):
            self.received.append(measured)
            return self._output(self.time + self.control_period, self.state)

    spy = Spy(lipm=LIPM(com_height=robot.com_height))
    controller = WalkingController(robot, spy, schedule, observer_gain=0.25)
    out = controller.reset()
    controller.step(ComState(out.generator.com + [0.04, 0.0], [0.2, 0.0]))
    received = spy.received[-1]
    np.testing.assert_allclose(received.position, out.generator.com + [0.01, 0.0])
    np.testing.assert_allclose(received.velocity, [0.05, 0.0])
    controller.step(None)  # no measurement: the generator runs on its own state
    assert spy.received[-1] is None
    no_feedback = WalkingController(robot, spy, schedule, feedback=False)
    no_feedback.reset()
    no_feedback.step(ComState([1.0, 1.0]))
    assert spy.received[-1] is None


class FailingGenerator(PatternGenerator):
    """Reports failed solves on some ticks and raises NoSolutionFound on others."""

    name = "failing"

    def __init__(self, raise_every=7, fail_every=3, **kwargs):
        super().__init__(**kwargs)
        self.inner = make_generator("mpc", **kwargs)
        self.raise_every, self.fail_every = raise_every, fail_every

    def _reset(self, schedule, initial_state):
        return self.inner.reset(schedule, initial_state)

    def _step(self, measured):
        if self.tick % self.raise_every == self.raise_every - 1:
            self.inner.tick += 1
            raise NoSolutionFound("fake", "infeasible")
        out = self.inner.step(measured)
        if self.tick % self.fail_every == 0:
            solve = SolveInfo(False, "fake", "failed", fallback=True, consecutive_failures=1)
            return GeneratorOutput(
                out.time,
                out.com,
                out.com_velocity,
                out.com_acceleration,
                out.zmp,
                out.com_height,
                out.horizon,
                solve,
            )
        return out


def test_generator_failures_do_not_stop_the_walk_and_are_counted():
    robot = get_robot()
    schedule = make_schedule(robot, nb_steps=2)
    generator = FailingGenerator(lipm=LIPM(com_height=robot.com_height))
    controller = WalkingController(robot, generator, schedule)
    outputs = walk_kinematically(controller)
    failed = [out.generator_failed for out in outputs[1:]]
    raised = sum(1 for k in range(len(failed)) if k % 7 == 6)
    reported = sum(1 for k in range(len(failed)) if k % 7 != 6 and k % 3 == 0)
    assert controller.nb_generator_failures == sum(failed) == raised + reported
    times = [out.time for out in outputs]
    np.testing.assert_allclose(np.diff(times), 0.01, atol=1e-9)
    assert all(np.all(np.isfinite(out.joint_targets)) for out in outputs)
    steps = np.diff([out.generator.com for out in outputs], axis=0)
    assert np.abs(steps).max() < 0.005  # [m] per tick: no jump at a fallback


def test_bad_inputs_raise_named_errors():
    robot = get_robot()
    schedule = make_schedule(robot, nb_steps=1)
    wrong_height = make_generator("analytic", lipm=LIPM(com_height=0.5))
    with pytest.raises(ConfigurationError, match="CoM height of 0.5 m.*0.23 m"):
        WalkingController(robot, wrong_height, schedule)
    slow = make_generator("analytic", lipm=LIPM(com_height=robot.com_height), control_period=0.02)
    with pytest.raises(ConfigurationError, match="control_period=0.01"):
        WalkingController(robot, slow, schedule)
    good = make_generator("analytic", lipm=LIPM(com_height=robot.com_height))
    with pytest.raises(ConfigurationError, match="ContactSchedule"):
        WalkingController(robot, good, schedule.plan)
    with pytest.raises(ConfigurationError, match="observer_gain"):
        WalkingController(robot, good, schedule, observer_gain=1.5)
    controller = WalkingController(robot, good, schedule)
    with pytest.raises(NotReset):
        controller.step()
    with pytest.raises(ConfigurationError, match="size nq"):
        controller.reset(np.zeros(3))
    controller.reset()
    with pytest.raises(ConfigurationError, match=r"steps on an EstimatedState \(the estimator's"):
        controller.step(state=[0.0, 0.0])


def test_measured_com_is_anchored_to_the_planned_feet():
    robot = get_robot()
    schedule = make_schedule(robot, nb_steps=2)
    feedback = DcmFeedback(schedule, omega=7.0)
    left, right = schedule.plan.initial_left, schedule.plan.initial_right

    def measured_soles(shift, turn):
        c, s = np.cos(turn), np.sin(turn)
        rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        positions = np.array([rotation @ left.position + shift, rotation @ right.position + shift])
        return positions, np.array([turn, turn])

    planned_com = np.array([0.01, 0.003])
    for shift, turn in (([0.02, -0.01, 0.0], 0.0), ([0.0, 0.0, 0.0], 0.1)):
        positions, yaws = measured_soles(np.array(shift), turn)
        c, s = np.cos(turn), np.sin(turn)
        measured = ComState(
            np.array([[c, -s], [s, c]]) @ planned_com + shift[:2],
            np.array([[c, -s], [s, c]]) @ [0.1, 0.0],
        )
        anchored = feedback.anchor(measured, positions, yaws, 0.2, (0.5, 0.5))
        np.testing.assert_allclose(anchored.position, planned_com, atol=1e-12)
        np.testing.assert_allclose(anchored.velocity, [0.1, 0.0], atol=1e-12)


def test_stabilizer_sees_a_typed_input_with_the_references_of_the_measurement_time():
    robot = get_robot()
    seen = []

    class Spy(Stabilizer):
        def reset(self, inputs):
            seen.append(("reset", inputs))

        def adjust_targets(self, inputs):
            seen.append(("targets", inputs))
            return inputs.targets

        def adjust_joint_targets(self, inputs, joint_targets):
            seen.append(("joints", inputs))
            return joint_targets

    controller = WalkingController.for_robot(
        robot, "analytic", make_schedule(robot, nb_steps=1), stabilizer=Spy()
    )
    first = controller.reset()
    kind, inputs = seen[0]
    assert kind == "reset" and inputs.state is None and inputs.time == first.time
    state = estimated_state(com=robot.compute_com(robot.q0), q=robot.q0)
    second = controller.step(state)
    (_, before), (_, after) = seen[1:]
    assert isinstance(before, StabilizerInput) and before.state is state
    assert before.time == after.time == second.time
    np.testing.assert_array_equal(before.q_ref, first.q_ref)  # the IK's starting point
    np.testing.assert_array_equal(after.q_ref, second.q_ref)  # this tick's reference
    np.testing.assert_array_equal(after.com_reference, first.com_target)
    np.testing.assert_array_equal(after.zmp_reference, first.zmp_command)
    np.testing.assert_array_equal(after.targets.com_xy, second.com_target[:2])


def test_project_into_polygon():
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    np.testing.assert_allclose(project_into_polygon(square, [0.3, 0.6]), [0.3, 0.6])
    np.testing.assert_allclose(project_into_polygon(square, [2.0, 0.5]), [1.0, 0.5])
    np.testing.assert_allclose(project_into_polygon(square, [-1.0, -2.0]), [0.0, 0.0])
    np.testing.assert_allclose(
        shrink_polygon(square, 0.1), [[0.1, 0.1], [0.9, 0.1], [0.9, 0.9], [0.1, 0.9]], atol=1e-15
    )
    triangle = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    inner = shrink_polygon(triangle, 0.05)
    polygon = SupportPolygon.from_vertices(triangle)
    np.testing.assert_allclose(polygon.signed_distance(inner), 0.05, atol=1e-12)


def test_control_output_is_frozen():
    robot = get_robot()
    controller = WalkingController.for_robot(robot, "analytic", make_schedule(robot, nb_steps=1))
    out = controller.reset()
    assert isinstance(out, ControlOutput)
    with pytest.raises(AttributeError):
        out.time = 1.0


def test_generators_take_their_robot_options_from_the_preset():
    from mpcwalk.footsteps import LegLimits
    from mpcwalk.generators import generator_class

    g1 = get_robot("g1")  # [gait] mpc_sampling_period 0.05, mpc_horizon 40
    mpc = generator_class("mpc").robot_options(g1)
    assert mpc == {"sampling_period": 0.05, "horizon": 40}
    steps = generator_class("mpc-steps").robot_options(g1)
    assert steps["horizon"] == 40 and "jerk_weight" not in steps
    assert isinstance(steps["reachability"], LegLimits) and steps["reachability"] == g1.leg_limits
    assert generator_class("static-qp").robot_options(g1) == {}
    assert generator_class("analytic").robot_options(g1) == {"lateral_cop_reach": 0.035}
    schedule = make_schedule(g1, nb_steps=1)
    controller = WalkingController.for_robot(g1, "mpc", schedule, generator_options={"horizon": 20})
    assert controller.generator.parameters.horizon == 20  # the caller's option wins
    assert controller.generator.parameters.sampling_period == 0.05  # the preset's
