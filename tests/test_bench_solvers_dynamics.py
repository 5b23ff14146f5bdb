"""The inverse-dynamics stage of the solver benchmark: the snapshots are the QPs the torque
controller solved, every back-end is judged on them, the in-loop walk records its fields,
and the options that choose the stage and the back-end are checked."""

import dataclasses
import math

import numpy as np
import pytest

from mpcwalk.bench.solvers.config import DYNAMICS_FAMILY, SolverBenchConfig
from mpcwalk.bench.solvers.dynamics.capture import (
    capture_walk,
    classify_ticks,
    sample_dynamics_problems,
)
from mpcwalk.bench.solvers.dynamics.loops import LOOP_FIELDS, loop_backends, run_dynamics_loop
from mpcwalk.bench.solvers.dynamics.report import level_table
from mpcwalk.bench.solvers.dynamics.solves import (
    DynamicsSolves,
    dynamics_backends,
    dynamics_cases,
)
from mpcwalk.cli import main
from mpcwalk.control.torque_controller import TorqueController
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.dynamics_program import check_dynamics_solver, dynamics_solver_names
from mpcwalk.qp.solvers.registry import make_solver
from mpcwalk.walking.controller_builder import check_controller
from mpcwalk.walking.specification import ControllerSpec


@pytest.fixture(scope="module")
def captured():
    walk = capture_walk("bioloid-like", nb_steps=2, vx=0.1)
    problems = sample_dynamics_problems(
        walk.recorder,
        "bioloid-like",
        control_period=0.01,
        nb_per_phase=1,
        nb_pushed=1,
        push_speed=0.1,
        warmup_ticks=2,
    )
    return walk, problems


def test_the_walk_is_recorded_and_every_phase_sampled(captured):
    walk, problems = captured
    assert not walk.fell and walk.steps == "3/3"
    assert len(walk.recorder.states) == len(walk.recorder.results) > 100  # measured 351
    assert [p.phase for p in problems] == ["double", "single", "touch-down", "single"]
    assert [p.pushed for p in problems] == [False, False, False, True]
    single, pushed = problems[1], problems[3]
    assert single.qp.contacts.count(True) == 1 and problems[0].qp.contacts == (True, True)
    assert np.linalg.norm(pushed.push) == pytest.approx(0.1)
    assert all(len(p.warmup) == 2 for p in problems)


@pytest.mark.parametrize("index", [0, 1, 2])
def test_snapshots_reproduce_the_live_solution(captured, index):
    problem = captured[1][index]
    solves = DynamicsSolves()
    torques = {}
    for name in ("daqp-direct", "quadprog"):
        result = make_solver(name).solve(solves.program(problem.qp))
        assert result.success, name
        x = np.asarray(result.x)
        # the floating base's equations of motion: M_b a + h_b = sum_i J_i,b^T f_i
        assert np.abs(problem.generalized_forces(x)[:6]).max() < 1e-9  # measured 1e-13
        torques[name] = problem.torques(x)
    assert problem.live_torques is not None
    # the walk's own solve (daqp-direct, warm) and the snapshot solved again, cold
    assert np.abs(torques["daqp-direct"] - problem.live_torques).max() < 1e-6  # measured 0
    assert np.abs(torques["quadprog"] - torques["daqp-direct"]).max() < 1e-6  # measured 8e-12 N m
    assert np.abs(problem.live_torques).max() > 0.1  # measured 0.26 to 0.59 N m


def test_a_pushed_snapshot_is_another_qp(captured):
    pushed = captured[1][3]
    assert pushed.live_torques is None
    assert pushed.tick not in [p.tick for p in captured[1][:3]]
    x = make_solver("quadprog").solve(DynamicsSolves().program(pushed.qp)).x
    assert np.abs(pushed.generalized_forces(np.asarray(x))[:6]).max() < 1e-9


def test_every_backend_is_judged_cold_and_warm(captured):
    problem = captured[1][2]  # a touch-down ramp: the contacts changed before it
    backends = ["daqp-direct", "quadprog"]
    cases = dynamics_cases([problem], backends, ("default", "high"), ("cold", "warm"), 1.0)
    assert [(b, lv.name, s) for _, b, lv, s in cases].count(("quadprog", "high", "warm")) == 0
    assert len(cases) == 6  # quadprog takes no initial guess: no warm case
    rows = DynamicsSolves().run(cases)
    for row in rows:
        assert row["success"], row
        assert row["torque_error"] < 1e-6  # measured 8e-12 N m against quadprog
        assert abs(row["cost_gap"]) < 1e-9
        assert row["primal_residual"] < 1e-9
        assert row["runtime"] > 0.0
        assert math.isnan(row["warmup_runtime"]) == (row["start"] == "cold")
    broken = DynamicsSolves().run([(problem, "no-such-solver", cases[0][2], "cold")])
    assert not broken[0]["success"] and broken[0]["status"].startswith("error: SolverNotFound")


def test_the_backends_of_the_stage_take_the_qp():
    names = dynamics_backends()
    assert names[0] == "daqp-direct" and "kkt" not in names and "quadprog" in names
    assert dynamics_backends(("kkt", "quadprog", "unknown")) == ["quadprog"]


def test_level_table_ranks_by_median_and_gives_the_ratio():
    def row(solver, runtime, success=True):
        return {
            "solver": solver,
            "tolerance": "default",
            "start": "cold",
            "runtime": runtime,
            "success": success,
            "torque_error": 0.0,
            "cost_gap": 0.0,
            "base_residual": 0.0,
        }

    rows = [row("slow", 4e-4), row("slow", 6e-4), row("fast", 1e-4), row("fast", 1e-4)]
    rows += [row("flaky", 1e-5), row("flaky", 1.0, success=False)]
    text, stats = level_table(rows, ["slow", "fast", "flaky"], "default")
    assert [s[0] for s in stats] == ["flaky", "fast", "slow"]
    assert "| slow | 100% | - | 500 us |" in text
    assert "| 5.0 |" in text  # 500 us over the fastest back-end succeeding on 95 %: 100 us
    assert "| flaky | 50% |" in text


def test_in_loop_walk_records_its_fields():
    run = run_dynamics_loop("quadprog", nb_steps=2)
    assert set(run) == set(LOOP_FIELDS)
    assert run["steps"] == "3/3" and run["fell"] is False and run["error"] == ""
    assert run["dynamics_failures"] == 0 and run["nb_ticks"] > 100  # measured 351
    assert 0.0 < run["solve_median_us"] < run["tick_median_us"] <= run["tick_p99_us"]
    assert run["real_time_factor"] > 0.0
    bad = run_dynamics_loop("kkt", nb_steps=2)
    assert bad["fell"] and "dynamics_solver must be" in bad["error"]


def test_loop_backends_are_the_ones_that_succeeded_offline():
    rows = [
        {"solver": s, "robot": "r", "tolerance": "default", "start": "cold", "success": ok}
        for s, ok in [("a", True), ("a", True), ("b", True), ("b", False)]
    ]
    assert loop_backends(rows, "r", 0.95) == ["a"]
    assert loop_backends(rows, "r", 0.5) == ["a", "b"]
    assert loop_backends(rows, "other", 0.5) == []


def test_the_dynamics_solver_option_is_validated(bioloid):
    assert check_dynamics_solver("quadprog") == "quadprog"
    assert "daqp-direct" in dynamics_solver_names() and "kkt" not in dynamics_solver_names()
    with pytest.raises(ConfigurationError, match="dynamics_solver must be.*got 'nope'.*quadprog"):
        check_dynamics_solver("nope")
    spec = ControllerSpec(generator="mpc", controller_options={"dynamics_solver": "kkt"})
    with pytest.raises(ConfigurationError, match="got 'kkt'; the choices.*daqp-direct"):
        check_controller(spec, "torque")
    good = dataclasses.replace(spec, controller_options={"dynamics_solver": "quadprog"})
    check_controller(good, "torque")
    with pytest.raises(ConfigurationError, match="actuation is 'position'.*--actuation torque"):
        check_controller(good, "position")
    with pytest.raises(ConfigurationError, match="dynamics_solver must be"):
        TorqueController.for_robot(
            bioloid, "mpc", _schedule(), dynamics_solver="nope", state_delay=0.01
        )


def _schedule():
    from mpcwalk import ContactSchedule, VelocityCommand, VelocityPlanner

    return ContactSchedule(VelocityPlanner().plan(VelocityCommand(0.1, 0.0, 0.0), nb_steps=2))


def test_the_family_option_chooses_the_stage(tmp_path, capsys):
    alone = SolverBenchConfig(families=(DYNAMICS_FAMILY,))
    assert alone.dynamics and alone.mpc_families == ()
    default = SolverBenchConfig()
    assert default.dynamics and default.mpc_families == ("mpc", "mpc-dcm", "mpc-tick", "static-qp")
    assert not SolverBenchConfig(families=("mpc",)).dynamics
    code = main(["bench", "solvers", "--families", "inverse-dynamic", "--out", str(tmp_path)])
    assert code == 2
    err = capsys.readouterr().err
    assert "Unknown problem family 'inverse-dynamic'" in err and "inverse-dynamics" in err
    assert not any(tmp_path.iterdir())


def test_ticks_are_classified_by_the_sole_loads():
    weights = np.array([[1, 1], [1, 0.5], [1, 0], [1, 0], [1, 0.25], [1, 0.5], [1, 1], [0.5, 1]])
    assert classify_ticks(weights) == [
        "double",
        "other",  # the right sole's load falls before its lift-off
        "single",
        "single",
        "touch-down",
        "touch-down",
        "double",
        "other",
    ]


def test_the_walk_command_takes_the_dynamics_solver(tmp_path, capsys):
    out = str(tmp_path / "walk")
    walk = ["walk", "--robot", "bioloid-like", "--steps", "2", "--out", out]
    assert main([*walk, "--actuation", "torque", "--dynamics-solver", "kkt"]) == 2
    assert "got 'kkt'; the choices on this installation are" in capsys.readouterr().err
    assert main([*walk, "--dynamics-solver", "quadprog"]) == 2  # a position-servo walk
    assert "actuation is 'position'" in capsys.readouterr().err
