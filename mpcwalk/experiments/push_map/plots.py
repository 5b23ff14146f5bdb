"""The push map's figures: per speed, polar plots of each controller's largest impulse per
direction and phase against the LIPM's bounds; per controller and speed, heat maps of the
ratio to ``paper-m``."""

import math
from pathlib import Path

from mpcwalk.experiments.push_map.cases import REFERENCE, PushMapConfig, cell_of, impulses, ratios


def polar_figures(out: Path, rows: list[dict], bounds, config: PushMapConfig) -> list[str]:
    """Per speed, one polar plot per phase: each controller's largest impulse per direction
    against the LIPM's 1- and 2-step bounds (and the 1-step bound with adapted timing)."""
    import matplotlib.pyplot as plt
    import numpy as np

    values, names = impulses(rows), []
    phases = sorted({cell_of(r)[1] for r in rows})
    directions = sorted({cell_of(r)[0] for r in rows})
    closed = [*directions, directions[0]]
    angles = np.radians(closed)
    for speed in config.speed_shares:
        cols = min(3, len(phases))
        nrows = math.ceil(len(phases) / cols)
        fig, axes = plt.subplots(
            nrows, cols, subplot_kw={"projection": "polar"}, figsize=(4.0 * cols, 3.8 * nrows)
        )
        for ax, phase in zip(np.atleast_1d(axes).ravel(), phases):
            for label, which, n, style, colour in (
                ("LIPM 1 step", "fixed", 1, "--", "black"),
                ("LIPM 2 steps", "fixed", 2, "--", "grey"),
                ("LIPM 1 step, adapted timing", "adaptive", 1, ":", "black"),
            ):
                line = [
                    getattr(bounds[(d, phase, speed)], which)[n]
                    if (d, phase, speed) in bounds
                    else np.nan
                    for d in closed
                ]
                ax.plot(angles, line, style, lw=1.0, label=label, color=colour)
            for controller, cells in values.items():
                line = [cells.get((d, phase, speed), np.nan) for d in closed]
                ax.plot(angles, line, "-o", ms=2, lw=1.2, label=controller)
            single = any(
                b.single_support for (d, p, s), b in bounds.items() if p == phase and s == speed
            )
            ax.set_title(
                f"phase {phase:.2f} ({'single' if single else 'double'} support)", fontsize=9
            )
            ax.tick_params(labelsize=7)
            ax.set_rlabel_position(112.5)
        top = max(
            [v for cells in values.values() for c, v in cells.items() if c[2] == speed]
            + [max(b.fixed[2], b.adaptive[1]) for c, b in bounds.items() if c[2] == speed],
            default=1.0,
        )
        for ax in np.atleast_1d(axes).ravel()[: len(phases)]:  # one scale for every phase
            ax.set_ylim(0.0, 1.05 * top)
        for ax in np.atleast_1d(axes).ravel()[len(phases) :]:
            ax.set_visible(False)
        handles, labels = np.atleast_1d(axes).ravel()[0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=8)
        fig.suptitle(
            f"{config.robot}: largest impulse survived [N s] per push direction (0: forward, "
            f"90: left), speed x{speed:g}",
            fontsize=10,
        )
        fig.tight_layout(rect=(0, 0.06, 1, 0.96))
        name = f"push_polar_speed{speed:g}.png"
        fig.savefig(out / name, dpi=90)
        plt.close(fig)
        names.append(name)
    return names


def ratio_heatmaps(out: Path, rows: list[dict], config: PushMapConfig) -> list[str]:
    """Ratio to paper-m per direction and phase, one heat map per controller and speed."""
    import matplotlib.pyplot as plt
    import numpy as np

    names = []
    directions = sorted({cell_of(r)[0] for r in rows})
    phases = sorted({cell_of(r)[1] for r in rows})
    for controller, pairs in ratios(rows).items():
        if controller == REFERENCE:
            continue
        for speed in config.speed_shares:
            grid = np.full((len(phases), len(directions)), np.nan)
            for (direction, phase, share), value in pairs:
                if share == speed and value is not None:
                    grid[phases.index(phase), directions.index(direction)] = value
            if not np.isfinite(grid).any():  # the reference walks nowhere: no ratio
                continue
            fig, ax = plt.subplots(figsize=(1.2 + 0.5 * len(directions), 1.0 + 0.4 * len(phases)))
            image = ax.imshow(np.log2(grid), cmap="RdBu", vmin=-2, vmax=2, aspect="auto")
            for (i, j), value in np.ndenumerate(grid):
                if np.isfinite(value):
                    ax.text(j, i, f"{value:.1f}", ha="center", va="center", fontsize=6)
            ax.set_xticks(range(len(directions)), [f"{d:g}" for d in directions], fontsize=7)
            ax.set_yticks(range(len(phases)), [f"{p:.2f}" for p in phases], fontsize=7)
            ax.set_xlabel("push direction [deg] (0: forward, 90: left)")
            ax.set_ylabel("phase [share of the step]")
            ax.set_title(f"{controller} / {REFERENCE}, speed x{speed:g}", fontsize=9)
            fig.colorbar(image, ax=ax, fraction=0.03, label="log2 ratio")
            fig.tight_layout()
            name = f"push_ratio_{controller}_speed{speed:g}.png"
            fig.savefig(out / name, dpi=100)
            plt.close(fig)
            names.append(name)
    return names


__all__ = ["polar_figures", "ratio_heatmaps"]
