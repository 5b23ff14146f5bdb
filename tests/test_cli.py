"""The command line: `mpcwalk plan`, `mpcwalk generators`, `mpcwalk bench ticks`."""

import json

import pytest

from mpcwalk.bench.ticks import format_table, run_tick_benchmark
from mpcwalk.cli import main


def test_plan_writes_plots_and_metrics(tmp_path, capsys):
    out = tmp_path / "plan"
    code = main(
        [
            "plan",
            "--generator",
            "mpc",
            "--vx",
            "0.1",
            "--vy",
            "0",
            "--vyaw",
            "0.35",
            "--steps",
            "6",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    assert (out / "top_view.png").stat().st_size > 10_000
    assert (out / "com_zmp.png").stat().st_size > 10_000
    metrics = json.loads((out / "metrics.json").read_text())
    for key in ("generator", "nb_steps", "zmp_margin_min_m", "com_margin_min_m", "tick_us_median"):
        assert key in metrics
    assert metrics["generator"] == "mpc"
    assert metrics["nb_steps"] == 7  # 6 steps and the closing one
    assert 0.0 < metrics["zmp_margin_min_m"] < 0.03
    assert metrics["tick_us_median"] > 0.0
    assert "ZMP margin min" in capsys.readouterr().out


def test_plan_of_static_gait_at_paper_m_speed_warns(tmp_path, capsys):
    code = main(["plan", "--generator", "static", "--steps", "2", "--out", str(tmp_path)])
    assert code == 0
    metrics = json.loads((tmp_path / "metrics.json").read_text())
    assert metrics["zmp_margin_min_m"] < 0.0 < metrics["com_margin_min_m"]
    assert "leaves the support polygon" in capsys.readouterr().err


@pytest.mark.parametrize(
    "args, message",
    [
        (["--vx", "0.5"], r"vx=0.5 m/s exceeds its limit"),
        (["--ds-ratio", "1.2"], r"double_support_ratio must lie in \[0, 1\)"),
        (["--step-duration", "-1"], r"step_duration must be a positive number"),
        (
            ["--generator", "mpc", "--solver", "gurobo"],
            r"'gurobo' is not available; the available solvers are",
        ),
        (["--generator", "zmp-magic"], r"Unknown pattern generator 'zmp-magic'"),
    ],
)
def test_bad_input_is_a_named_error_not_a_traceback(tmp_path, capsys, args, message):
    code = main(["plan", "--steps", "2", "--out", str(tmp_path), *args])
    assert code == 2
    err = capsys.readouterr().err
    assert err.startswith("mpcwalk: error: ")
    assert __import__("re").search(message, err), err
    assert "Traceback" not in err


def test_generators_lists_every_name(capsys):
    assert main(["generators"]) == 0
    out = capsys.readouterr().out
    for name in ("analytic", "static", "preview", "mpc", "static-qp", "mpc-steps"):
        assert name in out


def test_tick_benchmark_reduced_run():
    results = run_tick_benchmark(nb_steps=2, solvers=["daqp"], include_peer=True, progress=False)
    labels = [r.label for r in results]
    assert labels[0] == "analytic" and results[0].ratio_to_analytic == 1.0
    assert {
        "mpc osqp-direct",
        "mpc casadi",
        "mpc daqp",
        "mpc-steps daqp",
        "mpc-steps quadprog",
        "qpmpc daqp (peer)",
    } <= set(labels)
    for r in results:
        assert not r.error, (r.label, r.error)
        assert r.nb_ticks > 100 and r.median_us > 0.0 and r.p99_us >= r.median_us
        assert r.failures == 0, r.label
    table = format_table(results)
    assert table.count("\n") == len(results) + 1


def test_bench_commands_write_their_markdown_and_json(tmp_path, capsys):
    import json

    assert (
        main(
            [
                "bench",
                "ticks",
                "--steps",
                "2",
                "--solvers",
                "daqp",
                "--no-peer",
                "--no-progress",
                "--out",
                str(tmp_path / "ticks"),
            ]
        )
        == 0
    )
    assert (
        main(
            [
                "bench",
                "ik",
                "--robots",
                "bioloid-like",
                "--duration",
                "0.3",
                "--no-pink",
                "--no-progress",
                "--out",
                str(tmp_path / "ik"),
            ]
        )
        == 0
    )
    for name in ("ticks", "ik"):
        text = (tmp_path / name / f"{name}.md").read_text()
        rows = json.loads((tmp_path / name / f"{name}.json").read_text())
        assert f"Command: `mpcwalk bench {name}" in text and "cores, Python" in text
        assert rows and text.count("\n| ") >= len(rows)  # a table row per result
    out = capsys.readouterr().out
    assert "wrote " in out and "ticks.json" in out and "ik.json" in out
