"""The walking loop reproduces walks recorded before its speed work (issue 28), and its
shortcuts give what the general paths give.

The reference values were printed by the loop before the per-tick changes (commit 769b7ca:
stability check, joint targets to ``ctrl``, clip/outer as ufuncs, phase lookup, ZMP
reference, ground truth's roll-pitch-yaw and DCM, contact wrenches without gathers); a
change of the order of floating-point operations would move them beyond the tolerance (1e-9
of the sums below, over 450 ticks).
"""

import numpy as np
import pytest
from conftest import get_robot

from mpcwalk.robot import robot_names
from mpcwalk.sim import Simulation
from mpcwalk.sim.simulation import _ctrl_joint_index
from mpcwalk.walking.runner import run_walk
from mpcwalk.walking.specification import WalkSpec

#: Sums over the walk's log of each series (NaN as 0), recorded before the change.
REFERENCE = {
    "mpc-turning": {
        "com": 155.7149028497326,
        "estimated_com": 155.87899150768274,
        "joint_targets": -188.92312030937683,
        "cop": 55.63118164631003,
        "foot_wrenches": 8438.121364664246,
        "actuator_force": -250.7522420605859,
        "estimated_sole_positions": 112.57184158986584,
    },
    "paper-m": {
        "com": 148.86941447359533,
        "estimated_com": 147.80136392572254,
        "joint_targets": -250.42622885627128,
        "cop": 47.66774437456192,
        "foot_wrenches": 8417.525106809864,
        "actuator_force": -169.92556231105314,
        "estimated_sole_positions": 91.30761240054397,
    },
    "mpc-push": {
        "com": 149.35948396197227,
        "estimated_com": 149.43479357549754,
        "joint_targets": -168.3284078793983,
        "cop": 49.03146474409266,
        "foot_wrenches": 8509.973780623164,
        "actuator_force": -213.64900793464108,
        "estimated_sole_positions": 93.91406882172878,
    },
}
#: (steps completed, foot position error mean [cm], CoP margin p5 [m]), recorded before.
REFERENCE_METRICS = {
    "mpc-turning": (5, 0.11221566884854696, 0.01373646518316613),
    "paper-m": (5, 0.20420825109086446, 0.00017941165735644958),
    "mpc-push": (5, 0.11839580026055316, 0.010493893186899497),
}


def _spec(case: str) -> WalkSpec:
    if case == "mpc-turning":
        return WalkSpec.build("bioloid-like", generator="mpc", command=(0.1, 0.0, 0.35), nb_steps=4)
    if case == "paper-m":
        return WalkSpec.build(
            "bioloid-like", controller="paper-m", command=(0.1, 0.0, 0.0), nb_steps=4
        )
    return WalkSpec.build(
        "bioloid-like",
        generator="mpc",
        command=(0.1, 0.0, 0.0),
        nb_steps=4,
        pushes=((2.2, 0.1, 0.0, 1.5, 0.0),),
    )


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(REFERENCE))
def test_walks_reproduce_the_values_recorded_before_the_speed_work(case):
    result = run_walk(_spec(case))
    log = result.log
    assert len(log.time) == 450
    for field, expected in REFERENCE[case].items():
        total = float(np.nan_to_num(np.asarray(getattr(log, field), dtype=float)).sum())
        assert total == pytest.approx(expected, rel=0.0, abs=1e-9), field  # measured: equal
    m = result.metrics
    steps, error, margin = REFERENCE_METRICS[case]
    assert m.steps_completed == steps
    assert m.foot_position_error_cm_mean == pytest.approx(error, rel=0.0, abs=1e-12)
    assert m.cop_margin_p05_m == pytest.approx(margin, rel=0.0, abs=1e-12)


@pytest.mark.parametrize(
    "name", [n for n in ("bioloid-like", "atlas-like", "g1") if n in robot_names()]
)
def test_joint_targets_reach_ctrl_as_the_configuration_would(name):
    robot = get_robot(name)
    index = _ctrl_joint_index(robot)
    assert index is not None  # every shipped actuator holds a joint
    angles = np.random.default_rng(0).uniform(-1.0, 1.0, len(robot.joint_names))
    q = robot.q0.copy()
    q[7:] = angles
    np.testing.assert_array_equal(angles[index], robot.q_to_ctrl(q))


def test_simulation_ctrl_is_the_same_through_the_gather_and_the_general_path():
    robot = get_robot("bioloid-like")
    sim = Simulation(robot)
    angles = robot.q0[7:] + 0.01 * np.arange(len(robot.joint_names))
    fast = sim._ctrl_of(angles)
    sim._ctrl_joints = None  # the general path: q_to_ctrl of the configuration
    general = sim._ctrl_of(angles)
    full = sim._ctrl_of(np.concatenate([robot.q0[:7], angles]))
    np.testing.assert_array_equal(fast, general)
    np.testing.assert_array_equal(full, general)
    assert not np.array_equal(general, robot.q_to_ctrl(robot.q0))  # the targets moved it


def test_bad_joint_targets_are_refused_at_the_simulation_boundary():
    from mpcwalk.exceptions import ConfigurationError

    robot = get_robot("bioloid-like")
    sim = Simulation(robot)
    angles = robot.q0[7:].copy()
    angles[2] = np.nan
    with pytest.raises(
        ConfigurationError, match=f"infinite angles for \\['{robot.joint_names[2]}'\\]"
    ):
        sim.step(angles)
    with pytest.raises(ConfigurationError, match="Joint targets must have"):
        sim.step(angles[:-1])


def test_contact_wrenches_of_all_contacts_equal_those_of_their_indices():
    import mujoco

    robot = get_robot("g1")
    sim = Simulation(robot)
    rng = np.random.default_rng(5)
    for _ in range(20):
        sim.step(robot.q0[7:] + rng.normal(0.0, 0.03, robot.model.nq - 7))
    ncon = sim.data.ncon
    assert ncon >= 4  # measured: 5 contacts
    every = sim.contacts._contact_wrenches(sim.model, sim.data, slice(0, ncon))
    indexed = sim.contacts._contact_wrenches(sim.model, sim.data, np.arange(ncon))
    expected = np.zeros((ncon, 6))
    for i in range(ncon):
        mujoco.mj_contactForce(sim.model, sim.data, i, expected[i])
    np.testing.assert_array_equal(every, indexed)
    np.testing.assert_allclose(every, expected, rtol=0.0, atol=1e-12)  # measured: 0.0
    assert np.abs(every[:, 0]).sum() > 0.5 * weight_of(robot)  # measured: 401 N for 327 N


def weight_of(robot) -> float:
    return robot.total_mass * float(np.linalg.norm(robot.model.gravity.linear))
