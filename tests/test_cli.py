"""The command line: `mpcwalk plan`, `mpcwalk generators`, `mpcwalk bench ticks`, and what
a new user sees in `--help`."""

import argparse
import json
from pathlib import Path

import pytest

import mpcwalk
from mpcwalk.bench.ticks import format_table, run_tick_benchmark
from mpcwalk.cli import build_parser, main
from mpcwalk.cli.console import format_length
from mpcwalk.cli.walk_options import spec_from_args
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.walking.specification import WorldSpec


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
    # 6 steps and the closing one, named apart
    assert (metrics["nb_steps"], metrics["closing_steps"], metrics["steps_planned"]) == (6, 1, 7)
    assert 0.0 < metrics["zmp_margin_min_m"] < 0.03
    assert metrics["tick_us_median"] > 0.0
    out_text = capsys.readouterr().out
    assert "ZMP margin min" in out_text  # the planned ZMP: a ZMP, not a measured CoP
    assert "mpc: 6 steps + closing step over 5.50 s" in out_text  # 3.5 s + 2 x 1 s standing


def test_plan_of_static_gait_at_paper_m_timing_is_refused(tmp_path, capsys):
    out = tmp_path / "plan"
    code = main(
        ["plan", "--generator", "static", "--steps", "2", "--step-duration", "0.5"]
        + ["--out", str(out)]
    )
    assert code == 2
    err = capsys.readouterr().err
    assert "The static gait cannot walk this plan at T = 0.5 s, r_ds = 0.2" in err
    assert "The fastest feasible timing is a step duration of" in err
    assert not out.exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (["--vx", "0.5"], r"vx=0.5 m/s exceeds its limit"),
        (["--ds-ratio", "1.2"], r"double_support_ratio must lie in \[0, 1\)"),
        (["--step-duration", "-1"], r"step_duration must be a number of seconds in"),
        (
            ["--generator", "mpc", "--solver", "gurobo"],
            r"Unknown solver 'gurobo'; available: ",
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


@pytest.mark.slow
def test_tick_benchmark_reduced_run():
    results = run_tick_benchmark(
        nb_steps=2, solvers=["daqp"], include_peer=True, progress=False, repeats=2
    )
    labels = [r.label for r in results]
    assert {r.repeats for r in results} == {2}
    assert labels[0] == "analytic"
    for r in results:  # each median against the closed form's of the same run
        assert r.ratio_to_analytic == pytest.approx(r.median_us / results[0].median_us)
    assert {
        "mpc osqp-direct",
        "mpc casadi",
        "mpc daqp",
        "mpc-steps daqp",
        "mpc-steps quadprog (default)",
        "mpc-steps quadprog-screened",
        "mpc-timing quadprog",
        "mpc-hip quadprog",
        "mpc-hip quadprog-screened",
        "qpmpc daqp (peer)",
    } <= set(labels)
    for r in results:
        assert not r.error, (r.label, r.error)
        assert r.nb_ticks > 100 and r.median_us > 0.0 and r.p99_us >= r.median_us
        assert r.failures == 0, r.label
    table = format_table(results)
    assert table.count("\n") == len(results) + 1


def test_tick_benchmark_walks_in_rounds_and_keeps_going_past_a_failing_case(monkeypatch):
    import mpcwalk.bench.ticks as ticks

    cases = [
        ("analytic", "analytic", "", {}),
        ("broken", "mpc", "nowhere", {"solver": "nowhere"}),
        ("preview", "preview", "", {}),
    ]
    monkeypatch.setattr(ticks, "_cases", lambda solvers, include_peer: cases)
    order = []
    rollout = ticks.rollout

    def recorded(generator, schedule):
        order.append(generator.name)
        return rollout(generator, schedule)

    monkeypatch.setattr(ticks, "rollout", recorded)
    results = ticks.run_tick_benchmark(nb_steps=2, progress=False, repeats=2)
    assert order == ["analytic", "preview", "analytic", "preview"]  # round after round
    assert [r.label for r in results] == ["analytic", "broken", "preview"]
    assert "nowhere" in results[1].error and results[1].nb_ticks == 0
    assert results[0].repeats == results[2].repeats == 2 and not results[2].error
    with pytest.raises(ConfigurationError, match="repeats must be a positive integer"):
        ticks.run_tick_benchmark(nb_steps=2, progress=False, repeats=0)


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


def test_version(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out.strip() == f"mpcwalk {mpcwalk.__version__}"


def test_plan_refuses_zero_steps(tmp_path, capsys):
    assert main(["plan", "--steps", "0", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mpcwalk: error: --steps must be a number of steps in [1, 10000], got 0")
    assert not (tmp_path / "metrics.json").exists()


def _parsers(parser, path=("mpcwalk",)):
    """Every (command path, parser) of the command line."""
    yield path, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, child in action.choices.items():
                yield from _parsers(child, (*path, name))


def test_help_shows_defaults_and_no_markup(monkeypatch):
    monkeypatch.setenv("COLUMNS", "200")  # no line breaks inside a default
    parsers = dict(_parsers(build_parser()))
    assert {("mpcwalk", "walk"), ("mpcwalk", "bench", "loop")} <= set(parsers)
    for path, parser in parsers.items():
        text = parser.format_help()
        assert "`" not in text, (path, text)  # no reST or markdown backticks
        assert "default: None" not in text, path
    walk = " ".join(parsers["mpcwalk", "walk"].format_help().split())
    for default in ("(default: bioloid-like)", "(default: mpc)", "(default: 0.01)"):
        assert default in walk
    assert "(default: mpc)" in parsers["mpcwalk", "plan"].format_help()


@pytest.mark.parametrize("command", ["ticks", "ik", "loop"])
def test_every_bench_option_has_help(command):
    parser = dict(_parsers(build_parser()))["mpcwalk", "bench", command]
    for action in parser._actions:
        assert action.help, (command, action.option_strings)


def test_lengths_print_with_their_digits():
    assert format_length(4e-6) == "0.004 mm"  # not "0.00 cm"
    assert format_length(-0.0123) == "-12.3 mm"
    assert format_length(None) == "n/a"


def test_walk_help_shows_the_sensor_and_world_options(monkeypatch):
    monkeypatch.setenv("COLUMNS", "200")
    walk = dict(_parsers(build_parser()))["mpcwalk", "walk"]
    text = " ".join(walk.format_help().split())
    assert "sensors and world:" in text
    text = text.split("sensors and world:", 1)[1]
    for option, default in (
        ("--noise-scale X", "default: 1)"),
        ("--latency S", "(default: one control period)"),
        ("--state {estimator,oracle}", "(default: estimator; oracle with --ideal)"),
        ("--mass-scale X", "(default: 1)"),
        ("--com-offset DX,DY", "(default: 0,0)"),
        ("--friction MU", "(default: the robot model's)"),
        ("--servo-strength X", "(default: 1)"),
        ("--seed N", "(default: 0)"),
    ):
        assert option in text and default in text.split(option, 1)[1][:300], option
    assert "--ideal" in text


def test_walk_world_options_map_onto_the_spec():
    args = build_parser().parse_args(
        [
            "walk",
            "--out",
            "x",
            "--steps",
            "2",
            "--noise-scale",
            "2",
            "--latency",
            "0.02",
            "--state",
            "oracle",
            "--mass-scale",
            "1.3",
            "--com-offset",
            "0.01,-0.005",
            "--friction",
            "0.4",
            "--servo-strength",
            "0.8",
            "--seed",
            "5",
        ]
    )
    spec = spec_from_args(args, out=Path("x"))
    assert spec.world == WorldSpec(
        noise_scale=2.0,
        latency=0.02,
        ideal=False,
        state="oracle",
        mass_scale=1.3,
        com_offset=(0.01, -0.005),
        friction=0.4,
        servo_strength=0.8,
    )
    assert spec.run.seed == 5
    args = build_parser().parse_args(["walk", "--out", "x", "--steps", "2"])
    defaults = spec_from_args(args, out=Path("x"))
    assert defaults.world == WorldSpec() and defaults.world.state == "estimator"
    assert defaults.world.com_offset == (0.0, 0.0) and defaults.run.seed == 0


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--com-offset", "0.01"], "--com-offset takes two numbers DX,DY in metres, got '0.01'"),
        (["--noise-scale", "-1"], "noise_scale must be a finite number >= 0"),
        (["--latency", "0.015"], "latency = 0.015 s is not a multiple of the control period"),
        (["--ideal", "--noise-scale", "2"], "ideal sensors have no noise and no latency"),
        (["--mass-scale", "0"], r"ModelMismatch.mass_scale must be a number in [0.1, 10]"),
        (["--friction", "-1"], r"ModelMismatch.friction must be a number in [0.01, 10]"),
        (["--seed", "-2"], "seed must be an integer >= 0"),
    ],
)
def test_walk_bad_world_options_exit_with_code_2(tmp_path, capsys, argv, message):
    code = main(["walk", "--out", str(tmp_path / "out"), "--steps", "1", "--no-progress", *argv])
    assert code == 2
    err = capsys.readouterr().err
    assert err.startswith("mpcwalk: error: ") and message in err, err
    assert not (tmp_path / "out" / "metrics.json").exists()


#: The methods that build an argparse parser.
_PARSER_CALLS = {
    "add_argument",
    "add_argument_group",
    "add_mutually_exclusive_group",
    "add_subparsers",
}


def _imports_and_parser_calls(path: Path) -> tuple[set[str], set[str]]:
    """The modules a source file imports (at its top or inside a function), and the
    argparse-building methods it calls."""
    import ast

    modules: set[str] = set()
    calls: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            modules.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            modules.add(node.module)
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            if node.func.attr in _PARSER_CALLS:
                calls.add(node.func.attr)
    return modules, calls


def test_argparse_lives_in_the_command_line_package_only():
    package = Path(mpcwalk.__file__).parent
    sources = [p for p in package.rglob("*.py") if p.relative_to(package).parts[0] != "cli"]
    assert len(sources) > 100
    offenders = []
    for path in sources:
        modules, calls = _imports_and_parser_calls(path)
        if calls or any(name.split(".")[0] == "argparse" for name in modules):
            offenders.append(str(path.relative_to(package)))
    assert not offenders, f"argparse outside mpcwalk/cli/: {offenders}"
    modules, calls = _imports_and_parser_calls(package / "cli" / "bench.py")
    assert "argparse" in modules and "add_argument" in calls  # the scan sees them


def test_every_command_runs_through_a_run_of_the_cli_package():
    parser = build_parser()
    for argv in (
        ["bench", "ticks"],
        ["bench", "ik", "--robots", "g1", "--no-pink"],
        ["bench", "loop"],
        ["bench", "solvers", "--out", "x"],
        ["experiment", "list"],
        ["experiment", "run", "paper_m", "--out", "x"],
        ["experiment", "scaling", "robustness", "--out", "x"],
    ):
        run = parser.parse_args(argv).run
        assert run.__module__.startswith("mpcwalk.cli."), (argv, run.__module__)
