"""A schedule's phases built as queries reach them are the phases built at once."""

import numpy as np
import pytest
from plans import tail_moved, velocity_schedule

from mpcwalk.footsteps.footstep import FootGeometry, Footstep, Side
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.support_polygons import SupportPolygons


def chain(schedule: ContactSchedule, firsts, seed: int, read_each: bool):
    """Schedules each built from the last with the steps from ``first`` on moved by one
    offset (a publication's tail); ``read_each``: every phase read when built, else only
    the first half-planes (the footstep MPC's horizon)."""
    rng = np.random.default_rng(seed)
    out = []
    for first in firsts:
        schedule = tail_moved(schedule, first, rng.normal(0.0, 2e-3, 2))
        if read_each:
            schedule.phase_halfplanes
        else:
            schedule.leading_halfplanes(3 * first + 4)
        out.append(schedule)
    return out


def arrays(schedule: ContactSchedule) -> list[np.ndarray]:
    A, b = schedule.phase_halfplanes
    vertices = [phase.polygon.vertices for phase in schedule.phases]
    return [A, b, schedule.phase_centers, schedule.zmp_breakpoint_values, *vertices]


@pytest.mark.parametrize("seed", [0, 1])
def test_phases_built_when_asked_are_the_phases_built_at_once(seed):
    plan = velocity_schedule((0.1, 0.0, np.deg2rad(20.0)), 14).plan
    firsts = [1, 2, 2, 3, 5, 5, 6, 8, 9, 9, 11]
    # two chains from two schedules of the same plan (their own polygon shapes)
    eager = chain(ContactSchedule(plan), firsts, seed, read_each=True)
    lazy = chain(ContactSchedule(plan), firsts, seed, read_each=False)
    assert not lazy[0]._builder.complete  # its later phases were never asked for
    # (and each is its plan's: built anew, the polygons of the same shapes to 1e-12 m)
    for schedule in lazy[::3]:
        anew = ContactSchedule(schedule.plan)
        for a, b in zip(arrays(schedule), arrays(anew), strict=True):
            np.testing.assert_allclose(a, b, rtol=0.0, atol=1e-12)
    for mine, theirs in zip(reversed(lazy), reversed(eager)):  # the last chain's first
        for a, b in zip(arrays(mine), arrays(theirs), strict=True):
            np.testing.assert_array_equal(a, b)
        for a, b in zip(mine.phases, theirs.phases, strict=True):
            assert list(a.feet) == list(b.feet)
            for foot, other in zip(a.feet.values(), b.feet.values()):
                np.testing.assert_array_equal(foot.position, other.position)


def test_the_queries_of_a_partly_built_schedule():
    plan = velocity_schedule((0.1, 0.0, np.deg2rad(20.0)), 8).plan
    full = ContactSchedule(plan)
    steps = list(plan.steps)
    steps[2] = steps[2].moved(position=steps[2].position + [0.01, 0.0, 0.0])
    partial, built = full.with_steps(steps), full.with_steps(steps)
    built.phases  # every phase built at once
    times = np.linspace(0.0, partial.duration, 97)
    A, _, edges = partial.leading_halfplanes(4)
    assert 4 <= len(A) < len(built.phases) and len(edges) == len(A)
    for t in times[:20]:  # one phase at a time
        assert partial.phase(t).polygon is not None
    for mine, theirs in zip(partial.halfplanes(times[:40]), built.halfplanes(times[:40])):
        np.testing.assert_array_equal(mine, theirs)
    assert not partial._builder.complete
    for mine, theirs in zip(partial.halfplanes(times), built.halfplanes(times)):
        np.testing.assert_array_equal(mine, theirs)
    np.testing.assert_array_equal(partial.support_center(times), built.support_center(times))
    np.testing.assert_array_equal(partial.zmp_reference(times), built.zmp_reference(times))


@pytest.mark.parametrize("pitch", [0.0, 0.3])
def test_a_hull_on_the_shape_of_its_first_sole_is_the_hull_made_anew(pitch):
    left = Footstep(Side.LEFT, [0.1, 0.12, 0.0], yaw=0.2, pitch=pitch)
    right = Footstep(Side.RIGHT, [0.25, -0.05, 0.0], yaw=-0.1)
    feet = {Side.LEFT: left, Side.RIGHT: right}
    polygons, anew = SupportPolygons(FootGeometry()), SupportPolygons(FootGeometry())
    polygons.rect(left)  # the first sole's shape made first
    mine, theirs = polygons.hull(feet), anew.hull(feet)
    for a, b in zip((mine.vertices, mine.A, mine.b), (theirs.vertices, theirs.A, theirs.b)):
        np.testing.assert_array_equal(a, b)
