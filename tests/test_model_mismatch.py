"""The model mismatch of the simulated robot: trunk mass and CoM, friction, servo strength,
applied to the simulator's model only, validated, serialisable."""

import json

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from mpcwalk.exceptions import ConfigurationError, SimulationModelError
from mpcwalk.sim import ModelMismatch, SensorModel, Simulation, trunk_body

MODEL_ARRAYS = (
    "body_mass",
    "body_inertia",
    "body_ipos",
    "body_subtreemass",
    "geom_friction",
    "actuator_gainprm",
    "actuator_biasprm",
    "actuator_forcerange",
)


def simulation(robot, **mismatch) -> Simulation:
    return Simulation(robot, sensors=SensorModel.ideal(), model_mismatch=ModelMismatch(**mismatch))


def test_trunk_is_the_torso_frame_body():
    for name, trunk in (("bioloid-like", "torso"), ("g1", "torso_link"), ("atlas-like", "torso")):
        robot = get_robot(name)
        body = trunk_body(robot.mj_model, robot.torso_frame)
        assert robot.mj_model.body(body).name == trunk
    robot = get_robot("bioloid-like")
    assert trunk_body(robot.mj_model, "no_such_body") == robot.mj_model.jnt_bodyid[0]  # root


@pytest.mark.parametrize("name", ["bioloid-like", "g1"])
def test_mass_and_com_offset_change_the_simulated_trunk_and_the_whole_body_com(name):
    robot = get_robot(name)
    nominal = simulation(robot)
    sim = simulation(robot, mass_scale=1.3, com_offset=(0.01, -0.01))
    trunk, model = sim.trunk_body, robot.mj_model
    mass, total = model.body_mass[trunk], model.body_mass.sum()
    assert sim.model.body_mass[trunk] == pytest.approx(1.3 * mass)
    np.testing.assert_allclose(sim.model.body_inertia[trunk], 1.3 * model.body_inertia[trunk])
    np.testing.assert_allclose(
        sim.model.body_ipos[trunk] - model.body_ipos[trunk], [0.01, -0.01, 0.0], atol=1e-15
    )
    assert sim.model.body_subtreemass[0] == pytest.approx(total + 0.3 * mass)
    # the simulated CoM: the nominal one, plus 0.3 m_trunk at the trunk's CoM, plus the
    # shifted 1.3 m_trunk (the trunk upright at q0, its frame's x and y the world's)
    shift = nominal.data.xmat[trunk].reshape(3, 3) @ np.array([0.01, -0.01, 0.0])
    expected = (
        total * nominal.state().oracle.com
        + 0.3 * mass * nominal.data.xipos[trunk]
        + 1.3 * mass * shift
    ) / (total + 0.3 * mass)
    np.testing.assert_allclose(sim.state().oracle.com, expected, rtol=0.0, atol=1e-12)  # 1e-16
    np.testing.assert_allclose(nominal.state().oracle.com, robot.compute_com(robot.q0), atol=1e-12)


def test_friction_sets_the_floor_and_soles_and_makes_them_slide():
    robot = get_robot("bioloid-like")
    slides = {}
    for friction in (None, 0.05):
        sim = simulation(robot, friction=friction)
        colliding = (sim.model.geom_contype != 0) | (sim.model.geom_conaffinity != 0)
        if friction is not None:
            np.testing.assert_array_equal(sim.model.geom_friction[colliding, 0], friction)
            np.testing.assert_array_equal(
                sim.model.geom_friction[:, 1:], robot.mj_model.geom_friction[:, 1:]
            )
        velocity = np.zeros(robot.model.nv)
        velocity[1] = 0.3  # [m/s] sideways, the whole robot
        start = sim.reset(robot.q0, v=velocity).sole_positions
        for _ in range(20):
            state = sim.step()
        slides[friction] = np.abs(state.sole_positions - start)[:, :2].max()
    assert slides[None] < 0.01  # [m] measured 4.7e-3: the soles stick, the robot tips
    assert slides[0.05] > 0.03  # [m] measured 4.9e-2: the soles slide


def test_an_elliptic_cone_with_a_stiff_friction_holds_a_sole_mujoco_s_default_lets_creep():
    """MuJoCo's default contacts (pyramidal cone, impratio 1) let a loaded sole creep under a
    tangential force below its friction's bound; the elliptic cone with impratio 10 holds
    it. The robot stands on the floor with gravity tilted 8 deg (tan 8 deg = 0.14, well
    under the friction coefficient): its soles should not move."""
    robot = get_robot("bioloid-like")
    creep = {}
    for cone, impratio in ((None, None), ("elliptic", 10.0)):
        sim = simulation(robot, friction_cone=cone, impratio=impratio)
        if cone is not None:
            assert sim.model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
            assert sim.model.opt.impratio == 10.0
            assert robot.mj_model.opt.cone == mujoco.mjtCone.mjCONE_PYRAMIDAL  # its own
        tilt = np.radians(8.0)
        sim.model.opt.gravity[:] = 9.81 * np.array([np.sin(tilt), 0.0, -np.cos(tilt)])
        start = sim.reset(robot.q0).sole_positions
        for _ in range(100):  # 1 s
            state = sim.step()
        creep[cone] = np.abs(state.sole_positions - start)[:, 0].max()
    assert creep[None] > 2.0 * creep["elliptic"]
    assert creep["elliptic"] < 1e-3  # [m]


def test_servo_strength_scales_gains_and_torque_limits():
    robot = get_robot("g1")
    sim = simulation(robot, servo_strength=0.5)
    model = robot.mj_model
    np.testing.assert_allclose(sim.model.actuator_gainprm[:, 0], 0.5 * model.actuator_gainprm[:, 0])
    np.testing.assert_allclose(
        sim.model.actuator_biasprm[:, 1:3], 0.5 * model.actuator_biasprm[:, 1:3]
    )
    np.testing.assert_allclose(sim.model.actuator_forcerange, 0.5 * model.actuator_forcerange)
    sags = {}
    for strength in (1.0, 0.5):
        sim = simulation(robot, servo_strength=strength)
        for _ in range(100):
            state = sim.step()
        sags[strength] = np.abs(state.q[7:] - robot.q0[7:]).max()
    # weaker servos sag more under the same weight: measured 0.082 rad against 0.032 rad
    assert sags[0.5] > 1.5 * sags[1.0]


def test_servo_strength_scales_the_torque_motors():
    """In torque mode a joint gives that share of the torque it is asked, within limits
    scaled alike; the servos' test above cannot see the motors (no bias)."""
    robot = get_robot("bioloid-like")
    nominal = Simulation(robot, sensors=SensorModel.ideal(), actuation="torque").model
    weak = Simulation(
        robot,
        sensors=SensorModel.ideal(),
        actuation="torque",
        model_mismatch=ModelMismatch(servo_strength=0.7),
    ).model
    assert np.all(nominal.actuator_biastype == 0)  # motors: no position feedback
    np.testing.assert_allclose(weak.actuator_gainprm[:, 0], 0.7 * nominal.actuator_gainprm[:, 0])
    np.testing.assert_allclose(weak.actuator_forcerange, 0.7 * nominal.actuator_forcerange)
    np.testing.assert_allclose(weak.actuator_ctrlrange, nominal.actuator_ctrlrange)


def test_the_robot_the_controller_uses_is_left_alone():
    """The perturbation changes the simulator's copy only: the robot's MuJoCo model, its
    Pinocchio model (masses, inertias, CoM) and its servo gains are untouched."""
    robot = get_robot("g1")
    before = {name: np.array(getattr(robot.mj_model, name)) for name in MODEL_ARRAYS}
    inertias = [pin.Inertia(inertia) for inertia in robot.model.inertias]
    com = robot.compute_com(robot.q0)
    gains = robot.servo_gains.stiffness.copy()
    sim = simulation(
        robot, mass_scale=0.7, com_offset=(0.02, 0.01), friction=0.4, servo_strength=2.0
    )
    for name in MODEL_ARRAYS:
        np.testing.assert_array_equal(getattr(robot.mj_model, name), before[name], err_msg=name)
        assert not np.array_equal(getattr(sim.model, name), before[name]), name
    for inertia, kept in zip(robot.model.inertias, inertias):
        assert inertia.isApprox(kept, 0.0)
    np.testing.assert_array_equal(robot.compute_com(robot.q0), com)
    np.testing.assert_array_equal(robot.servo_gains.stiffness, gains)


def test_no_perturbation_leaves_the_model_as_loaded():
    robot = get_robot("bioloid-like")
    sim = Simulation(robot)
    assert sim.model_mismatch.is_nominal and ModelMismatch().is_nominal
    for name in MODEL_ARRAYS:
        np.testing.assert_array_equal(getattr(sim.model, name), getattr(robot.mj_model, name))


def test_to_dict_is_json_and_round_trips():
    perturbation = ModelMismatch(mass_scale=1.3, com_offset=(0.01, 0), friction=0.4)
    values = perturbation.to_dict()
    assert values == {
        "mass_scale": 1.3,
        "com_offset": [0.01, 0.0],
        "friction": 0.4,
        "servo_strength": 1.0,
        "friction_cone": None,
        "impratio": None,
    }
    assert ModelMismatch.from_dict(json.loads(json.dumps(values))) == perturbation
    assert ModelMismatch().to_dict()["friction"] is None


@pytest.mark.parametrize(
    ("values", "match"),
    [
        ({"mass_scale": 0.0}, r"mass_scale must be a number in \[0.1, 10\], got 0.0"),
        ({"mass_scale": float("nan")}, r"mass_scale must be a number in \[0.1, 10\], got nan"),
        ({"mass_scale": "1.3"}, r"mass_scale must be a number in \[0.1, 10\], got '1.3'"),
        ({"com_offset": (0.01,)}, r"com_offset must be two numbers \(dx, dy\) \[m\]"),
        ({"com_offset": 0.01}, r"com_offset must be two numbers"),
        ({"com_offset": (0.7, 0.0)}, r"each within \+-0.5 m, got \(0.7, 0.0\)"),
        ({"friction": 0.0}, r"friction must be a number in \[0.01, 10\], got 0.0"),
        ({"servo_strength": -1.0}, r"servo_strength must be a number in \[0.1, 10\]"),
        ({"friction_cone": "round"}, r"friction_cone must be one of pyramidal, elliptic"),
        ({"impratio": 0.5}, r"impratio must be a number in \[1, 100\], got 0.5"),
    ],
)
def test_bad_mismatches_raise_a_named_error(values, match):
    with pytest.raises(SimulationModelError, match=match) as error:
        ModelMismatch(**values)
    assert error.value.field == next(iter(values))
    assert isinstance(error.value, ConfigurationError)
    assert "ModelMismatch() is the robot as modelled" in str(error.value)
