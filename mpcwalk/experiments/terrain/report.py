"""The terrain experiment's report: the step duration and stride kept per robot and
controller, the largest
rise climbed next to the peers' figure, the walks at the goal's rise, the slopes, stepping
stones and rough patch, the crashes, and the issue's goals checked on them."""

from typing import Any

from mpcwalk.experiments.reporting import table
from mpcwalk.experiments.terrain.cases import timing_of

#: The controllers the stairs goal names (paper A's static gait among them).
GOAL_CONTROLLERS = ("mpc", "mpc-steps", "paper-a")
#: Largest mean 3D landing error of the goal [cm].
GOAL_LANDING_CM = 1.0
#: The peers' figure, not measured here.
PEERS = (
    "Peers' figure (published, not measured here): HRP-4 climbed an industrial staircase of "
    "18.5 cm steps with the LIPM walking controller of Caron et al. (2019)."
)


def variant_of(row: dict[str, Any]) -> str:
    """A row's step duration and stride (:attr:`TerrainCase.variant`)."""
    return str(row["variant"])


def _variant_key(row: dict[str, Any]) -> tuple[float, float, float, float]:
    """Higher climbs first, then the goal's walk that went farther (its share of the
    steps), then the faster step, then the longer stride."""
    timing = timing_of(row)
    planned = float(row.get("steps_planned") or 0)
    return (
        float(row.get("largest_rise_m") or 0.0),
        float(row.get("steps_completed") or 0) / planned if planned else 0.0,
        -(float(timing) if timing != "own" else 1e9),
        float(row.get("stride_share") or 0.0),
    )


def kept_variants(rows: list[dict[str, Any]]) -> dict[tuple[str, str], str]:
    """Per robot and controller, the step duration and stride whose stairs climb higher."""
    best: dict[tuple[str, str], dict[str, Any]] = {}
    for row in rows:
        if row["terrain"] != "stairs":
            continue
        key = (row["robot"], row["controller"])
        if key not in best or _variant_key(row) > _variant_key(best[key]):
            best[key] = row
    return {key: variant_of(row) for key, row in best.items()}


def kept_rows(rows: list[dict[str, Any]], terrain: str) -> list[dict[str, Any]]:
    """The rows of ``terrain`` at the kept step durations and strides."""
    kept = kept_variants(rows)
    return [
        r
        for r in rows
        if r["terrain"] == terrain and kept.get((r["robot"], r["controller"])) == variant_of(r)
    ]


def short_refusal(message: str) -> str:
    """A refusal in a few words: its error's name and first clause (the whole message is
    in the Refusals section)."""
    name, _, text = str(message).partition(": ")
    head = text.split(";")[0].split(". ")[0]
    return f"{name}: {head[:90]}{'...' if len(head) > 90 else ''}"


def _status(row: dict[str, Any]) -> str:
    if row.get("error"):
        return "crashed (see Crashes)"
    if row.get("refused"):
        return f"refused ({short_refusal(row['refused'])})"
    if row.get("outcome") == "walked":
        return "crossed" if row.get("climbed") else "walked, not all steps or landings off"
    return f"{row.get('outcome')} ({row.get('fall_reason') or row.get('stop_reason') or ''})"


def _shown_timing(row: dict[str, Any]) -> str:
    """The step duration, with the controller's own in brackets when it kept it."""
    timing = timing_of(row)
    own = row.get("step_duration_s")
    return f"own ({float(own):g})" if timing == "own" and own is not None else timing


def _cm(value: Any) -> float | None:
    return None if value is None else 100.0 * float(value)


def variant_table(rows: list[dict[str, Any]]) -> str:
    """Largest rise per robot, controller, step duration and stride, and the one kept."""
    kept = kept_variants(rows)
    lines = [
        {
            "robot": r["robot"],
            "controller": r["controller"],
            "timing": _shown_timing(r),
            "stride": r.get("stride_share"),
            "steps": (
                f"{r['steps_completed']}/{r['steps_planned']}"
                if r.get("steps_planned") is not None
                else None
            ),
            "rise": _cm(r.get("largest_rise_m")),
            "kept": kept.get((r["robot"], r["controller"])) == variant_of(r),
            "state": "" if r.get("climbed") or r.get("outcome") == "walked" else _status(r),
        }
        for r in rows
        if r["terrain"] == "stairs"
    ]
    return table(
        lines,
        [
            ("robot", "robot", 0),
            ("controller", "controller", 0),
            ("timing", "step duration T [s]", 0),
            ("stride", "stride [x run]", 2),
            ("rise", "largest rise climbed [cm]", 1),
            ("steps", "goal's walk: steps", 0),
            ("kept", "kept", 0),
            ("state", "goal's walk, when it did not walk", 0),
        ],
    )


def rise_table(kept: list[dict[str, Any]]) -> str:
    """Largest rise climbed per robot and controller (kept timing)."""
    lines = [
        {
            "robot": r["robot"],
            "controller": r["controller"],
            "timing": _shown_timing(r),
            "stride": r.get("stride_share"),
            "rise": _cm(r.get("largest_rise_m")),
            "share": None if r.get("largest_rise_share") is None else 100 * r["largest_rise_share"],
            "failed": _cm(r.get("smallest_failed_rise_m")),
            "reach": _cm(0.5 * float(r["leg_length_m"])) if r.get("leg_length_m") else None,
            "walks": r.get("nb_walks"),
            "note": _status(r) if r.get("refused") or r.get("error") else "",
        }
        for r in kept
    ]
    return table(
        lines,
        [
            ("robot", "robot", 0),
            ("controller", "controller", 0),
            ("timing", "T [s]", 0),
            ("stride", "stride [x run]", 2),
            ("rise", "largest rise climbed [cm]", 1),
            ("share", "of the leg length [%]", 1),
            ("failed", "smallest rise failed [cm]", 1),
            ("reach", "bisection's upper bound [cm]", 1),
            ("walks", "walks", 0),
            ("note", "note", 0),
        ],
    )


def walk_table(kept: list[dict[str, Any]], *, rise: bool = False) -> str:
    """One walk per robot and controller (kept timing): its outcome and terrain measures."""
    lines = [
        {
            **r,
            "timing": _shown_timing(r),
            "stride": r.get("stride_share"),
            "rise_cm": _cm(r.get("rise_m")),
            "steps": (
                f"{r['steps_completed']}/{r['steps_planned']}"
                if r.get("steps_planned") is not None
                else None
            ),
            "status": _status(r),
        }
        for r in kept
    ]
    columns = [
        ("robot", "robot", 0),
        ("controller", "controller", 0),
        ("timing", "T [s]", 0),
        ("stride", "stride [x run]", 2),
    ]
    columns += [("rise_cm", "rise [cm]", 1)] if rise else []
    columns += [
        ("status", "walked?", 0),
        ("steps", "steps completed", 0),
        ("landing_error_3d_cm_mean", "landing error 3D mean [cm]", 2),
        ("landing_error_3d_cm_max", "landing error 3D max [cm]", 2),
        ("tread_margin_cm_min", "tread margin min [cm]", 1),
        ("swing_clearance_cm_min", "swing clearance min [cm]", 1),
        ("toe_stubs", "toe stubs", 0),
    ]
    return table(lines, columns)


def refusals_text(rows: list[dict[str, Any]]) -> str:
    """Each refusal once, whole, with the cases it refused."""
    cases: dict[str, list[str]] = {}
    for row in rows:
        if row.get("refused") and not row.get("error"):
            cases.setdefault(str(row["refused"]), []).append(str(row["case_id"]))
    if not cases:
        return "The library refused no walk.\n"
    return (
        "\n".join(
            f"- {message} ({len(ids)} cases: {', '.join(f'`{i}`' for i in ids)})"
            for message, ids in cases.items()
        )
        + "\n"
    )


def trials_text(kept: list[dict[str, Any]]) -> str:
    """Each bisection's walks in the order they ran: rise [cm], climbed or why not."""
    lines = []
    for row in kept:
        trials = row.get("trials") or []
        if not trials:
            continue
        walks = "; ".join(
            f"{100.0 * float(rise):.2f} cm {'climbed' if ok else why}" for rise, ok, why in trials
        )
        lines.append(
            f"- {row['robot']}, `{row['controller']}` (T = {_shown_timing(row)} s, stride "
            f"{float(row['stride_share']):g} x the run): {walks}"
        )
    return "\n".join(lines) + "\n" if lines else "No bisection ran.\n"


def crashes_text(rows: list[dict[str, Any]]) -> str:
    """The cases that crashed (an exception that is not a refusal), with the error's head."""
    crashed = [r for r in rows if r.get("error")]
    if not crashed:
        return "No walk crashed (every failure is a fall, a stop, or a refusal).\n"
    return (
        "\n".join(f"- `{r['case_id']}`: {str(r['error']).splitlines()[0][:300]}" for r in crashed)
        + "\n"
    )


__all__ = [
    "GOAL_CONTROLLERS",
    "GOAL_LANDING_CM",
    "PEERS",
    "crashes_text",
    "kept_rows",
    "kept_variants",
    "refusals_text",
    "rise_table",
    "short_refusal",
    "trials_text",
    "variant_of",
    "variant_table",
    "walk_table",
]
