"""``report.md`` of the solver benchmark: tables, headline numbers, figures."""

import datetime
import math
from pathlib import Path

import numpy as np

from mpcwalk.bench.solvers.backends.registry import (
    KNOWN_SLOW_BACKENDS,
    is_applicable,
    supports_warm_start,
)
from mpcwalk.bench.solvers.backends.settings import settings_table
from mpcwalk.bench.solvers.config import SolverBenchConfig
from mpcwalk.bench.solvers.dynamics.report import dynamics_section
from mpcwalk.bench.solvers.problems.families import PENDING_FAMILIES, get_family
from mpcwalk.bench.solvers.report.plots import (
    plot_success_rates,
    plot_tick_histograms,
    plot_time_vs_horizon,
    save_figure,
)
from mpcwalk.bench.solvers.report.scaling import (
    growth_headline,
    growth_section,
    markdown_table,
    ticks_section,
)
from mpcwalk.bench.solvers.results import (
    format_time,
    in_set,
    select,
    shgeom_runtimes,
    solvers_of,
    success_rates,
    timing_stats,
)
from mpcwalk.bench.solvers.tolerances import LEVEL_NAMES, tolerance_levels


def _label(solver: str) -> str:
    """Back-end name, marked when it was only sampled (known slow)."""
    return f"{solver} (sampled)" if solver in KNOWN_SLOW_BACKENDS else solver


def _pct(v: float) -> str:
    return "-" if not math.isfinite(v) else f"{v:.0f}"


def _levels(rows: list[dict]) -> list[str]:
    return [lv for lv in LEVEL_NAMES if select(rows, tolerance=lv)]


def problems_section(rows: list[dict], config: SolverBenchConfig, extras: dict) -> str:
    main = in_set(rows, "main")
    body = []
    for name in config.mpc_families:
        fam = get_family(name)
        p = fam.parameters
        sel = select(main, family=name)
        sizes = {
            f: (r["n"], r["m"]) for f in config.formulations for r in select(sel, formulation=f)[:1]
        }
        size = ", ".join(f"{f} {n} x {m}" for f, (n, m) in sizes.items())
        body.append(
            [
                name,
                fam.description,
                f"{p.horizon} x {p.sampling_period:g} s",
                fam.timing,
                size,
                len({r["problem"] for r in sel}),
            ]
        )
    text = markdown_table(
        ["family", "QP", "horizon", "timing", "variables x rows", "problems"], body
    )
    dropped = [n for p in extras.get("prepared", []) for n in p["dropped"]]
    sweep = sorted({r["horizon"] for r in in_set(rows, "sweep")})
    text += (
        f"\n\nProblems are snapshots of the QP along {config.nb_steps}-step walks "
        f"({', '.join(config.walks)}; paper M timing, static-qp on the slow timing T = 2 s, "
        f"r_ds = 0.5), {config.nb_nominal} ticks per walk at the walk's own state and "
        f"{config.nb_pushed} with a push of {config.push_speed} m/s on the CoM velocity. "
        f"Warm starts solve the {config.warmup_ticks} preceding ticks of the walk first. "
        f"Horizon sweep: family `{config.sweep_family}`, walk `{config.sweep_walk}`, horizons "
        f"{sweep} samples over the same 1.6 s, levels {', '.join(config.sweep_levels)}, "
        f"{' and '.join(config.sweep_starts)} start. "
        f"Dropped as infeasible (Clarabel): {len(dropped)}"
        + (f" ({', '.join(dropped[:8])}{'...' if len(dropped) > 8 else ''})" if dropped else "")
        + ". Not benchmarked: "
        + "; ".join(f"`{k}` ({v})" for k, v in PENDING_FAMILIES.items())
        + "."
    )
    return text


def success_section(rows: list[dict], config: SolverBenchConfig) -> str:
    main = in_set(rows, "main")
    levels = _levels(main)
    parts = []
    for formulation in config.formulations:
        for start in config.starts:
            sel = select(main, formulation=formulation, start=start)
            if not sel:
                continue
            rates = success_rates(sel, levels)
            body = [[_label(s)] + [_pct(rates[s][lv]) for lv in levels] for s in rates]
            parts.append(
                f"**{formulation}, {start} start** (success [%])\n\n"
                + markdown_table(["back-end"] + levels, body)
            )
    return "\n\n".join(parts)


def shgeom_section(rows: list[dict], config: SolverBenchConfig) -> str:
    main = in_set(rows, "main")
    levels = _levels(main)
    parts = []
    for formulation in config.formulations:
        for start in config.starts:
            sel = [
                r
                for r in select(main, formulation=formulation, start=start)
                if r["solver"] not in KNOWN_SLOW_BACKENDS
            ]
            if not sel:
                continue
            per = {lv: shgeom_runtimes(sel, lv, config.time_limit) for lv in levels}
            body = [
                [s]
                + [
                    f"{per[lv][s][0]:.1f} ({format_time(per[lv][s][1])})" if s in per[lv] else "-"
                    for lv in levels
                ]
                for s in solvers_of(sel)
            ]
            body.sort(key=lambda r: float(r[1].split()[0]) if r[1] != "-" else math.inf)
            parts.append(
                f"**{formulation}, {start} start**: relative to the best "
                "(absolute mean)\n\n" + markdown_table(["back-end"] + levels, body)
            )
    return "\n\n".join(parts)


def family_section(rows: list[dict], config: SolverBenchConfig, level: str) -> str:
    main = select(in_set(rows, "main"), tolerance=level)
    parts = []
    for formulation in config.formulations:
        sel = select(main, formulation=formulation)
        body = []
        for solver in solvers_of(sel):
            for start in config.starts:
                mine = select(sel, solver=solver, start=start)
                if not mine:
                    continue
                cells = []
                for fam in config.mpc_families:
                    med, p99, count = timing_stats(select(mine, family=fam))
                    total = len(select(mine, family=fam))
                    cells.append(f"{format_time(med)} / {format_time(p99)} ({count}/{total})")
                body.append([_label(solver), start] + cells)
        body.sort(key=lambda r: (r[1], _sort_time(r[2])))
        parts.append(
            f"**{formulation}** (median / p99 of successful solves, successes/solves)"
            "\n\n" + markdown_table(["back-end", "start"] + list(config.mpc_families), body)
        )
    return "\n\n".join(parts)


def _sort_time(cell: str) -> float:
    head = cell.split(" / ")[0]
    if head == "-":
        return math.inf
    value, unit = head.split()
    return float(value) * {"us": 1e-6, "ms": 1e-3, "s": 1.0}[unit]


def write_report(out_dir: Path, rows: list[dict], config: SolverBenchConfig, extras: dict) -> Path:
    """Write ``report.md`` and its figures into ``out_dir``."""
    out_dir = Path(out_dir)
    figures = {}
    if in_set(rows, "sweep"):
        save_figure(
            plot_time_vs_horizon(rows, level=config.sweep_levels[0]),
            out_dir / "time_vs_horizon.png",
        )
        figures["horizon"] = "time_vs_horizon.png"
    if in_set(rows, "main"):
        save_figure(plot_success_rates(rows), out_dir / "success_rates.png")
        figures["success"] = "success_rates.png"
    loops = extras.get("loops") or {}
    for plant, name, key, what in (
        ("lipm", "tick_histograms.png", "ticks", "QP solve time per tick"),
        ("mujoco", "mujoco_tick_histograms.png", "mujoco_ticks", "generator tick"),
    ):
        if loops.get(plant):
            save_figure(
                plot_tick_histograms(loops[plant], control_period=config.control_period, what=what),
                out_dir / name,
            )
            figures[key] = name
    from mpcwalk.bench.solvers.report.text import compose_report

    text = compose_report(
        rows,
        config,
        extras,
        figures,
        sections={
            "problems": problems_section(rows, config, extras),
            "success": success_section(rows, config),
            "shgeom": shgeom_section(rows, config),
            "family_default": family_section(rows, config, "default"),
            "family_mid": family_section(rows, config, "mid") if "mid" in config.levels else "",
            "growth": growth_section(rows, config) if in_set(rows, "sweep") else "Not run.",
            "growth_headline": growth_headline(rows, config.sweep_levels[0]),
            "ticks": ticks_section(extras),
            "settings": settings_table(
                tolerance_levels(config.time_limit), extras.get("backends", solvers_of(rows))
            ),
            "not_applicable": ", ".join(
                f"{b} ({f})"
                for b in extras.get("backends", [])
                for f in config.formulations
                if not is_applicable(b, f)
            ),
            "warm": ", ".join(b for b in extras.get("backends", []) if supports_warm_start(b)),
            "date": datetime.datetime.now().strftime("%Y-%m-%d"),
            "median_warm_cold": _warm_cold(rows, config),
        },
    )
    path = out_dir / "report.md"
    path.write_text(text + dynamics_section(out_dir))
    return path


def _warm_cold(rows: list[dict], config: SolverBenchConfig) -> str:
    sel = select(in_set(rows, "main"), family=config.sweep_family, tolerance="default")
    body = []
    for formulation in config.formulations:
        for solver in solvers_of(select(sel, formulation=formulation, start="warm")):
            mine = select(sel, formulation=formulation, solver=solver)
            cold = timing_stats(select(mine, start="cold"))[0]
            warm = timing_stats(select(mine, start="warm"))[0]
            ratio = warm / cold if cold > 0 and math.isfinite(warm) else np.nan
            body.append(
                [
                    formulation,
                    solver,
                    format_time(cold),
                    format_time(warm),
                    f"{ratio:.2f}" if math.isfinite(ratio) else "-",
                ]
            )
    return markdown_table(
        ["formulation", "back-end", "cold median", "warm median", "warm / cold"], body
    )
