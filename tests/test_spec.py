"""One walk, one specification: a walk is reproducible from the ``spec.toml`` it wrote, every
part of a :class:`WalkSpec` refuses a bad value with a named error, and the command that a
sweep's report prints for a walk gives that walk back."""

import dataclasses
import inspect
import json
from pathlib import Path

import numpy as np
import pytest

import mpcwalk
from mpcwalk.cli import build_parser, main
from mpcwalk.cli.walk_options import spec_from_args
from mpcwalk.exceptions import ConfigurationError, NotRegistered, SpecFileError
from mpcwalk.terrain import Platform, Terrain
from mpcwalk.walking.specification import (
    FIELDS,
    ControllerSpec,
    DisturbanceSpec,
    PlanSpec,
    RunSpec,
    WalkSpec,
    WorldSpec,
    read_spec,
    spec_to_toml,
    write_spec,
)

#: A walk of three steps with a push, a turn and a changed world, from the command line.
WALK = [
    "walk",
    "--robot",
    "bioloid-like",
    "--controller",
    "mpc",
    "--vx",
    "0.1",
    "--vyaw",
    "0.2",
    "--steps",
    "3",
    "--push",
    "2.2,0.1,2,1,0",
    "--noise-scale",
    "1.5",
    "--mass-scale",
    "1.05",
    "--seed",
    "4",
    "--no-progress",
]


def _timing(key: str) -> bool:
    """Keys of ``metrics.json`` that are wall-clock timings (they differ run to run)."""
    return key.endswith("_us_median") or key == "real_time_factor"


def _metrics(out: Path) -> dict:
    """``metrics.json`` of ``out`` without its timings."""
    metrics = json.loads((out / "metrics.json").read_text())
    return {key: value for key, value in metrics.items() if not _timing(key)}


@pytest.fixture(scope="module")
def walked(tmp_path_factory) -> Path:
    """The output folder of :data:`WALK`."""
    out = tmp_path_factory.mktemp("spec") / "a"
    assert main([*WALK, "--out", str(out)]) == 0
    return out


def test_a_walk_from_its_spec_file_gives_the_same_metrics(walked, tmp_path):
    again = tmp_path / "b"
    assert (
        main(["walk", "--spec", str(walked / "spec.toml"), "--no-progress", "--out", str(again)])
        == 0
    )
    first, second = _metrics(walked), _metrics(again)
    assert first == second  # to the last digit, the configuration block included
    assert (again / "spec.toml").read_text() == (walked / "spec.toml").read_text()
    logs = [np.load(out / "walk_log.npz") for out in (walked, again)]
    for name in ("com", "estimated_com", "joint_targets"):  # the same walk, tick by tick
        np.testing.assert_array_equal(logs[0][name], logs[1][name])
    timings = [key for key in json.loads((walked / "metrics.json").read_text()) if _timing(key)]
    assert "real_time_factor" in timings and "controller_tick_us_median" in timings
    # what was walked: the push, the world, the yaw deviation measured against the unpushed walk
    assert first["config"]["pushes"] == [[2.2, 0.1, 2.0, 1.0, 0.0]]
    assert first["config"]["seed"] == 4 and first["config"]["noise_scale"] == 1.5
    assert first["yaw_deviation_deg"] is not None and first["steps_planned"] == 4


def test_the_spec_file_spells_out_every_field_resolved(walked):
    spec = read_spec(walked / "spec.toml")
    assert spec.controller == ControllerSpec.named("mpc")
    assert spec.plan.command == (0.1, 0.0, 0.2) and spec.plan.nb_steps == 3
    # the defaults the robot's preset decided, written down
    assert (spec.plan.step_duration, spec.plan.double_support_ratio) == (0.5, 0.2)
    assert spec.plan.step_height == 0.04 and spec.world.state == "estimator"
    assert spec.disturbances.pushes == ((2.2, 0.1, 2.0, 1.0, 0.0),)
    assert spec.disturbances.yaw_reference is True
    assert (spec.world.noise_scale, spec.world.mass_scale, spec.run.seed) == (1.5, 1.05, 4)
    text = (walked / "spec.toml").read_text()
    for field in FIELDS:  # every field, an unset one as a comment
        assert f"\n{field} = " in text or f"\n# {field} = (unset)" in text, field
    assert read_spec(walked / "spec.toml") == WalkSpec.from_dict(spec.to_dict())


@pytest.mark.parametrize(
    "option, value, field, config",
    [
        ("--seed", "3", ("run", "seed", 3), ("seed", 3)),
        (
            "--mass-scale",
            "1.1",
            ("world", "mass_scale", 1.1),
            ("model_mismatch", "mass_scale", 1.1),
        ),
    ],
)
def test_an_option_beside_the_spec_changes_that_field(
    minimal, tmp_path, option, value, field, config
):
    out = tmp_path / "b"
    first = minimal / "out" / "spec.toml"
    argv = ["walk", "--spec", str(first), option, value, "--no-progress", "--out", str(out)]
    assert main(argv) == 0
    spec, first = read_spec(out / "spec.toml"), read_spec(first)
    part, name, expected = field
    assert getattr(getattr(spec, part), name) == expected
    assert spec == first.replace(**{name: expected})  # that field, nothing else
    block = json.loads((out / "metrics.json").read_text())["config"]
    for key in config[:-1]:
        block = block[key]
    assert block == config[-1]


def test_run_walk_takes_at_most_ten_parameters():
    parameters = inspect.signature(mpcwalk.run_walk).parameters
    assert len(parameters) <= 10, list(parameters)


def test_the_short_form_and_a_robot_builds_the_same_spec(bioloid):
    from mpcwalk.walking.runner import run_walk

    short = run_walk(bioloid, controller="paper-m-open", command=(0.1, 0.0, 0.0), nb_steps=2)
    spec = WalkSpec.build(
        "bioloid-like", controller="paper-m-open", command=(0.1, 0, 0), nb_steps=2
    )
    assert short.spec.robot == "bioloid-like"
    assert (
        short.spec.replace(step_duration=None, double_support_ratio=None, step_height=None) == spec
    )


#: (part, its keywords, what the error says): each part refuses the value when it is made.
BAD_VALUES = [
    (ControllerSpec, {"generator": ""}, "ControllerSpec.generator must be a name"),
    (ControllerSpec, {"feedback": "yes"}, "feedback must be true or false"),
    (ControllerSpec, {"stabilizers": (1,)}, "stabilizers must be stabilizer names"),
    (ControllerSpec, {"arm_swing": 5.0}, "arm_swing"),
    (ControllerSpec, {"swing_profile": "spline"}, "swing_profile must be one of cosine, ctraj"),
    (ControllerSpec, {"controller_options": "fast"}, "controller_options must be a dict"),
    (ControllerSpec, {"controller_options": {"stabilizer": "gyro"}}, "fields of the controller"),
    (ControllerSpec, {"generator_options": {"solver": object()}}, r"generator_options\['solver'\]"),
    (PlanSpec, {"command": (0.1, 0.0)}, "A velocity command is three numbers"),
    (PlanSpec, {"command": (0.1, 0, 0), "path": "a.mdat"}, "not both"),
    (PlanSpec, {"nb_steps": 2, "duration": 1.0}, "either nb_steps or duration, not both"),
    (PlanSpec, {"nb_steps": 0}, "nb_steps must be a positive integer"),
    (PlanSpec, {"duration": -1.0}, "duration"),
    (PlanSpec, {"control_period": 1.0}, "control_period"),
    (PlanSpec, {"step_duration": 0.05}, "10 control periods"),
    (PlanSpec, {"double_support_ratio": 1.0}, "double_support_ratio"),
    (PlanSpec, {"step_height": -0.01}, "step_height"),
    (WorldSpec, {"noise_scale": -1.0}, "noise_scale must be a finite number >= 0"),
    (WorldSpec, {"latency": -0.01}, "latency must be a number of seconds"),
    (WorldSpec, {"ideal": True, "noise_scale": 2.0}, "ideal sensors have no noise"),
    (WorldSpec, {"state": "truth"}, "state must be one of estimator, oracle"),
    (WorldSpec, {"mass_scale": 0.0}, r"mass_scale must be a number in \[0.1, 10\]"),
    (WorldSpec, {"com_offset": (0.01,)}, "com_offset must be two numbers"),
    (WorldSpec, {"friction": -1.0}, "friction"),
    (WorldSpec, {"ground_tilt": 90.0}, r"tilt must be a number in \[-20, 20\] deg"),
    (DisturbanceSpec, {"pushes": "1,0.1,5,0,0"}, "pushes must be a list"),
    (DisturbanceSpec, {"pushes": [(1.0, 0.1, 5.0)]}, "A push is five finite numbers"),
    (DisturbanceSpec, {"pushes": [(-1.0, 0.1, 5.0, 0.0, 0.0)]}, "start >= 0"),
    (DisturbanceSpec, {"sensor_nan": [(2.0, 1.0)]}, "start < end"),
    (DisturbanceSpec, {"yaw_reference": 1}, "yaw_reference must be true or false"),
    (RunSpec, {"seed": -1}, "seed must be an integer >= 0"),
    (RunSpec, {"seed": 1.5}, "seed must be an integer >= 0"),
    (RunSpec, {"progress": "no"}, "progress must be true or false"),
]


@pytest.mark.parametrize(
    "part, values, message",
    BAD_VALUES,
    ids=[f"{part.__name__}-{'-'.join(values)}" for part, values, _ in BAD_VALUES],
)
def test_every_part_refuses_a_bad_value_with_a_named_error(part, values, message):
    with pytest.raises(ConfigurationError, match=message):
        part(**values)
    with pytest.raises(ConfigurationError, match=message):  # the same, field by field
        WalkSpec.build("bioloid-like", **values)


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: WalkSpec(3), "robot must be a robot name or a preset file"),
        (lambda: WalkSpec("bioloid-like", plan="fast"), "WalkSpec.plan must be a PlanSpec"),
        (lambda: WalkSpec.build("bioloid-like", controller=3), "controller must be a controller"),
        (lambda: WalkSpec("bioloid-like", labels={"seed": 1}), "would hide fields"),
    ],
)
def test_the_walk_spec_refuses_a_bad_part(make, message):
    with pytest.raises(ConfigurationError, match=message):
        make()


def test_an_unknown_field_or_controller_is_refused_naming_the_valid_ones():
    with pytest.raises(ConfigurationError, match=r"no field 'nb_step'; its fields are .*nb_steps"):
        WalkSpec.build("bioloid-like", nb_step=2)
    spec = WalkSpec.build("bioloid-like", nb_steps=2)
    with pytest.raises(ConfigurationError, match=r"no field 'stabilizer'.*stabilizers"):
        spec.replace(stabilizer="gyro")
    with pytest.raises(NotRegistered, match="Unknown controller 'paper-x'.*paper-m, paper-m-open"):
        spec.replace(controller="paper-x")
    assert spec.replace() == spec


@pytest.mark.parametrize(
    "text, message",
    [
        (
            'robot = "bioloid-like"\n[plan]\nnb_step = 2\n',
            r"\[plan\] has no field 'nb_step'; its fields are command, .*nb_steps",
        ),
        (
            'robot = "bioloid-like"\n[wrld]\nseed = 2\n',
            r"no part 'wrld'; its parts are robot, controller, plan, world",
        ),
        ("[plan]\nnb_steps = 2\n", r"needs at least its robot"),
        ('robot = "bioloid-like"\n[plan]\nnb_steps = 0\n', "nb_steps must be a positive integer"),
        ('robot = "bioloid-like"\n[world]\nnoise_scale = -1.0\n', "noise_scale must be"),
        (
            'robot = "bioloid-like"\n[controller]\nname = "paper-x"\n',
            "Unknown controller 'paper-x'",
        ),
        ('robot = "bioloid-like"\nplan = 2\n', r"\[plan\] must be a table"),
        ('robot = "bioloid-like"\n[plan\n', "not a TOML file"),
    ],
)
def test_a_bad_spec_file_is_refused_naming_the_file_and_the_field(tmp_path, text, message):
    path = tmp_path / "spec.toml"
    path.write_text(text)
    with pytest.raises(SpecFileError, match=message) as refused:
        read_spec(path)
    assert str(path) in str(refused.value)
    with pytest.raises(SpecFileError, match="no such file"):
        read_spec(tmp_path / "missing.toml")


@pytest.fixture(scope="module")
def minimal(tmp_path_factory) -> Path:
    """A hand-written specification (its robot and two steps), and the folder of its walk."""
    folder = tmp_path_factory.mktemp("minimal")
    (folder / "walk.toml").write_text('robot = "bioloid-like"\n\n[plan]\nnb_steps = 2\n')
    out = folder / "out"
    assert (
        main(["walk", "--spec", str(folder / "walk.toml"), "--no-progress", "--out", str(out)]) == 0
    )
    return folder


def test_a_hand_written_minimal_spec_walks(minimal):
    spec = read_spec(minimal / "walk.toml")
    assert spec == WalkSpec.build("bioloid-like", nb_steps=2)  # every other field its default
    assert spec.controller == ControllerSpec.named("mpc") and spec.plan.command is None
    out = minimal / "out"
    metrics = json.loads((out / "metrics.json").read_text())
    assert not metrics["fell"] and metrics["steps_planned"] == 3  # and the closing step
    assert metrics["config"]["generator"] == "mpc" and metrics["config"]["nb_steps"] == 2
    written = read_spec(out / "spec.toml")  # resolved: the preset's timing spelled out
    assert written.plan.step_duration == 0.5 and written.plan.nb_steps == 2


def test_a_controller_alone_in_a_spec_file_is_the_named_one_changed(tmp_path):
    path = tmp_path / "walk.toml"
    path.write_text('robot = "bioloid-like"\n[controller]\nname = "paper-m"\narm_swing = 0.5\n')
    controller = read_spec(path).controller
    assert controller == ControllerSpec.named("paper-m").replace(arm_swing=0.5)
    assert controller.name == "custom" and controller.stabilizers == ("gyro",)
    path.write_text('robot = "bioloid-like"\n[controller]\ngenerator = "preview"\n')
    assert read_spec(path).controller == ControllerSpec(generator="preview")


def _every_field_changed() -> dict:
    """A value other than the default for every field of a specification."""
    return {
        "generator": "preview",
        "generator_options": {"horizon": 2.0},
        "feedback": False,
        "stabilizers": ("gyro",),
        "arm_swing": 0.8,
        "swing_profile": "ctraj",
        "controller_options": {"heading_hold": False},
        "command": (0.05, 0.0, 0.0),
        "path": "a.mdat",
        "nb_steps": 3,
        "duration": 2.0,
        "step_duration": 0.6,
        "terrain_cadence": True,
        "double_support_ratio": 0.3,
        "step_height": 0.03,
        "control_period": 0.02,
        "noise_scale": 0.5,
        "latency": 0.02,
        "ideal": True,
        "state": "oracle",
        "mass_scale": 1.2,
        "com_offset": (0.01, 0.0),
        "friction": 0.8,
        "servo_strength": 0.9,
        "friction_cone": "elliptic",
        "impratio": 10.0,
        "actuation": "torque",
        "ground_tilt": 2.0,
        "ground_tilt_direction": 90.0,
        "ground_roughness": 0.002,
        "terrain": Terrain([Platform(0.5, length=0.4, height=0.02)]),
        "pushes": [(1.0, 0.1, 5.0, 0.0, 0.0)],
        "sensor_nan": [(1.0, 1.1)],
        "sensor_dropout": [(1.0, 1.1)],
        "yaw_reference": True,
        "seed": 1,
        "progress": True,
        "video": "walk.mp4",
    }


def test_the_case_id_changes_with_any_field_and_only_then():
    base = WalkSpec.build("bioloid-like", controller="mpc")
    assert base.case_id == WalkSpec.build("bioloid-like").case_id == base.replace().case_id
    assert len(base.case_id) == 16
    changed = _every_field_changed()
    assert set(changed) == set(FIELDS)  # every field of every part
    ids = {base.case_id}
    for name, value in changed.items():
        spec = base.replace(**{name: value})
        assert spec != base and spec.case_id not in ids, name
        ids.add(spec.case_id)
    for changes in ({"robot": "g1"}, {"controller": "paper-m"}, {"labels": {"group": "a"}}):
        assert base.replace(**changes).case_id not in ids, changes
    # the same walk made another way, the same id
    assert WalkSpec.build("bioloid-like", seed=1).case_id == base.replace(seed=1).case_id


def test_a_spec_goes_through_its_file_unchanged(tmp_path):
    changed = _every_field_changed()
    del changed["path"], changed["duration"], changed["noise_scale"], changed["latency"]
    del changed["ground_roughness"]  # no bumps under a terrain
    spec = WalkSpec.build("bioloid-like", labels={"group": "heavy", "factor": 1.5}, **changed)
    assert read_spec(write_spec(spec, tmp_path / "spec.toml")) == spec
    assert WalkSpec.from_dict(json.loads(json.dumps(spec.to_dict()))) == spec
    assert "\n# friction = (unset)" in spec_to_toml(WalkSpec.build("bioloid-like"))


def _parsed(spec: WalkSpec) -> WalkSpec:
    """The specification ``mpcwalk walk`` makes of ``spec.command_line()``."""
    import shlex

    words = shlex.split(spec.command_line(out="w"))
    assert words[:2] == ["mpcwalk", "walk"]
    from mpcwalk.cli.console import joined_negative_numbers

    args = build_parser().parse_args(joined_negative_numbers(words[1:]))
    return spec_from_args(args, out=Path("w"))


@pytest.mark.parametrize(
    "spec",
    [
        WalkSpec.build(
            "bioloid-like",
            controller="paper-m",
            command=(0.1, -0.02, 0.3),
            nb_steps=4,
            pushes=[(2.0, 0.1, 5.0, -3.0, 0.0), (3.5, 0.05, -2.5, 0.0, 0.0)],
            yaw_reference=True,
            mass_scale=1.15,
            com_offset=(0.01, -0.005),
            friction=0.6,
            noise_scale=2.0,
            latency=0.02,
            servo_strength=0.9,
            ground_tilt=3.0,
            ground_tilt_direction=-45.0,
            ground_roughness=0.004,
            seed=7,
        ),
        WalkSpec.build(
            "atlas-like",
            controller="mpc-steps",
            duration=6.0,
            command=(0.2, 0.0, 0.0),
            step_duration=0.8,
            double_support_ratio=0.25,
            step_height=0.06,
            ideal=True,
            state="estimator",
            control_period=0.02,
            generator_options={"solver": "quadprog"},
        ),
        WalkSpec.build(
            "bioloid-like",
            controller="paper-m",
            generator="mpc",
            controller_options={},  # a command line carries no controller options
            feedback=True,
            stabilizers=("reaim", "ankle-imu"),
            swing_profile="ctraj",
            arm_swing=0.4,
            command=(0.08, 0.0, 0.0),
            nb_steps=3,
            state="oracle",
        ),
        WalkSpec.build(
            "bioloid-like", generator="analytic", feedback=False, command=(0.1, 0, 0), nb_steps=2
        ),
        WalkSpec.build(
            "bioloid-like",
            controller="mpc",
            command=(0.1, 0.0, 0.0),
            nb_steps=3,
            actuation="torque",
            controller_options={"dynamics_solver": "quadprog"},  # --dynamics-solver
        ),
        WalkSpec.build(
            "romeo",
            controller="mpc-steps",
            command=(0.15, 0.0, 0.0),
            nb_steps=4,
            actuation="torque",
            servo_strength=0.8,
            controller_options={"torque_loop": True},  # --torque-loop
        ),
    ],
    ids=[
        "named-pushes-world",
        "named-timing-ideal",
        "custom-by-parts",
        "custom-open-loop",
        "torque-dynamics-solver",
        "torque-loop",
    ],
)
def test_the_command_line_of_a_spec_gives_the_spec_back(spec):
    again = _parsed(spec).replace(progress=False)  # the command shows a progress bar
    assert again == spec, (spec.command_line(), dataclasses.asdict(again))
    assert again.case_id == spec.case_id


def test_ideal_sensors_put_the_controller_on_the_ground_truth_unless_told():
    spec = WalkSpec.build("bioloid-like", nb_steps=2)
    assert spec.world.state == "estimator"
    assert spec.replace(ideal=True).world.state == "oracle"
    assert spec.replace(ideal=True, state="estimator").world.state == "estimator"
    assert spec.replace(ideal=True).replace(ideal=False).world.state == "estimator"
    args = build_parser().parse_args(["walk", "--steps", "2", "--ideal", "--out", "w"])
    assert spec_from_args(args, out=Path("w")).world == WorldSpec(ideal=True)
