"""The landing bands of a plan on a terrain, and the footstep QP of ``mpc-steps`` kept in them."""

import functools

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps import FootGeometry, LegLimits, VelocityPlanner
from mpcwalk.footsteps.footstep import StepTiming
from mpcwalk.footsteps.landing_bands import LandingBands, tread_bands
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.mpc_steps import FootstepMpcGenerator
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM
from mpcwalk.terrain import Stairs, Terrain, TerrainReach

#: The small humanoid's sole (10 x 6 cm) on three 3 cm stairs of 1.5 soles from 0.2 m.
SOLE = (0.10, 0.06)
STAIRS = Terrain([Stairs(0.2, rise=0.03, run=0.15, count=3)])
REACH = TerrainReach.for_leg(*SOLE, 0.2)


@functools.cache
def stairs_plan():
    planner = VelocityPlanner(LegLimits(), StepTiming(0.8, 0.2))
    return planner.plan((0.05, 0.0, 0.0), 12, terrain=STAIRS, reach=REACH)


def pushed_landings(bands, kick=0.2, push_time=4.0, after=0.6):
    """The landings ``mpc-steps`` publishes ``after`` [s] past a forward kick of the CoM
    velocity [m/s] at ``push_time`` [s] (the generator starts its tick from the kicked
    state: no simulation), shape (nb_steps, 2)."""
    schedule = ContactSchedule(stairs_plan(), FootGeometry(*SOLE))
    gen = FootstepMpcGenerator(
        lipm=LIPM(com_height=0.23), planned_strides=True, landing_bands=bands
    )
    out = gen.reset(schedule)
    while gen.time < push_time + after - 1e-9:
        measured = None
        if abs(gen.time - push_time) < 1e-9:
            velocity = out.com_velocity + np.array([kick, 0.0])
            measured = ComState(out.com, velocity, out.com_acceleration)
        out = gen.step(measured)
        assert out.solve.success
    assert gen.schedule is not None
    return np.array([step.xy for step in gen.schedule.plan.steps])


def beyond(bands, xy):
    """How far [m] each landing lies outside its band (negative: inside), shape (n,)."""
    return np.maximum(bands.lower - xy, xy - bands.upper).max(axis=1)


def test_a_band_keeps_the_whole_sole_on_its_tread_with_the_margin():
    """Every corner of every band is a sole centre whose sole lies on the landing's top, the
    placer's margin (1 cm) from its edges; the planned landing lies in its band."""
    plan = stairs_plan()
    bands = tread_bands(plan, STAIRS, REACH)
    assert len(bands) == plan.nb_steps
    treads = 0
    for k, step in enumerate(plan.steps):
        xy = step.xy
        assert np.all(bands.lower[k] <= xy) and np.all(xy <= bands.upper[k])
        # along the stairs the band is finite; across, the terrain's width (3 m) bounds it
        assert np.isfinite(bands.lower[k]).all() and np.isfinite(bands.upper[k]).all()
        for x in (bands.lower[k, 0], bands.upper[k, 0]):
            support = STAIRS.sole_support((x, xy[1]), step.yaw, *SOLE)
            assert support.height == pytest.approx(step.position[2], abs=1e-9)
            assert support.margin >= REACH.tread_margin - 1e-9  # measured: 1.0 cm
        width = bands.upper[k, 0] - bands.lower[k, 0]
        if STAIRS.surfaces[STAIRS.surface_index(*xy)].kind == "tread":
            treads += 1
            assert width == pytest.approx(0.15 - 0.10 - 2 * REACH.tread_margin)  # 3 cm
    assert treads >= 4  # the plan climbs the stairs (measured: 4 landings on treads)


def test_a_step_down_keeps_the_placers_room_behind_the_heel():
    """Down three 3 cm stairs: a landing lower than its lift-off keeps a fifth of the sole
    behind its heel (the placer's heel room, 2 cm) on top of the margin; the band of a
    tread is 1 cm long instead of 3."""
    down = Terrain([Stairs(0.2, rise=-0.03, run=0.15, count=3)])
    planner = VelocityPlanner(LegLimits(), StepTiming(0.8, 0.2))
    plan = planner.plan((0.05, 0.0, 0.0), 12, terrain=down, reach=REACH)
    bands = tread_bands(plan, down, REACH)
    lift = {plan.initial_left.side: 0.0, plan.initial_right.side: 0.0}
    descents = 0
    for k, step in enumerate(plan.steps):
        lifted, lift[step.side] = lift[step.side], float(step.position[2])
        surface = down.surfaces[down.surface_index(*step.xy)]
        if surface.kind != "tread" or step.position[2] > lifted - 0.005:
            continue
        descents += 1
        heel_room = 0.2 * SOLE[0]
        back = surface.x_min + 0.5 * SOLE[0] + REACH.tread_margin + heel_room
        assert bands.lower[k, 0] == pytest.approx(min(back, step.xy[0]))
        assert bands.upper[k, 0] == pytest.approx(surface.x_max - 0.5 * SOLE[0] - 0.01)
    assert descents == 4  # measured: two feet on each of the first two treads


def test_the_footstep_qp_keeps_pushed_landings_on_their_treads():
    """A forward kick of 0.2 m/s at 4.0 s (no simulation): without bands the QP moves the
    landing before the first riser 3.8 cm beyond its band (its toe 2.8 cm into the riser:
    measured); with them every published landing stays in its band, every solve found."""
    bands = tread_bands(stairs_plan(), STAIRS, REACH)
    free = beyond(bands, pushed_landings(None))
    assert free.max() > 0.02  # measured 3.8 cm: the test fails without the bounds
    kept = beyond(bands, pushed_landings(bands))
    assert kept.max() < 1e-6  # measured 0 (the bound active)


def test_without_bands_the_footstep_qp_has_no_band_rows():
    """Bands that bound nothing add no row: the flat floor's QP is the one it was."""
    plan = stairs_plan()
    schedule = ContactSchedule(plan, FootGeometry(*SOLE))
    rows = {}
    free = LandingBands(np.full((plan.nb_steps, 2), -np.inf), np.full((plan.nb_steps, 2), np.inf))
    for label, bands in (
        ("none", None),
        ("free", free),
        ("treads", tread_bands(plan, STAIRS, REACH)),
    ):
        gen = FootstepMpcGenerator(
            lipm=LIPM(com_height=0.23), planned_strides=True, landing_bands=bands
        )
        gen.reset(schedule)
        for _ in range(120):
            gen.step()
        assert gen.qp is not None
        rows[label] = gen.qp.m
    assert rows["free"] == rows["none"]
    assert rows["treads"] > rows["none"]  # measured: 4 more rows per landing in the horizon


def test_bad_bands_are_named_errors():
    with pytest.raises(ConfigurationError, match=r"shape \(nb_steps, 2\)"):
        LandingBands(np.zeros((3, 2)), np.zeros((2, 2)))
    with pytest.raises(ConfigurationError, match="lower <= upper"):
        LandingBands(np.ones((1, 2)), np.zeros((1, 2)))
    with pytest.raises(ConfigurationError, match="landing_bands must be LandingBands"):
        FootstepMpcGenerator(landing_bands=[(0.0, 1.0)])
    plan = stairs_plan()
    bands = tread_bands(plan, STAIRS, REACH)
    short = LandingBands(bands.lower[:-1], bands.upper[:-1])
    gen = FootstepMpcGenerator(
        lipm=LIPM(com_height=0.23), planned_strides=True, landing_bands=short
    )
    with pytest.raises(ConfigurationError, match="hold 12 landings and the plan 13 steps"):
        gen.reset(ContactSchedule(plan, FootGeometry(*SOLE)))


@pytest.mark.parametrize("controller", ["mpc-steps", "mpc-hip"])
def test_the_walk_builder_gives_every_footstep_adaptive_generator_its_bands(controller):
    """On a terrain the builder passes the plan's bands (and its strides) to ``mpc-steps``
    and to its subclasses alike."""
    from conftest import get_robot

    from mpcwalk.walking.controller_builder import build_controller
    from mpcwalk.walking.specification import WalkSpec
    from mpcwalk.walking.walk_setup import set_up_walk

    spec = WalkSpec.build(
        "bioloid-like",
        controller=controller,
        command=(0.05, 0.0, 0.0),
        nb_steps=12,
        step_duration=0.8,
        terrain=STAIRS,
        progress=False,
    )
    robot = get_robot("bioloid-like")
    setup = set_up_walk(spec, robot)
    built = build_controller(
        robot,
        setup.spec.controller,
        setup.schedule,
        control_period=0.01,
        step_height=setup.step_height,
        terrain=STAIRS,
    )
    generator = built.generator
    assert isinstance(generator, FootstepMpcGenerator) and generator.planned_strides
    reach = TerrainReach.for_leg(*robot.sole_size, robot.leg_length)
    expected = tread_bands(setup.plan, STAIRS, reach)
    assert generator.landing_bands is not None
    assert np.array_equal(generator.landing_bands.lower, expected.lower)
    assert np.array_equal(generator.landing_bands.upper, expected.upper)


def test_on_a_terrain_the_capture_point_term_is_off_unless_asked_for():
    """``dcm_step_gain`` defaults to 1 on the floor and to 0 with landing bands (a terrain:
    its growth over long steps made the G1's landings jump between their bounds); a gain
    given is kept."""
    lipm, bands = LIPM(com_height=0.23), tread_bands(stairs_plan(), STAIRS, REACH)
    assert FootstepMpcGenerator(lipm=lipm).dcm_step_gain == 1.0
    assert FootstepMpcGenerator(lipm=lipm, landing_bands=bands).dcm_step_gain == 0.0
    given = FootstepMpcGenerator(lipm=lipm, landing_bands=bands, dcm_step_gain=0.5)
    assert given.dcm_step_gain == 0.5
