"""Paper A's comparison as a table (with paper A's reported row and the ratios to paper A's
gait) and the figure of the per-step placement errors (paper A Fig. 8)."""

from collections.abc import Sequence

from mpcwalk.experiments import reporting

#: Paper A's reported numbers (turning walk, Fig. 8): the row to beat.
PAPER_A_ROW = {
    "controller": "paper A (Atlas, DRCsim, reported)",
    "experiment": "turning",
    "fell": False,
    "step_duration_s": 12.0,
    "total_time_s": None,
    "position_error_mean_cm": 2.05,
    "position_error_max_cm": 4.96,
    "yaw_error_mean_deg": 0.81,
    "yaw_error_max_deg": 5.21,
}

#: Label of the baseline every ratio of the table is taken against: paper A's gait as the
#: paper reports it (``--controller paper-a``: static, ankle strategy + IMU, re-aiming, 12 s).
PAPER_A_LABEL = "paper-a (static + ankle-imu, re-aiming), 12 s"

TABLE_COLUMNS = (
    ("controller", "controller", 0),
    ("experiment", "path", 0),
    ("fell", "fell", 0),
    ("step_duration_s", "T [s]", 1),
    ("steps", "steps", 0),
    ("total_time_s", "time [s]", 1),
    ("position_error_mean_cm", "pos. err. mean [cm]", 2),
    ("position_error_max_cm", "pos. err. max [cm]", 2),
    ("yaw_error_mean_deg", "yaw err. mean [deg]", 2),
    ("yaw_error_max_deg", "yaw err. max [deg]", 2),
    ("position_error_ratio", "pos. err. mean / paper-a", 2),
    ("cop_margin_min_cm", "min CoP margin [cm]", 1),
    ("com_margin_min_cm", "min CoM margin [cm]", 1),
    ("generator_tick_us", "generator tick [us]", 0),
    ("controller_tick_us", "controller tick [us]", 0),
)


def with_ratios(rows: Sequence[dict]) -> list[dict]:
    """The rows with ``position_error_ratio``: the mean position error over that of
    :data:`PAPER_A_LABEL` on the same path (None without it, or when it fell)."""
    base = {
        row["experiment"]: row["position_error_mean_cm"]
        for row in rows
        if row["controller"] == PAPER_A_LABEL and not row["fell"]
    }
    out = []
    for row in rows:
        reference, error = base.get(row["experiment"]), row.get("position_error_mean_cm")
        ratio = error / reference if reference and error is not None else None
        out.append({**row, "position_error_ratio": ratio})
    return out


def format_table(rows: Sequence[dict], *, with_paper: bool = True) -> str:
    """Markdown table of the rows, paper A's reported row first, with the ratios against
    paper A's gait (:func:`with_ratios`)."""
    return reporting.table(([PAPER_A_ROW] if with_paper else []) + with_ratios(rows), TABLE_COLUMNS)


def plot_placement_errors(
    entries: Sequence[tuple[str, Sequence[float], Sequence[float]]], *, title: str = ""
):
    """Per-step position [cm] and yaw [deg] errors of several walks (paper A Fig. 8):
    ``(label, positions, yaws)`` of each (:func:`~mpcwalk.experiments.paper_a.walks.
    placement_errors`)."""
    import matplotlib.pyplot as plt
    import numpy as np

    fig, (ax_p, ax_y) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    for label, positions, yaws in entries:
        steps = np.arange(1, len(positions) + 1)
        ax_p.plot(steps, positions, "o-", ms=3, label=label)
        ax_y.plot(steps, yaws, "o-", ms=3, label=label)
    ax_p.axhline(PAPER_A_ROW["position_error_max_cm"], color="k", ls=":", lw=1, label="paper A max")
    ax_y.axhline(PAPER_A_ROW["yaw_error_max_deg"], color="k", ls=":", lw=1, label="paper A max")
    ax_p.set_ylabel("position error [cm]")
    ax_y.set_ylabel("yaw error [deg]")
    ax_y.set_xlabel("step")
    ax_p.set_yscale("symlog", linthresh=0.1)
    ax_y.set_yscale("symlog", linthresh=0.1)
    ax_p.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False)
    ax_p.set_title(title)
    fig.tight_layout()
    return fig


__all__ = [
    "PAPER_A_LABEL",
    "PAPER_A_ROW",
    "TABLE_COLUMNS",
    "format_table",
    "plot_placement_errors",
    "with_ratios",
]
