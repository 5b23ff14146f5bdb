"""The solver benchmark (`mpcwalk bench solvers`): a reduced run, the qpbenchmark
export, the tolerance conventions and the statistics."""

import csv
import gzip
import importlib.util
import math
import re
import subprocess
import sys

import numpy as np
import pytest
import scipy.sparse as sp

from mpcwalk.bench.solvers.backends.registry import is_applicable, supports_warm_start
from mpcwalk.bench.solvers.backends.settings import backend_settings
from mpcwalk.bench.solvers.benchmark import make_cases, run_solver_benchmark
from mpcwalk.bench.solvers.config import DYNAMICS_FAMILY, SolverBenchConfig
from mpcwalk.bench.solvers.loops.plants import mujoco_walk_runner
from mpcwalk.bench.solvers.peers.qpbenchmark_export import (
    build_problem,
    export_test_set,
    load_problem,
)
from mpcwalk.bench.solvers.problems.families import get_family
from mpcwalk.bench.solvers.problems.sampling import reference_walk, sample_problems
from mpcwalk.bench.solvers.results import (
    RESULTS_FILE,
    fit_exponent,
    read_results,
    select,
    shgeom_runtimes,
    shifted_geometric_mean,
)
from mpcwalk.bench.solvers.solves.cases import CSV_COLUMNS, CaseSolver, SolverCase
from mpcwalk.bench.solvers.solves.timed import TimedSolves
from mpcwalk.bench.solvers.tolerances import select_levels, tolerance_levels
from mpcwalk.exceptions import ConfigurationError

BACKENDS = ("osqp-direct", "daqp", "proxqp")


@pytest.fixture(scope="module")
def problems():
    ref = reference_walk("mpc", "turning", 4)
    return sample_problems(ref, [16], nb_nominal=1, nb_pushed=1)


@pytest.fixture(scope="module")
def reduced_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("solvers")
    config = SolverBenchConfig(
        families=("mpc", "static-qp", DYNAMICS_FAMILY),  # the MPC rows, then the ID stage
        walks=("turning",),
        nb_steps=4,
        nb_nominal=1,
        nb_pushed=1,
        sweep_horizons=(16, 32, 64),
        sweep_nb_nominal=1,
        sweep_nb_pushed=0,
        sweep_levels=("default",),
        levels=("default", "mid"),
        backends=BACKENDS,
        ticks=False,
        qpbenchmark_solvers=("daqp", "proxqp"),
        export_max_horizon=32,
        loop_pushes=1,
        loop_nb_steps=4,
        loop_backends_max_time=1e-3,
        dynamics_robots=("bioloid-like",),
        dynamics_nb_steps=2,
        dynamics_nb_per_phase=1,
        dynamics_nb_pushed=0,
        dynamics_loop_nb_steps=2,
    )
    summary = run_solver_benchmark(config, out, progress=False, command="pytest")
    return out, config, summary, read_results(out / RESULTS_FILE)


@pytest.mark.slow
def test_results_csv_has_one_row_per_case(reduced_run):
    out, _config, summary, rows = reduced_run
    with gzip.open(out / RESULTS_FILE, "rt") as stream:
        assert tuple(next(csv.reader(stream))) == CSV_COLUMNS
    keys = [(r["problem"], r["formulation"], r["solver"], r["tolerance"], r["start"]) for r in rows]
    assert len(keys) == len(set(keys)) == summary["rows"]
    # main set: 2 families x 2 snapshots x (3 + 2 sparse back-ends) x 2 levels x starts,
    # sweep: 1 snapshot at N = 16 and 64 (N = 32 is the main set's), default level only.
    cold_main = 2 * 2 * (3 + 2) * 2
    warm_main = 2 * 2 * (2 + 2) * 2  # osqp-direct and proxqp, both formulations
    sweep = 2 * (5 + 4)
    assert len(rows) == cold_main + warm_main + sweep
    assert not select(rows, solver="daqp", formulation="sparse")  # needs a definite P
    assert {r["horizon"] for r in rows} == {16, 32, 64}
    for r in rows:
        assert r["n"] == (2 if r["formulation"] == "dense" else 8) * r["horizon"]


@pytest.mark.slow
def test_reduced_run_succeeds_on_every_problem(reduced_run):
    _, _, _, rows = reduced_run
    failed = [
        (r["problem"], r["formulation"], r["solver"], r["tolerance"], r["start"], r["status"])
        for r in rows
        if not r["success"]
        and not (
            r["solver"] == "osqp-direct"
            and r["start"] == "cold"
            and r["formulation"] == "dense"
            and r["horizon"] == 64
        )
    ]
    assert failed == []
    mid = select(rows, tolerance="mid")
    assert {r["solver"] for r in mid} == set(BACKENDS)  # a row for every back-end
    for r in mid:
        assert max(r["primal_residual"], r["dual_residual"], r["duality_gap"]) < 1e-6
        # timed, and the status columns agree: found, no timeout, no error or skip
        assert math.isfinite(r["runtime"]) and r["runtime"] > 0.0
        assert r["found"] and r["success"] and not r["timeout"]
        assert not r["status"].startswith(("error", "skipped")), r["status"]


@pytest.mark.slow
def test_report_has_the_tables_and_figures(reduced_run):
    out, _, _, _ = reduced_run
    report = (out / "report.md").read_text()
    for heading in (
        "## Headline",
        "## Success rate per tolerance level",
        "## Runtime: shifted geometric mean",
        "## Runtime per family",
        "## Growth with the horizon",
        "## In the loop",
        "## qpbenchmark test set",
    ):
        assert heading in report
    assert "| daqp | 100 | 100 |" in report
    assert "exponent N>=64" in report
    for figure in ("success_rates.png", "time_vs_horizon.png", "tick_histograms.png"):
        assert (out / figure).stat().st_size > 10_000
    assert "| lipm | daqp | dense |" in report
    # the inverse-dynamics stage: its own report, a section of this one
    assert "## Inverse dynamics (torque control)" in report
    assert "[inverse_dynamics.md](inverse_dynamics.md)" in report
    dynamics = (out / "inverse_dynamics.md").read_text()
    assert "| bioloid-like | double | 1 | 36 x 78 (18 eq.) |" in dynamics
    assert "| daqp | 100% | - |" in dynamics and "| osqp-direct | 100% | 100% |" in dynamics
    if mujoco_walk_runner() is not None:
        assert "| daqp | dense | 450 |" in report  # MuJoCo: 4 steps + closing one, 4.5 s
        assert "| no | 5/5 |" in report
    assert (out / "qpbenchmark" / "mpcwalk_qpbenchmark.py").exists()
    if importlib.util.find_spec("qpbenchmark") is not None:  # the `bench` extra
        assert "qpbenchmark/results/mpcwalk_qpbenchmark.md" in report
        assert (out / "qpbenchmark" / "results" / "mpcwalk_qpbenchmark.md").exists()
        assert re.search(r"\| daqp( \| 100% \/ [0-9.]+){4} \|", report)  # success, any time


@pytest.mark.parametrize("family", ["mpc", "static-qp"])
def test_problems_are_the_qps_the_controller_solves(family):
    """The QP rebuilt at a sampled tick is the generator's own QP at that tick."""
    from mpcwalk.generators import make_generator

    ref = reference_walk(family, "turning", 4)
    problem = sample_problems(
        ref, [get_family(family).parameters.horizon], nb_nominal=1, nb_pushed=0
    )[0]
    fam = get_family(family)
    generator = make_generator(fam.generator, control_period=0.01, **fam.generator_options())
    generator.reset(problem.schedule())
    for _ in range(problem.tick + 1):  # the QP of tick k is built in the (k+1)-th step
        generator.step()
    qp = fam.build_qp(problem.horizon, "dense", problem.control_period)
    fam.update_qp(qp, problem.state, problem.time, problem.schedule())
    np.testing.assert_allclose(qp.q, generator.qp.q, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(qp.u, generator.qp.u, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(qp.A_data, generator.qp.A_data)


def test_qpbenchmark_export_round_trips(problems, tmp_path):
    pairs = [(p, f) for p in problems for f in ("dense", "sparse")]
    names = export_test_set(pairs, tmp_path)
    assert (tmp_path / "mpcwalk_qpbenchmark.py").exists()
    for (problem, formulation), name in zip(pairs, names):
        loaded = load_problem(tmp_path / "data" / f"{name}.npz")
        original = build_problem(problem, formulation)
        np.testing.assert_array_equal(loaded.P, original.P.toarray())
        np.testing.assert_array_equal(loaded.q, original.q)
        np.testing.assert_array_equal(loaded.G, original.G.toarray())
        np.testing.assert_array_equal(loaded.h, original.h)
        if formulation == "dense":
            assert loaded.A is None and loaded.b is None
        else:
            np.testing.assert_array_equal(loaded.A, original.A.toarray())
            np.testing.assert_array_equal(loaded.b, original.b)
        assert loaded.lb is None and loaded.ub is None


def test_walking_test_set_yields_the_exported_problems(problems, tmp_path):
    pytest.importorskip("qpbenchmark")
    from mpcwalk.bench.solvers.peers.qpbenchmark_test_set import WalkingTestSet

    names = export_test_set([(problems[0], "dense")], tmp_path)
    test_set = WalkingTestSet(tmp_path / "data", solvers=["daqp", "nonexistent"], time_limit=2.0)
    assert [p.name for p in test_set] == names
    assert test_set.solvers == {"daqp"}
    assert test_set.tolerances["mid_accuracy"].primal == 1e-6
    assert test_set.tolerances["default"].runtime == 2.0


def test_tolerance_levels_follow_qpbenchmark():
    levels = tolerance_levels(0.5)
    assert [levels[n].primal for n in ("default", "low", "mid", "high")] == [1.0, 1e-3, 1e-6, 1e-9]
    mid = levels["mid"]
    assert mid.qpbenchmark_name == "mid_accuracy"
    assert mid.is_success(True, 1e-7, 1e-7, 1e-7, 0.1)
    assert not mid.is_success(True, 1e-7, None, 1e-7, 0.1)  # no dual: cannot be checked
    assert not mid.is_success(True, 1e-7, 1e-7, 2e-6, 0.1)
    assert not mid.is_success(False, 0.0, 0.0, 0.0, 0.1)
    assert not mid.is_success(True, 0.0, 0.0, 0.0, 0.6)  # over the time limit
    assert backend_settings("osqp-direct", mid) == {
        "time_limit": 0.5,
        "eps_abs": 1e-6,
        "eps_rel": 0.0,
    }
    assert backend_settings("daqp", mid)["primal_tol"] == 1e-6
    assert not is_applicable("daqp", "sparse") and is_applicable("daqp", "dense")
    assert supports_warm_start("osqp-direct") and not supports_warm_start("daqp")
    with pytest.raises(ConfigurationError, match="Unknown tolerance level.*default, low, mid"):
        select_levels(["medium"])
    with pytest.raises(ConfigurationError, match="positive number of seconds"):
        tolerance_levels(0.0)


def test_bad_configuration_names_the_known_values():
    with pytest.raises(ConfigurationError, match="Unknown problem family 'mpc-adaptive'.*mpc"):
        get_family("mpc-adaptive")
    with pytest.raises(ConfigurationError, match="Unknown walk 'backwards'"):
        SolverBenchConfig(walks=("backwards",))


def test_shifted_geometric_mean_and_exponent_fit():
    assert shifted_geometric_mean([1.0, 1.0], 10.0) == pytest.approx(1.0)
    assert shifted_geometric_mean([0.0, 80.0], 1.0) == pytest.approx(math.sqrt(81.0) - 1.0)
    horizons = np.array([16, 32, 64, 320])
    assert fit_exponent(horizons, 3e-6 * horizons**1.5) == pytest.approx(1.5)
    assert math.isnan(fit_exponent([16, 32], [1.0, 2.0]))
    rows = [
        dict(solver=s, tolerance="mid", runtime=t, found=f, timeout=False)
        for s, t, f in (
            ("a", 0.001, True),
            ("a", 0.002, True),
            ("b", 0.001, True),
            ("b", 0.5, False),
        )
    ]
    means = shgeom_runtimes(rows, "mid", time_limit=1.0)
    assert means["a"][0] == 1.0
    assert means["b"][1] == pytest.approx(math.sqrt(10.001 * 11.0) - 10.0)  # failure = limit


def test_timeouts_are_recorded_and_their_group_skipped(problems):
    config = SolverBenchConfig(
        levels=("mid",), starts=("cold",), formulations=("dense",), time_limit=1e-9
    )
    cases = make_cases([(p, "main") for p in problems] * 2, config, ["quadprog"])
    rows = TimedSolves(1).run(cases, progress=False)
    assert [r["timeout"] for r in rows] == [True] * 4
    assert [r["status"].startswith("skipped") for r in rows] == [False, False, True, True]
    assert not any(r["success"] for r in rows)


def test_case_solver_turns_errors_into_failed_rows(problems):
    level = tolerance_levels()["default"]
    row = CaseSolver().solve(SolverCase(problems[0], "sparse", "quadprog", level, "cold"))
    assert not row["found"] and not row["success"]
    assert row["status"].startswith("error: ConfigurationError")


def test_matrices_given_to_solvers_do_not_share_the_pattern():
    """A solver that edits its input in place (qpsolvers' sip calls
    eliminate_zeros) must not corrupt the QP's fixed pattern and values."""
    qp = get_family("mpc").build_qp(16, "sparse", 0.01)
    pattern = qp.layout.P_pattern
    indptr, data = pattern.indptr.copy(), qp.P_data.copy()
    P = pattern.matrix(qp.P_data)
    assert sp.issparse(P) and P.nnz == len(data)
    P.eliminate_zeros()
    P.data[:] = 0.0
    np.testing.assert_array_equal(pattern.indptr, indptr)
    np.testing.assert_array_equal(qp.P_data, data)


def test_importing_the_benchmark_leaves_the_solver_names_alone():
    """The benchmark's own back-end (CasADi's Opti layer) lives in the benchmark's registry:
    importing every module of ``mpcwalk.bench`` adds no name to the project's registry, so
    the names a walk accepts do not depend on what was imported (a fresh interpreter: this
    one may have imported the benchmark already)."""
    code = """
import importlib, pkgutil
from mpcwalk.qp.solvers import SOLVERS, solver_names
before = (SOLVERS.names(available=False), solver_names())
import mpcwalk.bench
for module in pkgutil.walk_packages(mpcwalk.bench.__path__, "mpcwalk.bench."):
    try:
        importlib.import_module(module.name)
    except ModuleNotFoundError as error:  # the optional qpbenchmark
        assert error.name == "qpbenchmark", error
from mpcwalk.bench.solvers.backends.registry import OPTI_BACKEND, benchmark_registry
assert OPTI_BACKEND in benchmark_registry() and OPTI_BACKEND not in SOLVERS
assert benchmark_registry().names(available=False)[:-1] == before[0]
print(before == (SOLVERS.names(available=False), solver_names()), len(before[0]))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    same, count = out.stdout.split()
    assert same == "True" and int(count) > 10
