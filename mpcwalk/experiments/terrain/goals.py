"""The issue's goals checked on the terrain experiment's rows (kept step durations and strides): each robot up
and down 5 stairs of a rise of at least 25 % of its leg length and a run no longer than 1.5
sole lengths without falling, with ``mpc``, ``mpc-steps`` and paper A's static gait,
landing errors under 1 cm on average; 15 deg slopes up and down; stepping stones 40 % of
the leg length apart; a rough patch of blocks up to 10 % of the leg length."""

from typing import Any

from mpcwalk.experiments.terrain.report import (
    GOAL_CONTROLLERS,
    GOAL_LANDING_CM,
    kept_rows,
    short_refusal,
)

#: The goals' sizes (as the issue states them).
GOAL_RUN_SOLES = 1.5


def _verdict(ok: bool) -> str:
    return "**met**" if ok else "**not met**"


def _walk_text(row: dict[str, Any]) -> str:
    if row.get("error"):
        return "crashed"
    if row.get("refused"):
        return f"refused ({short_refusal(row['refused'])})"
    steps = f"{row.get('steps_completed')}/{row.get('steps_planned')} steps"
    mean = row.get("landing_error_3d_cm_mean")
    landing = "" if mean is None else f", landing error mean {mean:.2f} cm"
    if row.get("outcome") != "walked":
        return f"{row.get('outcome')} after {steps}{landing}"
    return f"{'crossed' if row.get('climbed') else 'walked, not crossed'}: {steps}{landing}"


def _goal_rows(rows: list[dict[str, Any]], terrain: str) -> list[dict[str, Any]]:
    return [r for r in kept_rows(rows, terrain) if r["controller"] in GOAL_CONTROLLERS]


def stairs_goal(rows: list[dict[str, Any]], settings: dict[str, Any]) -> str:
    """The stairs goal: the goal's walk of each goal controller crossed with a mean 3D
    landing error under :data:`GOAL_LANDING_CM`."""
    share = float(settings.get("goal_rise_share", 0.25))
    run = float(settings.get("run_soles", GOAL_RUN_SOLES))
    checked = _goal_rows(rows, "stairs")
    good = [
        r
        for r in checked
        if r.get("climbed") and (r.get("landing_error_3d_cm_mean") or 1e9) < GOAL_LANDING_CM
    ]
    missing = sorted(
        {(p["robot"], c) for p in settings.get("robots", []) for c in GOAL_CONTROLLERS}
        - {(r["robot"], r["controller"]) for r in checked}
    )
    ok = bool(checked) and len(good) == len(checked) and not missing and run <= GOAL_RUN_SOLES
    lines = [
        f"- **Stairs** (5 up, a landing, 5 down; rise {share:.0%} of the leg length, run "
        f"{run:g} sole lengths or the sole with its margins): {_verdict(ok)}. "
        f"{len(good)}/{len(checked)} walks of {', '.join(GOAL_CONTROLLERS)} crossed with a "
        f"mean 3D landing error under {GOAL_LANDING_CM:g} cm"
        + (f"; not run here: {', '.join(f'{r}/{c}' for r, c in missing)}" if missing else "")
        + ".",
    ]
    lines += [f"  - {r['robot']}, `{r['controller']}`: {_walk_text(r)}" for r in checked]
    return "\n".join(lines)


def crossing_goal(rows: list[dict[str, Any]], terrain: str, what: str) -> str:
    """A terrain's goal: every robot crosses it with every goal controller (the other
    controllers' walks are in the table)."""
    checked = _goal_rows(rows, terrain)
    if not checked:
        return f"- **{what}**: not run."
    crossed = [r for r in checked if r.get("climbed")]
    ok = len(crossed) == len(checked)
    lines = [
        f"- **{what}**: {_verdict(ok)}. {len(crossed)}/{len(checked)} walks of "
        f"{', '.join(GOAL_CONTROLLERS)} crossed."
    ]
    lines += [f"  - {r['robot']}, `{r['controller']}`: {_walk_text(r)}" for r in checked]
    return "\n".join(lines)


def goals_text(rows: list[dict[str, Any]], settings: dict[str, Any]) -> str:
    """Every goal, met or not, with the measured figures."""
    terrains = settings.get("terrains", [])
    parts = [stairs_goal(rows, settings)] if "stairs" in terrains else ["- **Stairs**: not run."]
    slope = f"Slopes of {float(settings.get('slope_deg', 15.0)):g} deg up and down"
    gap = float(settings.get("stones_gap_share", 0.4))
    height = float(settings.get("rough_height_share", 0.1))
    for terrain, what in (
        ("slope", slope),
        ("stones", f"Stepping stones {gap:.0%} of the leg length apart"),
        ("rough", f"Rough patch of blocks up to {height:.0%} of the leg length"),
    ):
        parts.append(
            crossing_goal(rows, terrain, what) if terrain in terrains else f"- **{what}**: not run."
        )
    return (
        "A walk *crossed* when it did not fall, completed all its steps and its largest 3D "
        f"landing error stayed under {float(settings.get('climb_error_cm', 5.0)):g} cm.\n\n"
        + "\n".join(parts)
        + "\n"
    )


__all__ = ["GOAL_RUN_SOLES", "crossing_goal", "goals_text", "stairs_goal"]
