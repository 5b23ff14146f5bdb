"""Every bad input is refused before anything runs, with a named error (what was expected,
what came, the fix): exit code 2 on the command line, a ConfigurationError (an MpcwalkError)
from the API, and nothing left in --out. ``mpcwalk experiment run faults`` tallies these cases
into ``results/faults/README.md``."""

import math
import os

import pytest

from mpcwalk.cli import main
from mpcwalk.exceptions import MpcwalkError
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, StepTiming
from mpcwalk.footsteps.velocity_planner import VelocityCommand
from mpcwalk.generators import make_generator
from mpcwalk.sim import parse_push
from mpcwalk.sim.sensing.faults import SensorFaults
from mpcwalk.walking.runner import run_walk
from mpcwalk.walking.specification import WalkSpec

WALK = ["walk", "--robot", "bioloid-like", "--no-progress"]

#: (arguments of mpcwalk, what the error message says); each must exit 2 before running.
CLI_CASES = [
    (["walk", "--steps", "2", "--out", "{tmp}/afile"], "exists and is not a folder"),
    (["walk", "--steps", "2", "--out", "{tmp}/afile/sub"], "is a file, not a folder"),
    (["walk", "--steps", "2", "--out", "/proc/mpcwalk-x"], "cannot be created"),
    (["walk", "--steps", "2", "--out", ""], "an output folder is needed"),
    (["walk", "--duration", "1e9", "--out", "{out}"], r"duration must be a number in \(0, 3600\]"),
    (["walk", "--steps", "100000000", "--out", "{out}"], "nb_steps must be at most 10000"),
    (["walk", "--steps", "0", "--out", "{out}"], "nb_steps must be a positive integer"),
    (["walk", "--steps", "2", "--step-duration", "1e6", "--out", "{out}"], "step_duration"),
    (["walk", "--steps", "2", "--step-duration", "0.01", "--out", "{out}"], "10 control periods"),
    (["walk", "--steps", "2", "--step-height", "0", "--out", "{out}"], "step_height must be"),
    (["walk", "--steps", "2", "--arm-swing", "100", "--out", "{out}"], "arm_swing must be"),
    (["walk", "--steps", "2", "--control-period", "1.0", "--out", "{out}"], "control_period"),
    (["walk", "--steps", "2", "--push", "100,0.1,5,0,0", "--out", "{out}"], "after the walk"),
    (["walk", "--steps", "2", "--push", "1,0.1,1e30,0,0", "--out", "{out}"], "times the weight"),
    (["walk", "--steps", "2", "--push", "1,0.1,5", "--out", "{out}"], "fields instead of 5"),
    (
        ["walk", "--steps", "2", "--generator", "analytic", "--solver", "daqp", "--out", "{out}"],
        "takes no option 'solver'",
    ),
    (["walk", "--steps", "2", "--solver", "gurobo", "--out", "{out}"], "Unknown solver"),
    (["walk", "--steps", "2", "--generator", "zmp-magic", "--out", "{out}"], "Unknown pattern"),
    (["walk", "--steps", "2", "--controller", "paper-x", "--out", "{out}"], "Unknown controller"),
    (["walk", "--steps", "2", "--stabilizer", "hover", "--out", "{out}"], "Unknown stabilizer"),
    (["walk", "--spec", "{tmp}/missing.toml", "--out", "{out}"], "missing.toml.*no such file"),
    (["walk", "--spec", "{tmp}/short.mdat", "--out", "{out}"], "not a TOML file"),
    (["walk", "--spec", "{tmp}/typo.toml", "--out", "{out}"], r"no field 'nb_step'.*nb_steps"),
    (
        ["walk", "--spec", "{tmp}/bad.toml", "--out", "{out}"],
        r"bad.toml.*nb_steps must be a positive integer",
    ),
    (["walk", "--robot", "nao", "--steps", "2", "--out", "{out}"], "nao"),
    (["walk", "--vx", "5", "--steps", "2", "--out", "{out}"], "exceeds its limit"),
    (["walk", "--steps", "2", "--duration", "2", "--out", "{out}"], "not both"),
    (["walk", "--out", "{out}"], "needs --duration"),
    (["walk", "--path", "{tmp}/missing.mdat", "--out", "{out}"], "missing.mdat"),
    (["walk", "--path", "{tmp}/binary.mdat", "--out", "{out}"], "not UTF-8 text"),
    (["walk", "--path", "/dev/zero", "--out", "{out}"], "not a regular file"),
    (["walk", "--path", "{tmp}/nul.mdat", "--out", "{out}"], "binary content"),
    (["walk", "--path", "{tmp}/short.mdat", "--out", "{out}"], r"short.mdat:1 .*expected 14"),
    (["walk", "--steps", "2", "--mass-scale", "0", "--out", "{out}"], "mass"),
    (["walk", "--steps", "2", "--friction", "-1", "--out", "{out}"], "friction"),
    (["walk", "--steps", "2", "--latency", "0.015", "--out", "{out}"], "latency"),
    (["walk", "--steps", "2", "--step-duration", "1", "--generator", "static"], "fastest"),
    (["walk", "--steps", "2", "--vx", "abc", "--out", "{out}"], "invalid float"),
    (["walk", "--steps", "2", "--out", "{earlier}"], "holds an earlier run"),
    (["plan", "--control-period", "1.0", "--out", "{out}"], "control_period"),
    (["plan", "--control-period", "1e-6", "--out", "{out}"], "control_period"),
    (["plan", "--steps", "100000000", "--out", "{out}"], r"--steps must be a number"),
    (["plan", "--com-height", "-1", "--out", "{out}"], "--com-height must be"),
    (["plan", "--ds-ratio", "1.2", "--out", "{out}"], "double_support_ratio"),
    (["plan", "--generator", "static", "--step-duration", "0.5", "--out", "{out}"], "fastest"),
    (["plan", "--generator", "mpc", "--solver", "daqp", "--out", "{tmp}/afile"], "not a folder"),
]


def _prepare(tmp_path):
    (tmp_path / "afile").write_text("")
    (tmp_path / "binary.mdat").write_bytes(b"\xff\xfe\x00\x01 not text")
    (tmp_path / "nul.mdat").write_text("0 0.04 0 1 0 0 0\x00\n")
    (tmp_path / "short.mdat").write_text("0 0.04 0 1 0 0 0\n")
    (tmp_path / "typo.toml").write_text('robot = "bioloid-like"\n[plan]\nnb_step = 2\n')
    (tmp_path / "bad.toml").write_text('robot = "bioloid-like"\n[plan]\nnb_steps = -2\n')
    earlier = tmp_path / "earlier"
    earlier.mkdir()
    (earlier / "metrics.json").write_text("{}")


@pytest.mark.parametrize("args, message", CLI_CASES, ids=[" ".join(a) for a, _ in CLI_CASES])
def test_bad_cli_input_exits_2_with_a_named_error_and_creates_nothing(
    tmp_path, capsys, args, message
):
    import re

    _prepare(tmp_path)
    out = tmp_path / "out"
    values = {"tmp": str(tmp_path), "out": str(out), "earlier": str(tmp_path / "earlier")}
    argv = [a.format(**values) for a in args]
    if argv[0] == "walk":
        argv = WALK + argv[1:]
    if "--out" not in argv:
        argv += ["--out", str(out)]
    before = set(os.listdir(tmp_path))
    try:
        code = main(argv)
    except SystemExit as exit:  # argparse's own refusal (exit 2, its message)
        code = exit.code
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err
    assert re.search(message, err), err
    assert set(os.listdir(tmp_path)) == before  # nothing created
    assert (tmp_path / "earlier" / "metrics.json").read_text() == "{}"


def test_negative_numbers_are_option_values(tmp_path, capsys):
    assert main(["plan", "--vx", "-1e-2", "--steps", "2", "--out", str(tmp_path / "p")]) == 0
    assert '"vx": -0.01' in (tmp_path / "p" / "metrics.json").read_text()


def test_a_path_file_with_a_byte_order_mark_is_read(tmp_path):
    from mpcwalk.footsteps.mdat import read_mdat

    line = "0 0.04 0 1 0 0 0 0 -0.04 0 1 0 0 0\n"
    path = tmp_path / "bom.mdat"
    path.write_bytes(b"\xef\xbb\xbf" + line.encode() * 2)
    assert len(read_mdat(path)) == 2


def _walk(**fields):
    """A walk of bioloid-like with ``fields`` of its specification, to call."""
    return lambda: run_walk(WalkSpec.build("bioloid-like", command=(0.1, 0.0, 0.0), **fields))


#: (label, call, what the error message says); each raises an MpcwalkError, nothing runs.
API_CASES = [
    ("control_period str", lambda: make_generator("mpc", control_period="0.01"), "got '0.01'"),
    ("control_period 10", lambda: make_generator("mpc", control_period=10), "control_period"),
    ("lipm str", lambda: make_generator("mpc", lipm="x"), "lipm must be a LIPM"),
    ("solver int", lambda: make_generator("mpc", solver=3), "Unknown solver '3'"),
    ("solver on closed form", lambda: make_generator("analytic", solver="daqp"), "no option"),
    ("bogus setting", lambda: make_generator("mpc", solver_settings={"bogus": 1}), "bogus"),
    ("unknown generator", lambda: make_generator("zmp-magic"), "zmp-magic"),
    ("push string", _walk(nb_steps=2, pushes=["1,0.1,5,0,0"]), "five finite numbers"),
    ("pushes string", _walk(nb_steps=2, pushes="1,0.1,5,0,0"), "list of"),
    ("push nan", _walk(nb_steps=2, pushes=[(1.0, 0.1, math.nan, 0.0, 0.0)]), "finite"),
    ("push duration 0", _walk(nb_steps=2, pushes=[(1.0, 0.0, 5.0, 0.0, 0.0)]), "duration > 0"),
    ("duration str", _walk(duration="2"), "got '2'"),
    ("step_duration str", _walk(nb_steps=2, step_duration="0.5"), "got '0.5'"),
    ("nb_steps float", _walk(nb_steps=2.5), "positive integer"),
    ("nb_steps bool", _walk(nb_steps=True), "positive integer"),
    ("control_period nan", _walk(nb_steps=2, control_period=math.nan), "control_period"),
    ("step_height 0", _walk(nb_steps=2, step_height=0.0), "step_height"),
    ("arm_swing 100", _walk(nb_steps=2, arm_swing=100.0), "arm_swing"),
    ("controller option", _walk(nb_steps=2, controller_options={"bogus": 1}), "no option"),
    ("generator option", _walk(nb_steps=2, generator_options={"bogus": 1}), "bogus"),
    ("late push", _walk(nb_steps=2, pushes=[parse_push("100,0.1,5,0,0")]), "after the walk"),
    ("huge push", _walk(nb_steps=2, pushes=[parse_push("1,0.1,1e30,0,0")]), "weight"),
    ("unknown controller", _walk(nb_steps=2, controller="paper-x"), "Unknown controller"),
    ("unknown stabilizer", _walk(nb_steps=2, stabilizers=("hover",)), "Unknown stabilizer"),
    ("own field option", _walk(nb_steps=2, controller_options={"arm_swing": 0.8}), "own"),
    ("unknown field", _walk(nb_steps=2, perturbation=None), "no field 'perturbation'"),
    ("sensor nan window", _walk(nb_steps=2, sensor_nan=[(2.0, 1.0)]), "start < end"),
    ("video folder", _walk(nb_steps=2, video="/"), "is a folder"),
    ("video unwritable", _walk(nb_steps=2, video="/nonexistent/walk.mp4"), "cannot be written"),
    ("command bool", lambda: VelocityCommand(True, 0.0, 0.0), "must be a number"),
    ("command str", lambda: VelocityCommand("0.1", 0.0, 0.0), "must be a number"),
    (
        "initial_left tuple",
        lambda: FootstepPlan((0.0, 0.04), Footstep(Side.RIGHT, (0.0, -0.04))),
        "must be a Footstep",
    ),
    ("step_duration 1e6", lambda: StepTiming(step_duration=1e6), r"\(0, 60\]"),
    ("sensor fault window", lambda: SensorFaults(nan=[(2.0, 1.0)]), "start < end"),
]


@pytest.mark.parametrize("label, call, message", API_CASES, ids=[c[0] for c in API_CASES])
def test_bad_api_input_is_a_named_error(label, call, message):
    with pytest.raises(MpcwalkError, match=message):
        call()


def test_bad_api_input_misspelled_preset_key_is_refused(tmp_path):
    from mpcwalk.robot.package_data import ROBOT_DATA, package_data_dir
    from mpcwalk.robot.preset import RobotPreset

    shipped = package_data_dir(ROBOT_DATA) / "presets" / "bioloid_like.toml"
    text = shipped.read_text().replace("sole_size =", "sole_sizes =")
    (tmp_path / "bioloid_like.toml").write_text(text)
    with pytest.raises(MpcwalkError, match=r"unknown key\(s\) sole_sizes in \[feet\].*sole_size"):
        RobotPreset.from_file(tmp_path / "bioloid_like.toml")
