"""The figure of the LIPM's push-recovery map: per phase, a polar plot of the largest impulse
recovered with 0, 1 and 2 steps (and 2 with the timing adapted)."""

from pathlib import Path

import numpy as np


def polar_figure(robot: str, cells, path: Path) -> None:
    """Write the polar plots of ``robot``'s cells (:class:`~mpcwalk.experiments.capture_map.
    cells.CaptureCell`) per phase to ``path`` (a PNG)."""
    import matplotlib.pyplot as plt

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


__all__ = ["polar_figure"]
