"""Paper M's experiments: capturability bounds, bisection, a real push case, yaw deviation,
turning summary, the table and the quick run of the experiment."""

import json
import math
import os
from dataclasses import asdict
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.paper_m.config import PaperMConfig, TurningConfig, load_config
from mpcwalk.experiments.paper_m.push_grid import (
    CaseResult,
    PushSweepConfig,
    SweepCase,
    summarize_sweep,
)
from mpcwalk.experiments.paper_m.table import format_report, format_table, goal_checks, table_rows
from mpcwalk.experiments.paper_m.walks import (
    CONTROLLERS,
    controller_availability,
    push_case_task,
    turning_summary,
    walk_task,
)
from mpcwalk.experiments.survival import find_largest_survived
from mpcwalk.footsteps.capturability import Box, capture_impulse_bound
from mpcwalk.models.lipm import LIPM
from mpcwalk.sim import ExternalForce
from mpcwalk.sweep import WorkerDied, map_tasks
from mpcwalk.walking.metrics import yaw_deviation_deg
from mpcwalk.walking.specification import ControllerSpec

ROOT = Path(__file__).resolve().parent.parent
MASS, HEIGHT = 2.02, 0.23
OMEGA = math.sqrt(9.81 / HEIGHT)


def _ray(direction, forward, backward, lateral):
    return Box(-backward, forward, -lateral, lateral).ray_distance((0.0, 0.0), direction)


def test_the_ray_from_the_foot_centre_reaches_the_sole_border():
    assert _ray(0.0, 0.05, 0.05, 0.03) == pytest.approx(0.05)
    assert _ray(math.pi / 2, 0.05, 0.05, 0.03) == pytest.approx(0.03)
    assert _ray(math.pi, 0.08, 0.04, 0.04) == pytest.approx(0.04)
    # 45 deg: the lateral side is hit first, at 0.03 / sin(45 deg)
    assert _ray(math.pi / 4, 0.05, 0.05, 0.03) == pytest.approx(0.03 * 2**0.5)
    # 20 deg: the front side, at 0.05 / cos(20 deg)
    angle = math.radians(20.0)
    assert _ray(angle, 0.05, 0.05, 0.03) == pytest.approx(0.05 / math.cos(angle))


def test_capture_impulse_bound_values():
    # no step: m omega d, with omega = sqrt(9.81 / 0.23) = 6.531 1/s
    assert capture_impulse_bound(0.0, mass=MASS, com_height=HEIGHT) == pytest.approx(
        2.02 * 6.53085 * 0.05, rel=1e-5
    )
    assert capture_impulse_bound(0.0, mass=MASS, com_height=HEIGHT) == pytest.approx(
        0.65962, rel=1e-4
    )
    assert capture_impulse_bound(math.pi / 2, mass=MASS, com_height=HEIGHT) == pytest.approx(
        MASS * OMEGA * 0.03
    )
    # one forward step of 0.08 m landing 0.25 s later adds m omega L exp(-omega t)
    with_step = capture_impulse_bound(
        0.0, mass=MASS, com_height=HEIGHT, step_reach=(0.08, 0.04, 0.04), step_time=0.25
    )
    assert with_step == pytest.approx(MASS * OMEGA * (0.05 + 0.08 * math.exp(-OMEGA * 0.25)))
    assert with_step == pytest.approx(0.8658, rel=1e-3)  # 13.19 * (0.05 + 0.0156)
    with pytest.raises(ConfigurationError, match="mass > 0 kg"):
        capture_impulse_bound(0.0, mass=0.0, com_height=HEIGHT)


@pytest.mark.parametrize("factor, captured", [(0.99, True), (1.01, False)])
def test_capture_bound_matches_the_lipm(factor, captured):
    """Oracle: the LIPM pushed at rest over the foot centre, ZMP held at the sole's edge d,
    then a step landing t later with the ZMP at L + d: it stops before L + d iff the impulse
    is within the bound."""
    lipm, d, L, t = LIPM(HEIGHT, 9.81), 0.05, 0.08, 0.25
    bound = capture_impulse_bound(
        0.0, mass=MASS, com_height=HEIGHT, step_reach=(L, L, L), step_time=t, gravity=9.81
    )
    velocity = factor * bound / MASS
    c, v, _ = lipm.propagate(0.0, velocity, d, t)
    c, v, _ = lipm.propagate(c, v, L + d, 3.0)
    assert (c <= L + d) == captured
    no_step = capture_impulse_bound(0.0, mass=MASS, com_height=HEIGHT, gravity=9.81)
    c, v, _ = lipm.propagate(0.0, factor * no_step / MASS, d, 3.0)
    assert (c <= d) == captured


@pytest.mark.parametrize(
    "threshold, initial", [(0.537, 0.4), (0.537, 2.0), (0.11, 0.4), (1.9, 0.4)]
)
def test_bisection_finds_the_threshold_of_a_monotone_oracle(threshold, initial):
    calls = []

    def survives(value):
        calls.append(value)
        return value <= threshold

    found = find_largest_survived(survives, initial=initial, upper_limit=4.0, tolerance=0.01)
    assert found.largest_survived <= threshold < found.smallest_fallen
    assert found.smallest_fallen - found.largest_survived <= 0.01
    assert [v for v, _ in found.trials] == calls and len(calls) <= 12
    assert all(ok == (v <= threshold) for v, ok in found.trials)
    # the relative tolerance stops earlier, within 20 % of the upper end
    coarse = find_largest_survived(
        lambda v: v <= threshold,
        initial=initial,
        upper_limit=4.0,
        tolerance=0.01,
        relative_tolerance=0.2,
    )
    assert coarse.largest_survived <= threshold < coarse.smallest_fallen
    assert coarse.smallest_fallen - coarse.largest_survived <= 0.2 * coarse.smallest_fallen
    assert len(coarse.trials) < len(found.trials)


def test_bisection_censored_and_zero():
    above = find_largest_survived(lambda v: True, initial=0.4, upper_limit=3.0, tolerance=0.01)
    assert above.largest_survived == 3.0 and above.censored
    assert [v for v, _ in above.trials] == [0.4, 0.8, 1.6, 3.0]
    never = find_largest_survived(lambda v: False, initial=0.4, upper_limit=3.0, tolerance=0.05)
    assert never.largest_survived == 0.0 and never.smallest_fallen <= 0.05
    with pytest.raises(ConfigurationError, match="0 < initial <= upper_limit"):
        find_largest_survived(lambda v: True, initial=5.0, upper_limit=3.0, tolerance=0.01)
    # a limit that 9 decimals do not hold (3 x 0.4283786954394798 N s: a cell of the push
    # map) ends once it survived, censored there (it tried the rounded limit forever)
    limit = 3 * 0.4283786954394798
    odd = find_largest_survived(
        lambda v: True, initial=limit / 6, upper_limit=limit, tolerance=0.02
    )
    assert odd.censored and odd.largest_survived == pytest.approx(limit)
    assert len(odd.trials) == 4


def test_push_timing_and_force():
    config = PushSweepConfig()
    # step 2 of a walk that starts at 1 s, T = 0.5 s, r_ds = 0.2: t_b = 0.05 s, t_e = 0.45 s
    starts = {
        p: config.push_start(p, step_duration=0.5, double_support_ratio=0.2) for p in config.phases
    }
    assert starts == pytest.approx({"ss-start": 2.05, "ss-mid": 2.25, "ds": 2.45})
    force = config.push_force(135.0, 0.5)  # 0.5 N s over 0.1 s: 5 N backward-left
    assert force == pytest.approx([-5.0 / 2**0.5, 5.0 / 2**0.5, 0.0])
    with pytest.raises(ConfigurationError, match="Unknown push phase"):
        PushSweepConfig(phases=("swing",))


def test_real_push_case_on_the_analytic_gait():
    """MuJoCo: the open-loop gait walks the sweep's walk unpushed, falls under a 3 N s push,
    and the bisection's answer lies between, consistent with every walk it ran."""
    config = PushSweepConfig(
        directions_deg=(90.0,),
        phases=("ss-mid",),
        tolerance=0.1,
        relative_tolerance=0.5,
        max_impulse=3.0,
    )
    kwargs = CONTROLLERS["paper-m-open"]
    walk = {"command": config.command, "nb_steps": config.nb_steps}
    unpushed = walk_task("bioloid-like", kwargs, walk)
    assert not unpushed.fall.fell
    start = config.push_start("ss-mid", step_duration=0.5, double_support_ratio=0.2)
    assert unpushed.schedule.is_single_support(np.array([start, start + 0.1])).all()
    huge = walk_task(
        "bioloid-like",
        kwargs,
        {**walk, "pushes": [ExternalForce(start, 0.1, config.push_force(90.0, 3.0))]},
    )
    assert huge.fall.fell and huge.fall.time < start + 1.0
    result = push_case_task(
        "bioloid-like", kwargs, config, SweepCase("paper-m-open", 90.0, "ss-mid")
    )
    assert 0.0 <= result.largest_survived < result.smallest_fallen <= 3.0
    for impulse, survived in result.trials:
        assert survived == (impulse <= result.largest_survived)


class _Log(SimpleNamespace):
    def __len__(self):
        return len(self.time)


def _synthetic(times, yaws):
    rpy = np.zeros((len(times), 3))
    rpy[:, 2] = np.asarray(yaws)
    return _Log(time=np.asarray(times, float), base_rpy=rpy)


def test_yaw_deviation_on_synthetic_logs():
    t = np.arange(0.0, 6.0, 0.01)
    reference = _synthetic(t, 0.1 * t)
    bump = np.where((t > 3.0) & (t < 4.0), np.radians(5.0) * np.sin(np.pi * (t - 3.0)), 0.0)
    drift = np.where(t > 4.0, np.radians(2.0), 0.0)
    pushed = _synthetic(t, 0.1 * t + bump + drift)
    assert yaw_deviation_deg(pushed, reference, 3.05) == pytest.approx(5.0, abs=1e-3)
    assert yaw_deviation_deg(pushed, reference, 3.05, statistic="final") == pytest.approx(2.0)
    assert yaw_deviation_deg(pushed, reference, 4.5) == pytest.approx(2.0)
    # a walk that fell: compared until its end only
    fell = _synthetic(t[t < 3.5], (0.1 * t + bump)[t < 3.5])
    assert yaw_deviation_deg(fell, reference, 3.05) == pytest.approx(
        5.0 * math.sin(0.49 * math.pi), rel=1e-6
    )
    # wrapped IMU yaw around +-180 deg is unwrapped, the difference wrapped
    near_pi = np.pi - 0.01 + 0.001 * t
    wrapped = (near_pi + np.radians(3.0) * (t > 3.0) + np.pi) % (2 * np.pi) - np.pi
    assert yaw_deviation_deg(_synthetic(t, wrapped), _synthetic(t, near_pi), 3.05) == pytest.approx(
        3.0, abs=1e-9
    )
    assert yaw_deviation_deg(pushed, reference, 99.0) == 0.0
    with pytest.raises(ConfigurationError, match="'max' or 'final'"):
        yaw_deviation_deg(pushed, reference, 3.0, statistic="mean")


def test_turning_summary_on_an_ideal_yaw():
    """A walk whose IMU yaw follows the command exactly from the start of walking: 70 deg after
    3.5 s and 20 deg/s."""
    from mpcwalk.footsteps.footstep import StepTiming
    from mpcwalk.gait.contact_schedule import ContactSchedule
    from mpcwalk.robot.loading import load_robot
    from mpcwalk.walking.footstep_planning import plan_walk_footsteps

    config = TurningConfig()
    robot = load_robot("bioloid-like", visual=False)
    # 20 steps: more than 180 deg of turn
    plan = plan_walk_footsteps(robot, command=config.command, nb_steps=20, timing=StepTiming())
    schedule = ContactSchedule(plan)
    t = np.arange(0.01, schedule.duration + 1e-9, 0.01)
    yaw = config.command[2] * np.clip(t - schedule.walk_start, 0.0, None)
    log = _synthetic(t, (yaw + np.pi) % (2 * np.pi) - np.pi)
    result = SimpleNamespace(
        schedule=schedule,
        log=log,
        fall=SimpleNamespace(fell=False),
        metrics=SimpleNamespace(fall_time_s=None),
    )
    summary = turning_summary(result, config)
    assert summary["yaw_at_check_deg"] == pytest.approx(70.0, abs=0.05)
    assert summary["yaw_rate_deg_s"] == pytest.approx(20.0, rel=1e-6)
    assert summary["yaw_rate_planned_deg_s"] == pytest.approx(20.0, rel=1e-6)
    assert summary["yaw_rate_error_percent"] == pytest.approx(0.0, abs=1e-4)


def _case(name, direction, phase, largest, fallen=None):
    trials = ((0.4, largest >= 0.4), (largest, True))
    return CaseResult(SweepCase(name, direction, phase), largest, fallen, trials, 1.0)


def _synthetic_results():
    config = PushSweepConfig(
        directions_deg=(0.0, 90.0), phases=("ss-start", "ss-mid"), impulse_grid=(0.1, 0.2, 0.3, 0.4)
    )
    cases = [_case("paper-m", d, p, 0.1, 0.12) for d in (0.0, 90.0) for p in config.phases]
    cases += [
        _case("mpc", 0.0, "ss-start", 0.3, 0.33),
        _case("mpc", 0.0, "ss-mid", 0.35, 0.4),
        _case("mpc", 90.0, "ss-start", 0.15, 0.17),
        _case("mpc", 90.0, "ss-mid", 0.25, 0.3),
    ]
    summary = summarize_sweep(cases, config)
    dist = {"fell": False, "yaw_deviation_deg": 4.0}
    return config, {
        "command": "mpcwalk experiment run paper_m --quick --out out",
        "mode": "quick",
        "config": {
            "turning": vars(TurningConfig()) | {"command": [0.1, 0.0, 0.349]},
            "disturbance": {"command": [0.1, 0, 0], "pushes": [], "stabilizer": "gyro"},
            "push_sweep": vars(config),
            "speed": {"nb_steps": 10, "step_durations": [0.5]},
        },
        "controllers": {n: asdict(CONTROLLERS[n]) for n in ("paper-m", "mpc")},
        "skipped": {"mpc-steps": "no generator 'mpc-steps'"},
        "wall_time_s": 12.0,
        "workers": 2,
        "nb_tasks": 10,
        "turning": {
            "paper-m": {
                "fell": True,
                "yaw_at_check_deg": 50.0,
                "yaw_rate_deg_s": 15.0,
                "yaw_rate_error_percent": -25.0,
            },
            "mpc": {
                "fell": False,
                "yaw_at_check_deg": 66.0,
                "yaw_rate_deg_s": 19.5,
                "yaw_rate_error_percent": -2.5,
            },
        },
        "disturbance": {
            "paper-m": {
                "fell": True,
                "yaw_deviation_deg": 11.0,
                "stabilizer_ratio": 0.5,
                "without_stabilizer": dist,
                "with_stabilizer": {"fell": True},
            },
            "mpc": {
                **dist,
                "stabilizer_ratio": 0.4,
                "without_stabilizer": dist,
                "with_stabilizer": dist,
            },
        },
        "push_sweep": {"summary": summary},
        "speed": {
            "mpc": [
                {
                    "step_duration_s": 0.5,
                    "bound_m_s": 0.16,
                    "fastest_m_s": 0.16,
                    "fastest_measured_m_s": 0.155,
                    "limited_by": "kinematic bound",
                }
            ]
        },
    }


def test_sweep_summary_table_and_goals_on_synthetic_results():
    _config, results = _synthetic_results()
    summary = results["push_sweep"]["summary"]
    assert summary["mpc"]["median_impulse_Ns"] == pytest.approx(0.275)
    assert summary["mpc"]["per_direction_Ns"] == pytest.approx({"0": 0.325, "90": 0.2})
    # grid 0.1..0.4 against the cells 0.3, 0.35, 0.15, 0.25: 3 + 3 + 1 + 2 of 16
    assert summary["mpc"]["success_rate_grid"] == pytest.approx(9 / 16)
    assert summary["paper-m"]["success_rate_grid"] == pytest.approx(0.25)
    rows = table_rows(results)
    mpc = rows[1]
    assert mpc["impulse_ratio"] == pytest.approx(2.75)
    assert mpc["fastest_m_s"] == 0.16 and rows[0]["fastest_m_s"] is None
    goals = {(g["controller"], g["goal"].split()[0]): g["met"] for g in goal_checks(rows)}
    assert goals == {
        ("mpc", "impulse"): True,
        ("mpc", "turning"): True,
        ("paper-m", "turning"): False,
    }
    table = format_table(rows)
    lines = table.splitlines()
    assert "paper M (reported" in lines[2] and "| 70.0 |" in lines[2]
    assert lines[3].startswith("| paper-m | yes | 50.0 | 15.00 | -25.0 | yes | 11.00 (fell) |")
    assert "| 0.50 (fell) |" in lines[3] and "| 0.40 |" in lines[4] and "| 2.75 |" in lines[4]
    readme = format_report(
        {**results, "rows": rows, "goals": goal_checks(rows), "figures": ["push_polar.png"]}
    )
    assert table in readme and "**met**: mpc, impulse >= 1.5 x paper-m (2.75)" in readme
    assert "skipped `mpc-steps`: no generator 'mpc-steps'" in readme
    assert "| mpc | 0.325 | 0.200 |" in readme and "![push_polar.png](push_polar.png)" in readme


def test_config_file_matches_the_defaults_and_quick_is_smaller():
    full, quick = load_config(), load_config(quick=True)
    assert full == PaperMConfig()
    assert quick.turning.command == full.turning.command and quick.mode == "quick"
    cells = len(quick.push_sweep.directions_deg) * len(quick.push_sweep.phases)
    assert cells < len(full.push_sweep.directions_deg) * len(full.push_sweep.phases)
    assert quick.controllers == ("paper-m", "mpc") and full.controllers is None
    assert full.disturbance.last_push_end == pytest.approx(3.05)


def test_config_file_errors_name_the_key(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("[push_sweep]\nimpulses = [1.0]\n")
    with pytest.raises(
        ConfigurationError,
        match=r"Unknown key\(s\) \['impulses'\] in "
        r"\[push_sweep\]",
    ):
        load_config(path)
    path.write_text("parts = ['push', 'jump']\n")
    with pytest.raises(ConfigurationError, match=r"Unknown part\(s\) \['jump'\]"):
        load_config(path)


def test_controller_availability_names_what_is_missing():
    reasons = controller_availability(
        {
            "ok": ControllerSpec(generator="analytic", feedback=False, stabilizers=("gyro",)),
            "no-gen": ControllerSpec(generator="teleport"),
            "no-stab": ControllerSpec(generator="mpc", stabilizers=("reaim", "magic")),
        }
    )
    assert reasons["ok"] is None
    assert reasons["no-gen"] == "no generator 'teleport'"
    assert reasons["no-stab"] == "no stabilizer 'magic'"
    assert all(reason is None for reason in controller_availability().values())
    assert CONTROLLERS["analytic+gyro"].stabilizers == ("gyro",)
    assert CONTROLLERS["analytic+gyro"].generator == "analytic"
    assert CONTROLLERS["mpc-steps-qp-only"].generator_options == {"dcm_step_gain": 0.0}


def test_map_tasks_keeps_the_order_on_ray_workers():
    tasks = [(math.sqrt, (float(k),)) for k in (16, 1, 9, 4)]
    assert map_tasks(tasks, workers=2, progress=False) == [4.0, 1.0, 3.0, 2.0]
    assert map_tasks(tasks, workers=1, progress=False) == [4.0, 1.0, 3.0, 2.0]
    with pytest.raises(ConfigurationError, match="positive integer"):
        map_tasks(tasks, workers=0)
    # a task's own exception comes back as itself
    with pytest.raises(ValueError, match="math domain error"):
        map_tasks([(math.sqrt, (-1.0,))], workers=1, progress=False)
    # a worker that dies (here: exits) is named, never a hang
    with pytest.raises(WorkerDied):
        map_tasks([(os._exit, (3,)), (math.sqrt, (1.0,))], workers=2, progress=False)


@pytest.mark.slow
def test_the_quick_experiment_writes_its_table_report_and_figures(tmp_path):
    """`mpcwalk experiment run paper_m --quick`: paper-m and mpc on one push cell, one speed
    search, a short turning walk and the disturbances; the rows of the sweep, the table
    built from them, the figures."""
    from mpcwalk.cli import main as cli_main
    from mpcwalk.sweep import read_rows

    out = tmp_path / "paper_m"
    command = ["experiment", "run", "paper_m", "--quick", "--out", str(out), "--no-progress"]
    assert cli_main(command) == 0
    rows = {row["case_id"]: row for row in read_rows(out / "results.csv")}
    assert sorted(rows) == [
        "push/mpc/90/ss-mid",
        "push/paper-m/90/ss-mid",
        "speed/mpc/0.5",
        "speed/paper-m/0.5",
    ]
    results = json.loads((out / "results.json").read_text())
    assert results["mode"] == "quick" and list(results["controllers"]) == ["paper-m", "mpc"]
    for name in ("paper-m", "mpc"):
        cell = rows[f"push/{name}/90/ss-mid"]
        # the row's impulse is the cell's bisection result: the largest impulse it survived
        survived = [impulse for impulse, ok in cell["trials"] if ok]
        assert cell["largest_survived_Ns"] == pytest.approx(max(survived, default=0.0), abs=1e-6)
        row = next(r for r in results["rows"] if r["controller"] == name)
        assert row["impulse_median_Ns"] == pytest.approx(cell["largest_survived_Ns"])
        assert 0.0 < cell["largest_survived_Ns"] < 4.0
        speed = rows[f"speed/{name}/0.5"]
        assert 0.0 < speed["fastest_m_s"] <= speed["bound_m_s"]
        assert row["turning_yaw_rate_deg_s"] is not None and not row["turning_fell"]
        assert row["yaw_deviation_deg"] > 0.0
    report = (out / "report.md").read_text()
    assert "| paper-m |" in report and "mpcwalk experiment run paper_m --quick" in report
    assert "## Goals" in report and "neither fell nor was stopped" in report
    for name in (
        "turning_top_mpc.png",
        "turning_attitude.png",
        "disturbance_mpc.png",
        "push_polar.png",
    ):
        assert (out / name).stat().st_size > 1000
