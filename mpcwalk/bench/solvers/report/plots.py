"""Figures of the solver benchmark (used by the report and the notebook)."""

import math
from collections.abc import Iterable, Sequence

import numpy as np

from mpcwalk.bench.solvers.results import horizon_growth, in_set, select, solvers_of, success_rates
from mpcwalk.bench.solvers.tolerances import LEVEL_NAMES


def _colors(names: Iterable[str]) -> dict[str, tuple]:
    import matplotlib.pyplot as plt

    cmap = plt.get_cmap("tab20")
    return {name: cmap(i % 20) for i, name in enumerate(sorted(names))}


def plot_time_vs_horizon(
    rows: list[dict],
    *,
    level: str = "default",
    start: str = "cold",
    formulations: Sequence[str] = ("dense", "sparse"),
):
    """Median solve time against the horizon, log-log, one panel per
    formulation, with the fitted exponent of each back-end in the legend."""
    import matplotlib.pyplot as plt

    growth = horizon_growth(in_set(rows, "sweep"), level=level, start=start)
    colors = _colors({s for _, s in growth})
    fig, axes = plt.subplots(
        1, len(formulations), figsize=(7 * len(formulations), 5.5), sharey=True, squeeze=False
    )
    for ax, formulation in zip(axes[0], formulations):
        for (form, solver), g in sorted(growth.items()):
            if form != formulation:
                continue
            h, t = np.array(g["horizons"], float), np.array(g["medians"], float)
            if not np.isfinite(t).any():
                continue
            label = f"{solver} ({g['exponent']:.2f})" if math.isfinite(g["exponent"]) else solver
            ax.loglog(h, t * 1e3, "o-", color=colors[solver], label=label, ms=4)
        for slope, style in ((1, ":"), (2, "--")):
            ax.loglog(
                [16, 320], [0.05 * (x / 16) ** slope for x in (16, 320)], style, color="gray", lw=1
            )
        ax.set_title(f"{formulation} formulation ({level} settings, {start} start)")
        ax.set_xlabel("horizon N [samples] (1.6 s)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, title="back-end (fitted exponent)", title_fontsize=7, ncol=2)
    axes[0][0].set_ylabel("median solve time [ms]  (gray: slopes 1 and 2)")
    fig.tight_layout()
    return fig


def plot_success_rates(
    rows: list[dict], *, start: str = "cold", formulations: Sequence[str] = ("dense", "sparse")
):
    """Success rate per tolerance level and back-end (main set)."""
    import matplotlib.pyplot as plt

    main = in_set(rows, "main")
    levels = [lv for lv in LEVEL_NAMES if select(main, tolerance=lv)]
    fig, axes = plt.subplots(
        len(formulations), 1, figsize=(12, 3.6 * len(formulations)), squeeze=False
    )
    width = 0.8 / max(1, len(levels))
    for ax, formulation in zip(axes[:, 0], formulations):
        sel = select(main, formulation=formulation, start=start)
        rates = success_rates(sel, levels)
        solvers = list(rates)
        x = np.arange(len(solvers))
        for i, level in enumerate(levels):
            ax.bar(
                x + (i - (len(levels) - 1) / 2) * width,
                [rates[s][level] for s in solvers],
                width,
                label=level,
            )
        ax.set_xticks(x, solvers, rotation=40, ha="right", fontsize=8)
        ax.set_ylim(0, 105)
        ax.set_ylabel("success [%]")
        ax.set_title(f"{formulation} formulation, {start} start")
        ax.legend(fontsize=7, ncol=len(levels), loc="lower right")
        ax.grid(True, axis="y", alpha=0.3)
    fig.tight_layout()
    return fig


def plot_tick_histograms(
    runs: list[dict],
    *,
    control_period: float = 0.01,
    max_panels: int = 32,
    what: str = "solve time per tick",
):
    """Histogram of per-tick times of each in-loop walk (log scale)."""
    import matplotlib.pyplot as plt

    runs = sorted(
        (r for r in runs if r.get("solve_times_us")),
        key=lambda r: (r["formulation"], np.median(r["solve_times_us"])),
    )[:max_panels]
    if not runs:
        fig, ax = plt.subplots(figsize=(6, 2))
        ax.text(0.5, 0.5, "no in-loop run", ha="center", va="center")
        ax.axis("off")
        return fig
    cols = 4
    nrows = int(math.ceil(len(runs) / cols))
    fig, axes = plt.subplots(nrows, cols, figsize=(14, 2.4 * nrows), squeeze=False, sharex=True)
    times = np.concatenate([np.asarray(r["solve_times_us"], float) for r in runs])
    positive = times[times > 0]
    low = max(1.0, np.percentile(positive, 0.1) / 2) if positive.size else 1.0
    high = max(control_period * 1e6 * 2, np.max(times) * 1.2 if times.size else 1.0)
    bins = np.geomspace(low, high, 50)
    for ax, run in zip(axes.ravel(), runs):
        t = np.clip(np.asarray(run["solve_times_us"], float), low, high)
        ax.hist(t, bins=bins, color="tab:blue" if run["formulation"] == "dense" else "tab:orange")
        ax.axvline(control_period * 1e6, color="red", lw=1)
        ax.set_xscale("log")
        fails = run["failures"]
        ax.set_title(
            f"{run['backend']} {run['formulation']}" + (f", {fails} failed" if fails else ""),
            fontsize=8,
        )
        ax.tick_params(labelsize=7)
    for ax in axes.ravel()[len(runs) :]:
        ax.axis("off")
    for ax in axes[-1]:
        ax.set_xlabel(f"{what} [us] (red: control period)", fontsize=7)
    fig.tight_layout()
    return fig


def save_figure(fig, path) -> None:
    """Save and close a figure."""
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=110)
    plt.close(fig)


def unused_solvers(rows: list[dict], names: Sequence[str] | None = None) -> list[str]:
    """Back-ends of ``names`` that have no row (for the report's notes)."""
    present = set(solvers_of(rows))
    return [n for n in (names or []) if n not in present]
