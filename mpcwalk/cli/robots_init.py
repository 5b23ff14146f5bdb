"""``mpcwalk robots init DESCRIPTION --out PRESET.toml``: a preset drafted from a URDF."""

from __future__ import annotations

import os
from pathlib import Path

from mpcwalk.exceptions import ConfigurationError


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
    out.write_text(draft.toml())
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
    from mpcwalk.cli.robots import print_checks

    return print_checks(out, walk=not args.no_walk)


__all__ = ["init"]
