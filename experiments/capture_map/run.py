"""The LIPM's push-recovery map of the robots, the reference for the controllers' push maps.

python experiments/capture_map/run.py --out results/capture_map
"""

import argparse
import json
from dataclasses import asdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from mpcwalk.experiments.capture_map import capture_map
from mpcwalk.robot import load_robot

ROBOTS = ("bioloid-like", "g1")


def polar_figure(robot: str, cells, path: Path) -> None:
    phases = sorted({c.phase for c in cells})
    fig, axes = plt.subplots(
        1, len(phases), subplot_kw={"projection": "polar"}, figsize=(3.0 * len(phases), 3.6)
    )
    for ax, phase in zip(np.atleast_1d(axes), phases):
        row = [c for c in cells if c.phase == phase]
        angles = np.radians([c.direction_deg for c in row] + [row[0].direction_deg])
        for label, values, style in (
            ("0 steps", [c.fixed[0] for c in row], "k-"),
            ("1 step", [c.fixed[1] for c in row], "b-"),
            ("2 steps", [c.fixed[2] for c in row], "g-"),
            ("2 steps, timing adapted", [c.adaptive[2] for c in row], "r--"),
        ):
            ax.plot(angles, [*values, values[0]], style, lw=1.2, label=label)
        kind = "single" if row[0].single_support else "double"
        ax.set_title(f"phase {phase:.2f} ({kind} support)", fontsize=8)
        ax.tick_params(labelsize=6)
    np.atleast_1d(axes)[0].legend(loc="lower left", bbox_to_anchor=(0.0, -0.45), fontsize=7)
    fig.suptitle(f"{robot}: largest impulse the LIPM recovers [N s] (0 deg forward, 90 left)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/capture_map"))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    lines = [
        "# The LIPM's push-recovery map",
        "",
        "The largest impulse [N s] of a 0.1 s push a linear inverted pendulum with the robot's",
        "mass, CoM height, soles, leg limits and timing recovers, with at most 0, 1 and 2 steps",
        "(`mpcwalk.footsteps.capturability`, Koolen 2012), along its nominal straight walk,",
        "16 directions x 6 phases of the third step; first landing at the schedule's time",
        "(fixed) or at the best time the swing allows (adapted, down to a 0.15 s swing).",
        "No cross-over step: a push towards the stance leg can only be caught by the ankle or",
        "by the stance leg's own step after the swing leg's; on `bioloid-like` early in single",
        "support that second step comes too late even with 0.15 s swings (the bound stays the",
        "ankle's). In double support the robot stands on the hull of both soles. The walk is",
        "at the robot's nominal speed (a walk's default command), as in the push maps.",
        "Command: `python experiments/capture_map/run.py --out results/capture_map`",
        "",
        "| robot | steps | median over cells, fixed timing | smallest cell, fixed | median, timing adapted | smallest cell, adapted |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    payload = {}
    for robot_name in ROBOTS:
        robot = load_robot(robot_name, visual=False)
        cells = capture_map(robot)
        payload[robot_name] = [asdict(c) for c in cells]
        for n in range(3):
            fixed = [c.fixed[n] for c in cells]
            adaptive = [c.adaptive[n] for c in cells]
            lines.append(
                f"| {robot_name} | {n} | {np.median(fixed):.2f} | {min(fixed):.2f} | "
                f"{np.median(adaptive):.2f} | {min(adaptive):.2f} |"
            )
        polar_figure(robot_name, cells, args.out / f"capture_map_{robot_name}.png")
    lines += [""] + [f"![{r}](capture_map_{r}.png)" for r in ROBOTS]
    (args.out / "README.md").write_text("\n".join(lines) + "\n")
    (args.out / "capture_map.json").write_text(json.dumps(payload, indent=1) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
