"""``mpcwalk robots``: the robots that load here; ``mpcwalk robots check NAME|PRESET``;
``mpcwalk robots init DESCRIPTION --out PRESET.toml``."""

import argparse
import os
from pathlib import Path

from mpcwalk.exceptions import ConfigurationError


def add_parser(sub) -> argparse.ArgumentParser:
    """Add the ``robots`` sub-command to ``sub`` (``mpcwalk robots`` lists them,
    ``mpcwalk robots check NAME|PRESET`` runs the checks a preset must pass)."""
    p = sub.add_parser(
        "robots",
        help="list the robots that load on this machine; 'robots check PRESET' checks one",
        description="List the robots whose description is installed, with their size and "
        "walking defaults. 'mpcwalk robots check NAME|PRESET.toml' runs the checks a preset "
        "must pass: it loads (the URDF inertias repaired for MuJoCo listed), Pinocchio and "
        "MuJoCo agree, the nominal posture is within the joint limits, its soles flat, its "
        "torso frame upright, the soles lie on the feet, the servos hold the posture, it "
        "stands one second under the servos, a short walk with mpc does not fall. Each "
        "failure prints its numbers and its likely fix. Exit code 1 when a check fails, 2 "
        "when there is no robot to check (unknown name, no such preset file or description). "
        "'mpcwalk robots init DESCRIPTION.urdf --out PRESET.toml' drafts a preset from a URDF "
        "alone (legs, feet and soles, base axes, joint roles, torso and IMU, a knees-bent "
        "posture, servos and gait from documented rules, every guess commented), then checks "
        "it.",
    )
    p.add_argument(
        "action",
        nargs="?",
        choices=["check", "init"],
        help="check one robot, or draft a preset from a description",
    )
    p.add_argument(
        "robot",
        nargs="?",
        help="robot name or path of a preset file (.toml); for init, a URDF file",
    )
    p.add_argument("--no-walk", action="store_true", help="skip the short walk")
    p.add_argument("--out", help="init: the preset file to write (.toml)")
    p.add_argument("--name", help="init: the robot's name (default: the URDF's)")
    p.add_argument(
        "--srdf", help="init: an SRDF whose reference posture sets the arms and the head"
    )
    p.add_argument("--overwrite", action="store_true", help="init: replace --out")
    p.add_argument("--no-check", action="store_true", help="init: do not check the preset")
    p.set_defaults(run=run)
    return p


def check(args) -> int:
    """Run ``mpcwalk robots check ROBOT``: one line per check; 1 when one fails.

    Raises:
        RobotNotFound: No such robot, preset file or description (exit code 2 in ``main``).
    """
    if not args.robot:
        raise ConfigurationError(
            "mpcwalk robots check needs a robot: a name (mpcwalk robots) or the path of a "
            "preset file, e.g. mpcwalk robots check my_robot/my_biped.toml."
        )
    return print_checks(args.robot, walk=not args.no_walk)


def print_checks(robot: str | Path, *, walk: bool) -> int:
    """Run the checks of ``robot`` (a name or a preset file), one line each; 1 when one
    fails."""
    from mpcwalk.walking.robot_check import check_robot

    results = check_robot(robot, walk=walk)
    for result in results:
        print(f"{'ok  ' if result.passed else 'FAIL'} {result.name}: {result.detail}")
    return 0 if all(r.passed for r in results) else 1


def _reference(description: Path, out: Path) -> str:
    """How the preset names its description: inside example-robot-data, relative to its
    robots folder (as the shipped presets); elsewhere, relative to the preset's folder."""
    from mpcwalk.robot.loading import example_robot_data_dir

    root = example_robot_data_dir()
    resolved = description.resolve()
    if root is not None and resolved.is_relative_to(root.resolve()):
        return resolved.relative_to(root.resolve()).as_posix()
    return Path(os.path.relpath(resolved, out.resolve().parent)).as_posix()


def init(args) -> int:
    """Run ``mpcwalk robots init``: draft, write, then check the preset (exit 1 when a
    check fails, 2 for bad input)."""
    from mpcwalk.robot.survey.draft import draft_preset
    from mpcwalk.robot.survey.writer import preset_toml

    if not args.robot:
        raise ConfigurationError(
            "mpcwalk robots init needs a description: the path of a URDF file, e.g. mpcwalk "
            "robots init my_biped.urdf --out my_biped.toml."
        )
    description = Path(args.robot)
    if not description.is_file():
        raise ConfigurationError(
            f"mpcwalk robots init: the description {description} is not a file; give the "
            "path of a URDF file."
        )
    if not args.out:
        raise ConfigurationError(
            "mpcwalk robots init needs --out PRESET.toml: the preset file to write."
        )
    out = Path(args.out)
    if out.suffix != ".toml":
        raise ConfigurationError(f"--out {out}: a preset file ends in .toml.")
    if out.exists() and not args.overwrite:
        raise ConfigurationError(
            f"--out {out} exists; add --overwrite to replace it, or choose another file."
        )
    out.parent.mkdir(parents=True, exist_ok=True)
    draft = draft_preset(
        description, name=args.name, reference=_reference(description, out), srdf=args.srdf
    )
    out.write_text(preset_toml(draft))
    print(
        f"{draft.name}: legs {', '.join(draft.legs.left.joints)} | "
        f"{', '.join(draft.legs.right.joints)}; feet {draft.legs.left.foot}, "
        f"{draft.legs.right.foot}; base forward {draft.base[0]}, up {draft.base[1]}; "
        f"sole {draft.soles[0].size[0]:.3f} x {draft.soles[0].size[1]:.3f} m; torso "
        f"{draft.torso[0]}; CoM height {draft.posture.com_height:.3f} m; step "
        f"{draft.gait['step_duration']:g} s"
    )
    for note in draft.notes:
        print(f"note: {note}")
    for warning in draft.warnings:
        print(f"LOOK: {warning}")
    print(f"wrote {out}")
    if args.no_check:
        return 0
    return print_checks(out, walk=not args.no_walk)


def run(args) -> int:
    """Run ``mpcwalk robots``: one line per robot that loads.

    Raises:
        ConfigurationError: No robot is installed (exit code 2 in ``main``).
    """
    from mpcwalk.robot.loading import PRESETS_DIR, load_robot, robot_names

    if getattr(args, "action", None) == "check":
        return check(args)
    if getattr(args, "action", None) == "init":
        return init(args)
    names = robot_names()
    if not names:
        raise ConfigurationError(
            f"No robot found: searched {PRESETS_DIR} for presets (*.toml) whose description "
            "is installed (MJCF files in the robots folder, URDF models of the "
            "example-robot-data package). Reinstall mpcwalk with its robot files."
        )
    for name in names:
        robot = load_robot(name, visual=False)
        period = robot.gait.step_duration
        print(
            f"{name:14s} {len(robot.joint_names):2d} joints, {robot.total_mass:6.1f} kg, CoM "
            f"height {robot.com_height:.3f} m, soles {robot.sole_size[0]:.2f} x "
            f"{robot.sole_size[1]:.2f} m, step duration "
            f"{period:g} s  "
            f"[{robot.description_path.name}]"
        )
    return 0
