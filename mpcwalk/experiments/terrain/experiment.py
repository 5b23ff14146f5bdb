"""The terrain experiment as an experiment of the registry (``terrain``): one sweep of every
robot's controllers on the stairs (a bisection on the rise), the slopes, the stepping stones
and the rough patch, then its figures and ``report.md``."""

from pathlib import Path
from typing import Any

from mpcwalk.experiments.protocol import Experiment, read_table
from mpcwalk.experiments.reporting import read_runs, runs_text
from mpcwalk.experiments.terrain.config import TerrainConfig, load_terrain_config
from mpcwalk.sweep import Sweep

#: Where the report's words on the side view are kept between figures() and report().
_SIDE_VIEW_NOTE = "side_view.txt"


class TerrainExperiment(Experiment):
    """The controllers on stairs, slopes, stepping stones and a rough patch, per robot."""

    name = "terrain"
    summary = "the largest stair rise each controller climbs, slopes, stepping stones, rough ground"
    package = "mpcwalk.experiments.terrain"

    def config(self, *, quick: bool = False) -> TerrainConfig:
        return load_terrain_config(self.config_file, quick=quick)

    def cases(self, config: TerrainConfig) -> tuple[Any, ...]:
        from mpcwalk.experiments.terrain.cases import terrain_cases

        return terrain_cases(config)

    def sweep(self, config: TerrainConfig, out: str | Path | None = None) -> Sweep:
        from mpcwalk.experiments.terrain.cases import terrain_sweep

        return terrain_sweep(config, out)

    def figures(self, out: str | Path) -> list[str]:
        """The bar chart of the largest rises and the side views of the climbs."""
        from mpcwalk.experiments.terrain.plots import pick_side_views, rise_bars
        from mpcwalk.experiments.terrain.report import kept_rows

        out = Path(out)
        settings, rows = read_table(out)
        kept = kept_rows(rows, "stairs")
        if not kept:
            return []
        names = [rise_bars(out, kept, float(settings.get("goal_rise_share", 0.25)))]
        views, what = pick_side_views(out, kept)
        if what:
            (out / _SIDE_VIEW_NOTE).write_text(what + "\n")
        return names + views

    def report(self, out: str | Path) -> Path:
        from mpcwalk.experiments.terrain.goals import goals_text
        from mpcwalk.experiments.terrain.plots import RISE_FIGURE, SIDE_VIEW
        from mpcwalk.experiments.terrain.report import (
            PEERS,
            crashes_text,
            kept_rows,
            refusals_text,
            rise_table,
            trials_text,
            variant_table,
            walk_table,
        )

        out = Path(out)
        settings, rows = read_table(out)
        terrains = settings.get("terrains", [])
        note = out / _SIDE_VIEW_NOTE
        text = [
            "# Terrain: stairs, slopes, stepping stones, rough ground\n",
            runs_text(read_runs(out), len(rows), "cases (a bisection of walks, or one walk)"),
            _setting_text(settings),
        ]
        if "stairs" in terrains:
            stairs = kept_rows(rows, "stairs")
            text += [
                "## Step duration and stride\n",
                "Each robot's controllers walk at each of its step durations and each nominal "
                "stride; the report keeps, per robot and controller, the pair that climbs "
                "higher (then the one whose goal walk went through a larger share of its "
                "steps, then the faster, then the longer stride), and shows its walks in every "
                "table below. Controllers with a timing of their own (`own`: paper A's 12 s) "
                "keep it.\n",
                variant_table(rows),
                "## Largest rise climbed\n",
                rise_table(stairs),
                PEERS + "\n",
                "The bisection's walks (kept step duration and stride), in the order they ran "
                "(a walk that fails a rise under one it climbed shows the outcome is not "
                "monotone in the rise there):\n",
                trials_text(stairs),
                f"## At the goal's rise ({float(settings['goal_rise_share']):.0%} of the leg "
                "length)\n",
                walk_table(stairs, rise=True),
            ]
        for terrain, title in (
            ("slope", f"Slopes: {float(settings['slope_deg']):g} deg up, a landing, down"),
            ("stones", "Stepping stones"),
            ("rough", "Rough patch"),
        ):
            if terrain in terrains:
                text += [f"## {title}\n", walk_table(kept_rows(rows, terrain))]
        text += [
            "## Refusals\n",
            "Terrains or walks the library refused before they ran (the tables give them in "
            "short):\n",
            refusals_text(rows),
            "## Crashes\n",
            crashes_text(rows),
            "## Goals\n",
            goals_text(rows, settings),
        ]
        figures = [n for n in (RISE_FIGURE, SIDE_VIEW) if (out / n).exists()]
        robots = sorted(p.name for p in out.glob("side_view_*.png"))
        if figures:
            text.append("## Figures\n")
        if note.exists():
            text.append(f"The side view: {note.read_text().strip()}.\n")
        text += [f"![{name}]({name})\n" for name in figures]
        if robots:
            text.append(
                "Each robot's side view (its highest climb, else the goal's walk that went "
                "farthest): " + ", ".join(f"[{name}]({name})" for name in robots) + ".\n"
            )
        path = out / "report.md"
        path.write_text("\n".join(text))
        return path


def _setting_text(settings: dict[str, Any]) -> str:
    """The terrains in words, from the sweep's settings."""
    s = settings
    return (
        "Every size is relative to the robot: its leg length (the hip height above the "
        "soles) and its sole length. **Stairs**: "
        f"{s['nb_stairs']} steps up from {s['approach']:g} m ahead, a landing of "
        f"{s['landing_soles']:g} sole lengths, {s['nb_stairs']} steps down; run "
        f"{s['run_soles']:g} sole lengths (never under the sole with its margins); the rise by "
        "bisection between 0 and the legs' reach (half the leg length), the first walk at "
        f"the goal's rise ({s['goal_rise_share']:.0%} of the leg), at most "
        f"{s['bisection_iterations']} walks, down to a bracket of {s['tolerance_share']:.0%} of "
        "the leg. A walk *climbs* when it neither falls nor is stopped, completes all its "
        f"steps, and its largest 3D landing error is under {s['climb_error_cm']:g} cm. "
        f"**Slopes**: {s['slope_deg']:g} deg up over {s['slope_length_legs']:g} leg lengths, "
        f"a landing, as much down. **Stepping stones**: {s['stones_count']} stones "
        f"{s['stones_length_soles']:g} sole lengths long, {s['stones_gap_share']:.0%} of the "
        f"leg apart, over a pit. **Rough patch**: {s['rough_length_blocks']} x "
        f"{s['rough_width_blocks']} blocks of {s['rough_block_soles']:g} sole lengths, up to "
        f"{s['rough_height_share']:.0%} of the leg high (seed {s['seed']}). The command: "
        "forward, its nominal stride "
        f"{' or '.join(f'{v:g}' for v in s['stride_shares'])} x the stair run within the legs' "
        "flat reach (the planner moves the landings onto the treads), as many steps as leave "
        "the terrain behind. Settings: `results.csv`, `sweep.json`.\n"
    )


__all__ = ["TerrainExperiment"]
