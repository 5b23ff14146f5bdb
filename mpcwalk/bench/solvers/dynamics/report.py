"""``inverse_dynamics.md``: the report of the inverse-dynamics stage, from its JSON payload
(``inverse_dynamics.json.gz``), and the section ``report.md`` gains when the stage ran."""

import gzip
import json
import math
from pathlib import Path

import numpy as np

from mpcwalk.bench.solvers.backends.settings import settings_table
from mpcwalk.bench.solvers.report.scaling import markdown_table
from mpcwalk.bench.solvers.results import format_time
from mpcwalk.bench.solvers.tolerances import LEVEL_NAMES, tolerance_levels

#: The stage's payload in the output directory.
DYNAMICS_FILE = "inverse_dynamics.json.gz"
#: The stage's report in the output directory.
DYNAMICS_REPORT = "inverse_dynamics.md"
#: Success share from which a back-end is a candidate for the fastest (ratio 1).
RATIO_MIN_SUCCESS = 0.95


def _times(rows: list[dict]) -> tuple[float, float]:
    """Median and 99th percentile [s] of the successful solves of ``rows``."""
    times = [r["runtime"] for r in rows if r["success"]]
    if not times:
        return math.nan, math.nan
    return float(np.median(times)), float(np.percentile(times, 99))


def _share(rows: list[dict]) -> float:
    return float(np.mean([r["success"] for r in rows])) if rows else math.nan


def _pct(value: float) -> str:
    return "-" if not math.isfinite(value) else f"{100 * value:.0f}%"


def _worst(rows: list[dict], key: str) -> str:
    values = [abs(r[key]) for r in rows if r["success"] and math.isfinite(r[key])]
    return f"{max(values):.1e}" if values else "-"


def level_table(rows: list[dict], backends: list[str], level: str) -> tuple[str, list]:
    """The table of one tolerance level (rows by cold median) and its sorted entries
    ``(back-end, success cold, median cold [s])``."""
    mine = [r for r in rows if r["tolerance"] == level]
    stats = []
    for backend in backends:
        cold = [r for r in mine if r["solver"] == backend and r["start"] == "cold"]
        warm = [r for r in mine if r["solver"] == backend and r["start"] == "warm"]
        if cold:
            stats.append((backend, cold, warm, _share(cold), *_times(cold), *_times(warm)))
    fast = [s[4] for s in stats if s[3] >= RATIO_MIN_SUCCESS and math.isfinite(s[4])]
    fastest = min(fast) if fast else math.nan
    stats.sort(key=lambda s: (not math.isfinite(s[4]), s[4]))
    body = []
    for backend, cold, warm, share, c50, c99, w50, w99 in stats:
        ratio = c50 / fastest if math.isfinite(c50) and math.isfinite(fastest) else math.nan
        body.append(
            [
                backend,
                _pct(share),
                _pct(_share(warm)) if warm else "-",
                format_time(c50),
                format_time(c99),
                format_time(w50) if warm else "-",
                format_time(w99) if warm else "-",
                f"{ratio:.1f}" if math.isfinite(ratio) else "-",
                _worst(cold + warm, "torque_error"),
                _worst(cold + warm, "cost_gap"),
                _worst(cold + warm, "base_residual"),
            ]
        )
    header = [
        "back-end",
        "success cold",
        "success warm",
        "cold median",
        "cold p99",
        "warm median",
        "warm p99",
        "cold median / fastest",
        "torque error max [N m]",
        "cost gap max",
        "base residual max",
    ]
    return markdown_table(header, body), [(s[0], s[3], s[4]) for s in stats]


def loop_table(loops: list[dict]) -> str:
    """The table of the in-loop torque walks."""
    body = []
    for r in sorted(loops, key=lambda r: (r["tick_median_us"] is None, r["tick_median_us"])):
        num = lambda v, f="{:.0f}": "-" if v is None or not math.isfinite(v) else f.format(v)
        fell = "yes: " + (r["fall_reason"] or r["error"] or "")[:60] if r["fell"] else "no"
        body.append(
            [
                r["backend"],
                r["steps"] or "-",
                fell,
                "-" if r["dynamics_failures"] is None else r["dynamics_failures"],
                num(r["tick_median_us"]),
                num(r["tick_p99_us"]),
                num(r["solve_median_us"]),
                num(r["solve_p99_us"]),
                num(r["real_time_factor"], "{:.2f}"),
                num(r["foot_position_error_cm_max"], "{:.2f}"),
            ]
        )
    header = [
        "back-end",
        "steps",
        "fell",
        "ID failures",
        "ID tick median [us]",
        "ID tick p99 [us]",
        "solve median [us]",
        "solve p99 [us]",
        "real-time factor",
        "foot error max [cm]",
    ]
    return markdown_table(header, body)


def headline(payload: dict) -> list[str]:
    """The headline lines (also the section of ``report.md``)."""
    rows, loops = payload["rows"], payload["loops"]
    lines = [
        f"{len(payload['problems'])} problems, {len(rows)} solves, "
        f"{len(payload['backends'])} back-ends."
    ]
    for level in ("default", "mid"):
        _, stats = level_table(rows, payload["backends"], level)
        good = [s for s in stats if s[1] >= RATIO_MIN_SUCCESS and math.isfinite(s[2])][:4]
        if good:
            lines.append(
                f"{level} level, cold start, fastest back-ends succeeding on at least "
                f"{RATIO_MIN_SUCCESS:.0%} of the problems (median solve, success): "
                + ", ".join(f"{b} {format_time(t)} ({_pct(s)})" for b, s, t in good)
            )
    if loops:
        up = [r for r in loops if not r["fell"]]
        clean = [r for r in up if r["dynamics_failures"] == 0]
        lines.append(
            f"In the loop ({loops[0]['robot']}, torque mode): {len(up)} of {len(loops)} "
            f"back-ends kept the robot up, {len(clean)} without an inverse-dynamics failure"
            + (
                f"; fastest median ID tick {min(r['tick_median_us'] for r in up):.0f} us "
                f"({min(up, key=lambda r: r['tick_median_us'])['backend']})"
                if up
                else ""
            )
            + "."
        )
    return lines


def _load_note(payload: dict) -> str:
    load = payload.get("load_average") or {}
    before, after = load.get("before"), load.get("after")
    if before is None:
        return "The machine is shared with other engineers' work."
    idle = max(before, after or 0.0) < 0.3
    return (
        f"The machine is shared with other engineers' work; the 1-minute load average was "
        f"{before:.2f} before the stage and {after:.2f} after it on "
        f"{payload.get('cores', '?')} cores: "
        + (
            "idle."
            if idle
            else "not idle, absolute times carry that load; ratios from the "
            "same run are the robust numbers."
        )
    )


def compose(payload: dict) -> str:
    """The text of ``inverse_dynamics.md``."""
    d = payload.get("durations", {})
    stages = ", ".join(f"{k} {v / 60:.1f} min" for k, v in d.items())
    config = payload["config"]
    command = payload.get("command") or "mpcwalk bench solvers --families inverse-dynamics"
    parts = [
        "# Solver benchmark: the inverse-dynamics QP of torque control",
        f"Command: `{command}` ({payload.get('date', '')}; stages: {stages}).",
        f"Machine: {payload.get('machine', '')}. Timing: one Ray timing actor (one CPU, "
        "single-threaded numerical libraries) timed every solve, one at a time; the walks "
        "ran before, one Ray task at a time, the in-loop walks after, one at a time. "
        + _load_note(payload),
        "## Headline",
        "\n".join(f"- {line}" for line in headline(payload)),
        "## Problems",
        f"Snapshots of the whole-body inverse dynamics' QP "
        "(`mpcwalk.ik.InverseDynamicsQP`: accelerations and sole wrenches, floating-base "
        "and contact equalities, wrench cones and torque limits) along torque-mode walks "
        f"(`mpcwalk walk --robot R --controller mpc --actuation torque --vx "
        f"{config['dynamics_vx']} --steps {config['dynamics_nb_steps']}`): "
        f"{config['dynamics_nb_per_phase']} ticks per walk in double support, in single "
        "support and in the load ramp after a touch-down, and "
        f"{config['dynamics_nb_pushed']} in single support with a push of "
        f"{config['dynamics_push_speed']} m/s on the base velocity. Warm starts solve the "
        f"{config['warmup_ticks']} ticks before first (warm-started from the tick before "
        "when the contacts did not change, as the controller does).",
        markdown_table(
            ["robot", "walk", "ticks"],
            [
                [w["robot"], ("fell, " if w["fell"] else "") + w["steps"] + " steps", w["nb_ticks"]]
                for w in payload["walks"]
            ],
        ),
        _problem_table(payload["problems"]),
        "## Solves",
        "Success is the benchmark's (qpbenchmark's) test: primal and dual residuals and "
        "duality gap, recomputed on the same problem, under the level's tolerance, within "
        f"the time limit of {config['time_limit']} s. Times are over the successful solves "
        "(the back-end call, updates included); the ratio is the cold median over the "
        f"fastest cold median among back-ends succeeding on at least "
        f"{RATIO_MIN_SUCCESS:.0%}. Torque error: largest joint-torque difference to the "
        "reference solution (an exact active-set solve: quadprog); cost gap: cost minus "
        "the reference's over 1 + |reference's|; base residual: largest residual of the "
        "floating base's six equations of motion [N, N m].",
    ]
    for level in [lv for lv in LEVEL_NAMES if any(r["tolerance"] == lv for r in payload["rows"])]:
        parts += [f"### {level}", level_table(payload["rows"], payload["backends"], level)[0]]
    parts += [
        "## In the loop",
        f"Each back-end succeeding offline on at least "
        f"{config['dynamics_loop_min_success']:.0%} of the {config['dynamics_loop_robot']} "
        "problems (default level, cold) as the inverse dynamics' solver of a torque walk "
        f"(`mpcwalk walk --robot {config['dynamics_loop_robot']} --controller mpc "
        f"--actuation torque --steps {config['dynamics_loop_nb_steps']} "
        "--dynamics-solver NAME`, the back-end's registry defaults). ID tick: the whole inverse-dynamics tick (kinematics, QP build, solve, "
        "torques); solve: the back-end's call.",
        loop_table(payload["loops"]) if payload["loops"] else "Not run.",
        "## Settings per tolerance level",
        settings_table(tolerance_levels(config["time_limit"]), payload["backends"]),
    ]
    return "\n\n".join(parts) + "\n"


def _problem_table(problems: list[dict]) -> str:
    groups: dict[tuple, list[dict]] = {}
    for p in problems:
        groups.setdefault((p["robot"], p["phase"] + (" + push" if p["pushed"] else "")), []).append(
            p
        )
    body = [
        [
            robot,
            phase,
            len(ps),
            ", ".join(sorted({f"{p['n']} x {p['m']} ({p['m_eq']} eq.)" for p in ps})),
        ]
        for (robot, phase), ps in groups.items()
    ]
    return markdown_table(["robot", "phase", "problems", "variables x rows"], body)


def write_payload(out_dir: Path, payload: dict) -> Path:
    """Write the stage's payload (gzip-compressed JSON) into ``out_dir``."""
    path = Path(out_dir) / DYNAMICS_FILE
    with gzip.open(path, "wt") as stream:
        json.dump(payload, stream, separators=(",", ":"), default=str)
    return path


def read_payload(out_dir: Path) -> dict:
    """The stage's payload written into ``out_dir``."""
    with gzip.open(Path(out_dir) / DYNAMICS_FILE, "rt") as stream:
        payload: dict = json.load(stream)
    return payload


def write_dynamics_report(out_dir: Path, payload: dict) -> Path:
    """Write ``inverse_dynamics.md`` into ``out_dir``."""
    path = Path(out_dir) / DYNAMICS_REPORT
    path.write_text(compose(payload))
    return path


def dynamics_section(out_dir: Path) -> str:
    """The section ``report.md`` gains when ``out_dir`` holds the stage's payload ("" when
    it does not)."""
    path = Path(out_dir) / DYNAMICS_FILE
    if not path.exists():
        return ""
    payload = read_payload(out_dir)
    lines = "\n".join(f"- {line}" for line in headline(payload))
    return (
        "\n## Inverse dynamics (torque control)\n\n"
        f"The QP of the whole-body inverse dynamics, taken along torque-mode walks: "
        f"[{DYNAMICS_REPORT}]({DYNAMICS_REPORT}) (`{payload.get('command', '')}`, "
        f"{payload.get('date', '')}).\n\n{lines}\n"
    )
