"""The terrain metrics of a walk on ticks built by hand: the tread margin of a landed sole."""

import dataclasses

import numpy as np
import pytest
from plans import arc_schedule

from mpcwalk.terrain import Slope, Stairs, Terrain
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.metrics.terrain_metrics import terrain_metrics

SCHEDULE = arc_schedule((0.05, 0.0, 0.0), nb_steps=2)  # soles 0.10 x 0.06 m
CHECK = np.array([1.0])


def landed_at(x: float) -> WalkLog:
    """A one-tick log at the first landing's check time, both soles centred at ``x`` [m]."""
    values: dict = {f.name: np.zeros(1) for f in dataclasses.fields(WalkLog)}
    values.update(
        time=CHECK.copy(),
        sole_positions=np.array([[[x, 0.04, 0.0], [x, -0.04, 0.0]]]),
        sole_yaws=np.zeros((1, 2)),
        foot_wrenches=np.zeros((1, 2, 6)),
        com=np.zeros((1, 3)),
        joint_names=(),
        torque_limit=np.zeros(0),
    )
    return WalkLog(**values)


def tread_margin_cm(terrain: Terrain, x: float) -> float:
    metrics = terrain_metrics(landed_at(x), SCHEDULE, terrain, CHECK, 0.25, 2.0)
    return metrics["tread_margin_cm_min"]


def test_a_sole_on_a_gentle_ramps_foot_rests_on_both_tops():
    # the sole's heel on the floor, its toe on a 3 deg ramp: the planner lets a sole
    # straddle that kink, and the margin counts floor and ramp as one top (it measured
    # -5 cm, half the sole's length, against the floor alone)
    margin = tread_margin_cm(Terrain([Slope(0.3, 1.0, 3.0)]), 0.3)
    assert margin > 0.0


def test_a_sole_across_a_stairs_nose_has_a_negative_margin():
    # the same sole across a 5 cm riser: half of it hangs over the lower tread
    margin = tread_margin_cm(Terrain([Stairs(0.3, 0.05, 0.3, 2)]), 0.3)
    assert margin == pytest.approx(-5.0, abs=0.5)
