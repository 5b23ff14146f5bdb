"""Faults injected into running walks through the public API are contained: a QP back-end
that returns NaN, garbage, nothing or raises, a sensor stream with NaN and dropouts. Each is
survived (counted, the walk goes on) or ends the walk as a controlled stop (outcome
``stopped``, exit code 3) with the log and the metrics written; NaN never reaches the
actuators. ``mpcwalk experiment run faults`` tallies these cases into ``results/faults/report.md``."""

import json

import numpy as np
import pytest
from conftest import walk

from mpcwalk.cli import main
from mpcwalk.control.faults import FaultMonitor
from mpcwalk.exceptions import ControllerStopped
from mpcwalk.qp.result import QPResult
from mpcwalk.qp.solvers.base import QPSolver
from mpcwalk.qp.solvers.registry import SOLVERS, backend_entry, make_solver


class FaultySolver(QPSolver):
    """DAQP, except every ``every``-th solve (or every one from ``start``): NaN reported as
    success, garbage (the solution times 1e6) reported as success, None, or an exception."""

    def __init__(self, mode: str = "nan", every: int = 1, start: int = 0) -> None:
        self.inner = make_solver("daqp")
        self.mode, self.every, self.start, self.calls = mode, every, start, 0
        self.name = "faulty"

    def solve(self, qp, *, shift: float = 0.0):
        self.calls += 1
        result = self.inner.solve(qp, shift=shift)
        if self.calls < self.start or self.calls % self.every:
            return result
        if self.mode == "raise":
            raise RuntimeError("the back-end crashed")
        if self.mode == "none":
            return None
        x = np.full_like(result.x, np.nan) if self.mode == "nan" else 1e6 * result.x
        return QPResult(x, None, True, "solved", 0.0, 1, 0.0, None, None, "faulty")


SOLVERS.register(backend_entry("faulty", "the suite's fault injector", FaultySolver))


def _walk(**fields):
    return walk("bioloid-like", "mpc", command=(0.1, 0.0, 0.0), nb_steps=4, **fields)


def _check_no_nan_reached_the_actuators(result):
    assert np.all(np.isfinite(result.log.joint_targets))


@pytest.mark.parametrize("mode", ["nan", "garbage", "none", "raise"])
def test_a_faulty_solve_now_and_then_is_survived_and_counted(mode):
    settings = {"mode": mode, "every": 10}
    result = _walk(generator_options={"solver": "faulty", "solver_settings": settings})
    # the settings go to the back-end's factory: every 10th solve fails
    m = result.metrics
    assert m.outcome == "walked" and not m.fell
    assert m.mpc_failures > 0 and m.fallback_ticks >= m.mpc_failures
    _check_no_nan_reached_the_actuators(result)


def test_a_back_end_that_never_recovers_is_a_controlled_stop(tmp_path, capsys):
    out = tmp_path / "walk"
    code = main(
        ["walk", "--robot", "bioloid-like", "--steps", "4", "--no-progress", "--out", str(out)]
        + ["--solver", "faulty"]
    )
    assert code == 3, capsys.readouterr()
    printed = capsys.readouterr().out
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["outcome"] == "stopped" and not metrics["fell"]
    assert "fallback ticks in a row" in metrics["stop_reason"]
    assert metrics["fallback_ticks"] == FaultMonitor().max_fault_ticks + 1
    assert {p.name for p in out.iterdir()} >= {"metrics.json", "walk_log.npz", "top_view.png"}
    assert not list(out.glob(".*tmp*"))  # no temporary file left
    log = np.load(out / "walk_log.npz")
    assert np.all(np.isfinite(log["joint_targets"]))
    del printed


def test_nan_and_dropped_sensor_readings_are_survived():
    result = _walk(sensor_nan=[(1.5, 1.55)], sensor_dropout=[(2.0, 2.1)])
    m = result.metrics
    assert m.outcome == "walked" and not m.fell
    assert m.sensor_faults == 5 + 10  # ticks of the two windows at 10 ms
    _check_no_nan_reached_the_actuators(result)


def test_a_long_sensor_outage_is_a_controlled_stop():
    result = _walk(sensor_nan=[(1.5, 5.0)])
    m = result.metrics
    assert m.outcome == "stopped" and "bad or missing sensor readings" in m.stop_reason
    assert 1.7 < m.time_simulated_s < 1.9  # 26 ticks after 1.5 s (one of latency)
    assert len(result.log) == m.nb_ticks > 0
    _check_no_nan_reached_the_actuators(result)


def test_fault_monitor_replaces_bad_values_and_bounds_them():
    monitor = FaultMonitor(max_fault_ticks=2)
    good = np.zeros(3)
    assert monitor.ik(np.array([0.0, np.nan, 0.0]), good) is not good
    np.testing.assert_array_equal(monitor.joint_targets(np.full(3, np.inf), good), good)
    monitor.end_tick(0.01)
    monitor.generator(True)
    monitor.end_tick(0.02)
    monitor.end_tick(0.03)  # a clean tick resets the count
    assert (monitor.ik_failures, monitor.target_faults, monitor.generator_failures) == (1, 1, 1)
    assert monitor.fallback_ticks == 2
    for t in (0.04, 0.05):
        monitor.generator(True)
        monitor.end_tick(t)
    monitor.generator(True)
    with pytest.raises(ControllerStopped, match="3 fallback ticks in a row up to t = 0.060 s"):
        monitor.end_tick(0.06)
