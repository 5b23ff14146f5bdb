"""Sections of the solver benchmark's report on scaling: the growth of the solve time with
the horizon, and the MPC tick against the closed form and the qpmpc peer."""

import math
from collections.abc import Sequence

from mpcwalk.bench.solvers.config import SolverBenchConfig
from mpcwalk.bench.solvers.results import format_time, horizon_growth, in_set

#: Sparse back-ends that exploit the structure (sparse factorisations).
STRUCTURE_EXPLOITING = (
    "osqp-direct",
    "osqp",
    "casadi-osqp",
    "qpalm",
    "piqp",
    "clarabel",
    "proxqp",
    "casadi-qrqp",
    "scs",
    "sip",
    "qtqp",
    "cvxopt",
)


def markdown_table(header: list[str], rows: Sequence[Sequence[object]]) -> str:
    """A markdown table of the cells (any value, written with ``str``)."""
    lines = ["| " + " | ".join(header) + " |", "|---" * len(header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def growth_section(rows: list[dict], config: SolverBenchConfig) -> str:
    sweep = in_set(rows, "sweep")
    parts = []
    for level, start in [(lv, st) for lv in config.sweep_levels for st in config.sweep_starts]:
        growth = horizon_growth(sweep, level=level, start=start, min_horizon=64)
        if not growth:
            continue
        horizons = sorted({h for g in growth.values() for h in g["horizons"]})
        body = []
        for (form, solver), g in sorted(
            growth.items(), key=lambda kv: (kv[0][0], _finite(kv[1]["exponent_tail"]))
        ):
            med = dict(zip(g["horizons"], g["medians"]))
            body.append(
                [form, solver]
                + [format_time(med.get(h)) for h in horizons]
                + [_exp(g["exponent"]), _exp(g["exponent_tail"])]
            )
        parts.append(
            f"**{level} settings, {start} start** (median of successful solves; exponent "
            "of a power-law fit over all horizons, and over N >= 64)\n\n"
            + markdown_table(
                ["formulation", "back-end"]
                + [f"N={h}" for h in horizons]
                + ["exponent", "exponent N>=64"],
                body,
            )
        )
    return "\n\n".join(parts)


def _finite(v: float) -> float:
    return v if math.isfinite(v) else math.inf


def _exp(v: float) -> str:
    return f"{v:.2f}" if math.isfinite(v) else "-"


def growth_headline(rows: list[dict], level: str) -> str:
    growth = horizon_growth(in_set(rows, "sweep"), level=level, start="cold", min_horizon=64)
    key = "exponent_tail"
    if not any(math.isfinite(g[key]) for g in growth.values()):
        key = "exponent"  # fewer than 3 horizons from 64 on: fit over all of them
    span = "N >= 64" if key == "exponent_tail" else "all horizons"
    best: dict[str, tuple[str, float]] = {}
    dense: dict[str, float] = {}
    for (form, solver), g in growth.items():
        e = g[key]
        if math.isfinite(e) and (form not in best or e < best[form][1]):
            best[form] = (solver, e)
    if not best:
        return "growth with the horizon: not enough horizons to fit"
    text = ", ".join(f"{form} {solver} {e:.2f}" for form, (solver, e) in sorted(best.items()))
    exploit = [
        (g[key], s)
        for (f, s), g in growth.items()
        if f == "sparse" and s in STRUCTURE_EXPLOITING and math.isfinite(g[key])
    ]
    linear = sorted(s for e, s in exploit if e <= 1.05)
    goal = (
        f"goal met: {len(linear)} structure-exploiting back-ends grow at most linearly "
        f"(exponent <= 1.05) on the sparse formulation ({', '.join(linear)})"
        if linear
        else "goal NOT met: no structure-exploiting back-end grows linearly on the sparse "
        "formulation"
    )
    for (form, solver), g in growth.items():
        if form == "dense" and math.isfinite(g[key]):
            dense[solver] = g[key]
    dense_text = (
        f"; dense exponents range from {min(dense.values()):.2f} to {max(dense.values()):.2f}"
        if dense
        else ""
    )
    return f"smallest exponents ({span}, {level} settings): {text}{dense_text}; {goal}"


def ticks_section(extras: dict) -> str:
    ticks = extras.get("ticks")
    if not ticks:
        return "Not run (`--no-ticks`)."
    from mpcwalk.bench.ticks import TickCase, format_table

    cases = [TickCase(**t) for t in ticks]
    return format_table(cases) + "\n\n" + ticks_headline(ticks)


def ticks_headline(ticks: list[dict]) -> str:
    ok = [t for t in ticks if not t["error"]]
    analytic = next((t for t in ok if t["generator"] == "analytic"), None)
    mpc = [t for t in ok if t["generator"] == "mpc"]
    peers = [t for t in ok if t["generator"] == "qpmpc"]
    if not (analytic and mpc):
        return ""
    best = min(mpc, key=lambda t: t["median_us"])
    text = (
        f"Fastest MPC tick: `{best['label']}` {best['median_us']:.0f} us median, "
        f"{best['median_us'] / analytic['median_us']:.1f}x the closed form "
        f"({analytic['median_us']:.0f} us)"
    )
    if peers:
        peer = min(peers, key=lambda t: t["median_us"])
        text += (
            f", {peer['median_us'] / best['median_us']:.1f}x faster than the fastest "
            f"qpmpc tick (`{peer['label']}`, {peer['median_us']:.0f} us)"
        )
        same = next((t for t in peers if t["solver"] == best["solver"]), None)
        if same is not None and same is not peer:
            text += (
                f" and {same['median_us'] / best['median_us']:.1f}x faster than qpmpc on "
                f"the same back-end ({same['median_us']:.0f} us)"
            )
    return text + " (same run)."
