"""``results.csv.gz`` of the solver benchmark: writing, reading and statistics.

One row per solve, gzip-compressed (the full run has about 17,000 rows: 3.6 MB of text,
0.5 MB compressed); a plain ``.csv`` path is written and read uncompressed.

The statistics follow qpbenchmark where it has a convention: success rates
per tolerance level, and the shifted geometric mean of runtimes with a shift
of 10 s, a failed solve counting as the time limit, relative to the best
back-end. Since that mean cannot tell 50 us from 500 us (the shift is 10 s),
plain medians and 99th percentiles of the successful solves come beside it,
and the growth of the solve time with the horizon is fitted as a power law.
"""

import csv
import gzip
import math
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

from mpcwalk.bench.solvers.solves.cases import CSV_COLUMNS

_INTS = ("horizon", "tick", "n", "m")
_FLOATS = (
    "sampling_period",
    "time",
    "runtime",
    "primal_residual",
    "dual_residual",
    "duality_gap",
    "warmup_runtime",
)
_BOOLS = ("pushed", "found", "success", "timeout")
#: File name of the rows in a benchmark's output directory.
RESULTS_FILE = "results.csv.gz"
#: Shift of qpbenchmark's shifted geometric mean of runtimes, in [s].
RUNTIME_SHIFT = 10.0


def write_results(rows: Iterable[dict], path: Path) -> None:
    """Write rows to a CSV file (gzip-compressed for a ``.gz`` path) with the
    :data:`CSV_COLUMNS` header."""
    with _open(path, "w") as stream:
        writer = csv.DictWriter(stream, fieldnames=CSV_COLUMNS, extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow({k: _cell(row.get(k)) for k in CSV_COLUMNS})


def _open(path: Path, mode: str):
    """Text stream of a CSV file, through gzip for a ``.gz`` path."""
    if str(path).endswith(".gz"):
        return gzip.open(path, mode + "t", newline="")
    return open(path, mode, newline="")


def _cell(value) -> str:
    """CSV text of a value: floats with 7 significant digits."""
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.7g}"
    return str(value)


def read_results(path: Path) -> list[dict]:
    """Rows of a results file (``.csv`` or ``.csv.gz``), numbers and booleans typed back."""
    rows = []
    with _open(path, "r") as stream:
        for raw in csv.DictReader(stream):
            row: dict = dict(raw)
            for key in _INTS:
                row[key] = int(raw[key]) if raw.get(key) not in (None, "") else None
            for key in _FLOATS:
                row[key] = float(raw[key]) if raw.get(key) not in (None, "") else math.nan
            for key in _BOOLS:
                row[key] = raw.get(key) == "True"
            it = raw.get("iterations")
            row["iterations"] = int(float(it)) if it not in (None, "", "None") else None
            rows.append(row)
    return rows


def select(rows: Iterable[dict], **criteria) -> list[dict]:
    """Rows whose fields equal the criteria (a tuple, list or set means "one of")."""
    out = []
    for row in rows:
        for key, value in criteria.items():
            if isinstance(value, (tuple, list, set, frozenset)):
                if row[key] not in value:
                    break
            elif row[key] != value:
                break
        else:
            out.append(row)
    return out


def in_set(rows: Iterable[dict], name: str) -> list[dict]:
    """Rows of the ``"main"`` or ``"sweep"`` problem set."""
    return [r for r in rows if name in r["set"].split("+")]


def shifted_geometric_mean(values: Sequence[float], shift: float) -> float:
    """``exp(mean(log(v + shift))) - shift`` of non-negative values."""
    v = np.asarray(values, dtype=float)
    if v.size == 0:
        return math.nan
    return float(np.exp(np.mean(np.log(v + shift))) - shift)


def solvers_of(rows: Iterable[dict]) -> list[str]:
    """Back-end names in order of first appearance."""
    return list(dict.fromkeys(r["solver"] for r in rows))


def success_rates(rows: list[dict], levels: Sequence[str]) -> dict[str, dict[str, float]]:
    """Success rate [%] per back-end and level."""
    out: dict[str, dict[str, float]] = {}
    for solver in solvers_of(rows):
        out[solver] = {}
        for level in levels:
            sel = select(rows, solver=solver, tolerance=level)
            out[solver][level] = 100.0 * np.mean([r["success"] for r in sel]) if sel else math.nan
    return out


def shgeom_runtimes(
    rows: list[dict], level: str, time_limit: float
) -> dict[str, tuple[float, float]]:
    """qpbenchmark's runtime mean per back-end at ``level``: ``(relative to
    the best, absolute [s])``; runtime of a solve not found: the time limit."""
    means = {}
    for solver in solvers_of(rows):
        sel = select(rows, solver=solver, tolerance=level)
        if sel:
            values = [r["runtime"] if r["found"] and not r["timeout"] else time_limit for r in sel]
            means[solver] = shifted_geometric_mean(values, RUNTIME_SHIFT)
    best = min(means.values()) if means else math.nan
    return {s: (m / best if best > 0 else math.nan, m) for s, m in means.items()}


def timing_stats(rows: list[dict]) -> tuple[float, float, int]:
    """Median and 99th percentile [s] of the successful solves, and their count."""
    times = [r["runtime"] for r in rows if r["success"]]
    if not times:
        return math.nan, math.nan, 0
    return float(np.median(times)), float(np.percentile(times, 99)), len(times)


def fit_exponent(horizons: Sequence[float], times: Sequence[float]) -> float:
    """Slope of ``log(time)`` against ``log(horizon)`` (least squares); nan
    with fewer than 3 points."""
    h, t = np.asarray(horizons, dtype=float), np.asarray(times, dtype=float)
    keep = np.isfinite(t) & (t > 0)
    if keep.sum() < 3:
        return math.nan
    return float(np.polyfit(np.log(h[keep]), np.log(t[keep]), 1)[0])


def horizon_growth(
    rows: list[dict], *, level: str, start: str = "cold", min_horizon: int = 0
) -> dict[tuple[str, str], dict]:
    """Median successful solve time per horizon and fitted exponent.

    Only horizons where at least half of the solves succeeded enter the fit.

    Returns:
        ``{(formulation, solver): {"horizons": [...], "medians": [...],
        "exponent": e, "exponent_tail": e over horizons >= min_horizon}}``.
    """
    out = {}
    sel = select(rows, tolerance=level, start=start)
    for formulation in dict.fromkeys(r["formulation"] for r in sel):
        for solver in solvers_of(select(sel, formulation=formulation)):
            mine = select(sel, formulation=formulation, solver=solver)
            horizons = sorted({r["horizon"] for r in mine})
            medians = []
            for h in horizons:
                at = select(mine, horizon=h)
                ok = [r["runtime"] for r in at if r["success"]]
                medians.append(float(np.median(ok)) if len(ok) * 2 >= len(at) and ok else math.nan)
            tail = [i for i, h in enumerate(horizons) if h >= min_horizon]
            out[(formulation, solver)] = {
                "horizons": horizons,
                "medians": medians,
                "exponent": fit_exponent(horizons, medians),
                "exponent_tail": fit_exponent(
                    [horizons[i] for i in tail], [medians[i] for i in tail]
                ),
            }
    return out


def format_time(seconds: float | None) -> str:
    """Seconds as a short string in us or ms."""
    if seconds is None or not math.isfinite(seconds):
        return "-"
    if seconds < 1e-3:
        return f"{seconds * 1e6:.0f} us"
    if seconds < 1.0:
        return f"{seconds * 1e3:.2f} ms" if seconds < 1e-2 else f"{seconds * 1e3:.1f} ms"
    return f"{seconds:.2f} s"
