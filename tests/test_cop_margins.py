"""The CoP margin against the soles that carry the force, on ticks built by hand."""

import dataclasses

import numpy as np
import pytest
from plans import arc_schedule

from mpcwalk.models.support_polygon import SupportPolygon, foot_rectangle
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.metrics import (
    cop_margins,
    loaded_soles,
    measured_support_polygon,
    measured_zmp,
)
from mpcwalk.walking.metrics.cop_margins import LOADED_FLOOR, LOADED_SHARE

SCHEDULE = arc_schedule((0.05, 0.0, 0.0), nb_steps=2)  # soles 0.10 x 0.06 m
LENGTH, WIDTH = SCHEDULE.foot.length, SCHEDULE.foot.width


def wrench(force, cop, origin):
    """A foot's wrench [N, N m] of ``force`` applied at ``cop``, moment about ``origin``."""
    force = np.asarray(force, dtype=float)
    return np.concatenate((force, np.cross(np.subtract(cop, origin), force)))


def tick_log(soles, wrenches, com, yaws=None):
    """A log of ticks with only what the margins read: soles (n, 2, 3), wrenches (n, 2, 6),
    CoM (n, 3), yaws (n, 2)."""
    soles = np.asarray(soles, dtype=float)
    n = len(soles)
    values: dict = {f.name: np.zeros(n) for f in dataclasses.fields(WalkLog)}
    values.update(
        time=0.01 * np.arange(1, n + 1),
        sole_positions=soles,
        sole_yaws=np.zeros((n, 2)) if yaws is None else np.asarray(yaws, dtype=float),
        foot_wrenches=np.asarray(wrenches, dtype=float),
        com=np.asarray(com, dtype=float),
        joint_names=(),
        torque_limit=np.zeros(0),
    )
    return WalkLog(**values)


LEFT, RIGHT = (0.0, 0.04, 0.0), (0.05, -0.04, 0.0)  # the right foot a step ahead
COM = (0.02, 0.0, 0.25)


def test_a_landing_foot_that_carries_force_counts_though_the_schedule_says_single_support():
    # the right foot lands on its heel and already carries 14 of the 20 N; the schedule's
    # single support on the left would put this CoP 26 mm outside the left sole
    left = wrench((0.0, 0.0, 6.0), LEFT, LEFT)
    right = wrench((0.0, 0.0, 14.0), (0.0, -0.04, 0.0), RIGHT)
    log = tick_log([(LEFT, RIGHT)], [(left, right)], [COM])
    cop = np.array([0.0, (6.0 * 0.04 - 14.0 * 0.04) / 20.0])  # (0, -0.016)
    stance_only = foot_rectangle(LEFT, 0.0, LENGTH, WIDTH)
    assert stance_only.signed_distance(cop) == pytest.approx(-0.026)
    np.testing.assert_allclose(measured_zmp(log)[0][0], cop, atol=1e-12)
    # in the hull of both soles its nearest edge joins the left sole's outer heel corner
    # (-0.05, 0.01) to the right sole's (0, -0.07): cross product over the edge's length
    edge, to_cop = np.array([0.05, -0.08]), cop - (-0.05, 0.01)
    expected = (edge[0] * to_cop[1] - edge[1] * to_cop[0]) / np.linalg.norm(edge)
    assert expected == pytest.approx(0.0027 / np.sqrt(0.0089))
    assert cop_margins(log, SCHEDULE)[0] == pytest.approx(expected, abs=1e-12)
    assert cop_margins(log, SCHEDULE)[0] > 0.0


def test_an_unloaded_sole_is_left_out_of_the_support_and_of_the_zmp():
    # the left sole carries 19.5 N near its inner edge, the right one 0.5 N: under 5 %
    total = 20.0
    assert 0.5 < LOADED_SHARE * total and 0.5 >= LOADED_FLOOR
    left = wrench((0.0, 0.0, 19.5), (0.0, 0.015, 0.0), LEFT)
    right = wrench((0.0, 0.0, 0.5), RIGHT, RIGHT)
    log = tick_log([(LEFT, RIGHT)], [(left, right)], [COM])
    assert loaded_soles(log).tolist() == [[True, False]]
    np.testing.assert_allclose(measured_zmp(log)[0][0], (0.0, 0.015), atol=1e-12)
    # 5 mm from the left sole's inner edge (y = 0.01), whatever the right sole
    assert cop_margins(log, SCHEDULE)[0] == pytest.approx(0.005, abs=1e-12)
    both = SupportPolygon.union_hull([foot_rectangle(p, 0.0, LENGTH, WIDTH) for p in (LEFT, RIGHT)])
    assert both.signed_distance((0.0, 0.015)) > 0.02  # what counting it would have given


def test_no_loaded_sole_no_margin():
    # 0.3 N on each sole: above 5 % of the total, below the floor
    feet = [wrench((0.0, 0.0, 0.3), p, p) for p in (LEFT, RIGHT)]
    log = tick_log([(LEFT, RIGHT)], [feet], [COM])
    assert not loaded_soles(log).any()
    assert np.isnan(cop_margins(log, SCHEDULE)[0])
    assert measured_support_polygon(log, SCHEDULE, 0) is None


def test_soles_at_two_heights_by_hand():
    # left sole on the floor, right sole on a 4 cm step; a vertical 10 N under the left
    # origin, 10 N with 2 N forward through the right origin; CoM 0.5 m high
    left_sole, right_sole, com = (0.0, 0.05, 0.0), (0.1, -0.05, 0.04), (0.05, 0.0, 0.5)
    left = wrench((0.0, 0.0, 10.0), left_sole, left_sole)
    right = wrench((2.0, 0.0, 10.0), right_sole, right_sole)
    log = tick_log([(left_sole, right_sole)], [(left, right)], [com])
    zmp, height = measured_zmp(log)
    # plane z_v = (10 * 0 + 10 * 0.04) / 20 = 0.02; the right force's line crosses it at
    # x = 0.1 - 0.02 * 2 / 10 = 0.096, the left one at x = 0: ZMP (0.048, 0)
    assert height[0] == pytest.approx(0.02)
    np.testing.assert_allclose(zmp[0], (0.048, 0.0), atol=1e-12)
    # corners seen from the CoM: left scaled (0.5 - 0.02) / 0.5 = 0.96 about the CoM,
    # right (0.5 - 0.02) / (0.5 - 0.04) = 0.48 / 0.46; the nearest hull edge joins the left
    # sole's outer heel corner (-0.05, 0.02) to the right sole's (0.05, -0.08)
    a = np.array([0.05 + (-0.05 - 0.05) * 0.96, 0.02 * 0.96])  # (-0.046, 0.0192)
    b = np.array([0.05, -0.08 * 0.48 / 0.46])
    edge, to_zmp = b - a, np.array([0.048, 0.0]) - a
    expected = (edge[0] * to_zmp[1] - edge[1] * to_zmp[0]) / np.linalg.norm(edge)
    assert expected == pytest.approx(0.05555, abs=1e-5)
    assert cop_margins(log, SCHEDULE)[0] == pytest.approx(expected, abs=1e-12)
    polygon = measured_support_polygon(log, SCHEDULE, 0)
    assert polygon is not None
    assert polygon.signed_distance(zmp[0]) == pytest.approx(expected, abs=1e-12)
    # the soles' rectangles without the projection give another figure (0.4 mm apart)
    flat = SupportPolygon.union_hull(
        [foot_rectangle(p, 0.0, LENGTH, WIDTH) for p in (left_sole, right_sole)]
    )
    assert flat.signed_distance(zmp[0]) != pytest.approx(expected, abs=2e-4)


def test_level_soles_give_the_plain_hull_margin_of_the_cop():
    rng = np.random.default_rng(3)
    n, height = 50, 0.03  # level soles off the floor: a raised platform
    soles = np.zeros((n, 2, 3))
    soles[:, 0, :2] = rng.uniform(-0.02, 0.02, (n, 2)) + (0.0, 0.05)
    soles[:, 1, :2] = rng.uniform(-0.08, 0.08, (n, 2)) + (0.0, -0.05)
    soles[:, :, 2] = height
    yaws = rng.uniform(-0.5, 0.5, (n, 2))
    normal = rng.uniform(2.0, 20.0, (n, 2))
    shear = rng.uniform(-3.0, 3.0, (n, 2, 2))  # horizontal forces: no effect on level soles
    cops = soles.copy()
    cops[:, :, :2] += rng.uniform(-0.06, 0.06, (n, 2, 2))  # some beyond their soles
    wrenches = np.array(
        [
            [wrench((*shear[i, k], normal[i, k]), cops[i, k], soles[i, k]) for k in range(2)]
            for i in range(n)
        ]
    )
    com = np.column_stack((rng.uniform(-0.05, 0.05, (n, 2)), np.full(n, 0.3)))
    log = tick_log(soles, wrenches, com, yaws)
    cop = np.einsum("nk,nkj->nj", normal, cops[:, :, :2]) / normal.sum(axis=1, keepdims=True)
    expected = [
        SupportPolygon.union_hull(
            [foot_rectangle(soles[i, k], yaws[i, k], LENGTH, WIDTH) for k in range(2)]
        ).signed_distance(cop[i])
        for i in range(n)
    ]
    margins = cop_margins(log, SCHEDULE)
    np.testing.assert_allclose(measured_zmp(log)[1], height, atol=1e-15)
    np.testing.assert_allclose(margins, expected, atol=1e-12)
    assert (margins < 0.0).any() and (margins > 0.0).any()


def test_a_log_without_foot_wrenches_loads_without_margins(tmp_path):
    log = tick_log([(LEFT, RIGHT)], [[wrench((0, 0, 10), p, p) for p in (LEFT, RIGHT)]], [COM])
    path = log.save(tmp_path / "walk_log.npz")
    with np.load(path) as data:
        arrays = {name: data[name] for name in data.files if name != "foot_wrenches"}
    np.savez(tmp_path / "old.npz", **arrays)
    old = WalkLog.load(tmp_path / "old.npz")
    assert old.foot_wrenches.shape == (1, 2, 6) and np.isnan(old.foot_wrenches).all()
    assert np.isnan(cop_margins(old, SCHEDULE)).all()
    assert np.isfinite(cop_margins(WalkLog.load(path), SCHEDULE)).all()
