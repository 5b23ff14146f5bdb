"""The terrain in the simulated world: the robots' leg lengths, the scene's boxes, a robot
standing on a terrain, and the fall detector measuring heights from the ground under it."""

import pickle

import mujoco
import numpy as np
import pytest
from conftest import get_robot

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot import robot_names
from mpcwalk.robot.ground import Ground
from mpcwalk.robot.terrain_scene import FLOOR, TERRAIN, box_name, terrain_model
from mpcwalk.sim import FallDetector, Simulation
from mpcwalk.terrain import Slope, Stairs, SteppingStones, Terrain

NAMES = robot_names()


@pytest.mark.parametrize("name", NAMES)
def test_every_robot_has_two_hips_and_a_leg_length_below_its_com_height(name):
    robot = get_robot(name)
    left, right = robot.hip_joints
    assert left != right
    model = robot.model
    for hip, sole in zip(robot.hip_joints, robot.foot_frames):
        joint = model.frames[model.getFrameId(sole)].parentJoint
        chain = []
        while joint > 0:
            chain.append(model.names[joint])
            joint = model.parents[joint]
        assert hip in chain  # the hip carries its sole
        assert model.names[model.parents[model.getJointId(hip)]] == chain[-1]  # off the base
    assert 0.6 * robot.com_height < robot.leg_length < 1.0 * robot.com_height


def test_the_small_humanoid_has_a_leg_of_about_two_decimetres():
    assert get_robot("bioloid-like").leg_length == pytest.approx(0.215, abs=0.002)


ISSUE_TERRAIN = Terrain(
    [
        Stairs(0.6, rise=0.15, run=0.30, count=5),
        Stairs(2.4, rise=-0.15, run=0.30, count=5),
        Slope(4.5, length=1.5, angle=10.0),
    ]
)
#: Where the issue's terrain holds its landing 0.75 m up: between the flights.
LANDING_X, LANDING_Z = 2.1, 0.75


def ground_below(model: mujoco.MjModel, x: float, y: float) -> tuple[float, str]:
    """Height of the first visible geom (not the dormant height field) a ray cast down from
    3 m above ``(x, y)`` hits, and its name."""
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    geom = np.array([-1], dtype=np.int32)
    start, down = np.array([x, y, 3.0]), np.array([0.0, 0.0, -1.0])
    visible = np.array([1, 1, 1, 0, 0, 0], dtype=np.uint8)
    distance = mujoco.mj_ray(model, data, start, down, visible, 1, -1, geom)
    return 3.0 - distance, mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, int(geom[0]))


def test_the_scene_holds_the_terrains_blocks_where_the_terrain_says():
    robot = get_robot("bioloid-like")
    model = Simulation(robot, terrain=ISSUE_TERRAIN).model
    for x in (0.3, 0.75, 1.05, 1.65, LANDING_X, 2.55, 3.9, 4.4, 5.0, 5.25, 5.9, 6.5):
        for y in (0.0, 0.4, -1.2):
            height, geom = ground_below(model, x, y)
            assert height == pytest.approx(ISSUE_TERRAIN.height(x, y), abs=1e-9), (x, y, geom)
            assert geom.startswith(TERRAIN) or ISSUE_TERRAIN.height(x, y) == 0.0
    assert model.ngeom == robot.mj_model.ngeom + len(ISSUE_TERRAIN.boxes())
    box = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, box_name(0))
    floor = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, FLOOR)
    for setting in ("geom_friction", "geom_contype", "geom_conaffinity", "geom_condim"):
        np.testing.assert_array_equal(getattr(model, setting)[box], getattr(model, setting)[floor])


def test_a_pit_takes_the_floor_down_to_its_bottom():
    terrain = Terrain([SteppingStones(0.5, count=2, length=0.2, gap=0.1, width=0.4, depth=0.2)])
    model = terrain_model(get_robot("bioloid-like"), terrain)
    assert terrain.floor == pytest.approx(-0.2)
    assert ground_below(model, 0.75, 0.0)[0] == pytest.approx(-0.2)  # between the stones
    assert ground_below(model, 0.6, 0.0)[0] == pytest.approx(0.0)  # on a stone
    assert ground_below(model, 0.75, 2.0)[0] == pytest.approx(-0.2)  # off the terrain: floor
    assert ground_below(model, -0.5, 0.0)[0] == pytest.approx(0.0)  # behind the start


def test_a_walk_on_the_floor_simulates_the_robots_own_model():
    robot = get_robot("bioloid-like")
    sizes = ("nbody", "ngeom", "nq", "nu", "nsensor")
    before = {name: getattr(robot.mj_model, name) for name in sizes}
    assert terrain_model(robot, None) is robot.mj_model
    assert terrain_model(robot, Terrain()) is robot.mj_model
    for terrain in (None, Terrain(), ISSUE_TERRAIN):  # a terrain leaves the robot's model
        Simulation(robot, terrain=terrain)
        assert {name: getattr(robot.mj_model, name) for name in sizes} == before
    flat = Simulation(robot).model
    assert {name: getattr(flat, name) for name in sizes} == before
    assert terrain_model(robot, ISSUE_TERRAIN) is terrain_model(robot, ISSUE_TERRAIN)  # cached


def test_a_robot_from_another_process_gets_its_scene_built_again():
    robot = pickle.loads(pickle.dumps(get_robot("bioloid-like")))
    model = terrain_model(robot, ISSUE_TERRAIN)
    assert model.nbody == robot.mj_model.nbody
    assert ground_below(model, 0.75, 0.0)[0] == pytest.approx(0.15)


def on_the_landing(robot, height: float | None = None) -> np.ndarray:
    """``q0`` moved onto the issue terrain's landing (base ``height`` [m] above it: None,
    the nominal one)."""
    q = robot.q0.copy()
    q[0] += LANDING_X
    q[2] = LANDING_Z + (robot.q0[2] if height is None else height)
    return q


@pytest.mark.parametrize("where", ["start", "landing"])
def test_a_robot_holding_its_posture_stands_on_the_terrains_level_parts(where):
    robot = get_robot("bioloid-like")
    sim = Simulation(robot, terrain=ISSUE_TERRAIN)
    q = robot.q0 if where == "start" else on_the_landing(robot)
    detector = FallDetector.for_robot(robot, terrain=ISSUE_TERRAIN)
    state = sim.reset(q, settle=0.3)
    for _ in range(150):  # 1.5 s
        state = sim.step(q)
        assert not detector.check(state).fell
    truth = state.oracle
    assert truth.left_foot.in_contact and truth.right_foot.in_contact
    assert truth.total_force[2] == pytest.approx(robot.total_mass * 9.81, rel=0.02)
    ground = 0.0 if where == "start" else LANDING_Z
    np.testing.assert_allclose(state.sole_positions[:, 2], ground, atol=2e-3)
    assert state.base_position[2] == pytest.approx(ground + robot.q0[2], abs=5e-3)


def test_the_fall_detector_measures_the_base_from_the_ground_under_the_robot():
    robot = get_robot("bioloid-like")
    sim = Simulation(robot, terrain=ISSUE_TERRAIN)
    on_terrain = FallDetector.for_robot(robot, terrain=ISSUE_TERRAIN)
    on_floor = FallDetector.for_robot(robot)
    assert not on_terrain.check(sim.reset(on_the_landing(robot)))
    low = sim.reset(on_the_landing(robot, 0.3 * robot.q0[2]))  # sunk: lying on the landing
    assert not on_floor.check(low)  # 0.75 m above z = 0: the floor's detector misses it
    status = on_terrain.check(low)
    assert status.fell and "above the ground at 0.750 m" in status.reason


def test_a_terrain_and_a_rough_ground_are_refused_together():
    with pytest.raises(ConfigurationError, match="RoughPatch"):
        Simulation(get_robot("bioloid-like"), terrain=ISSUE_TERRAIN, ground=Ground(roughness=0.01))
