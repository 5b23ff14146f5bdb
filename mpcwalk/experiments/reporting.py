"""What every experiment's report is made of: markdown tables, medians, Wilson intervals, the
record of the runs that filled a results table, and where the committed results lie.

- :func:`cell` and :func:`table`: markdown tables of rows (``-`` for None, yes/no, fixed
  decimals);
- :func:`median` (of the values that are there) and :func:`wilson` (the 95 % interval of a
  success rate);
- :func:`record_run`, :func:`read_runs` and :func:`runs_text`: each run of an experiment
  appends its command, date, wall time, workers and place to ``runs.json``; the report says
  them;
- :func:`find_results`: the committed ``results/NAME`` folder of the repository, from any
  working directory.
"""

import datetime
import json
import math
import os
import platform
import statistics
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import mpcwalk

#: File of the runs that filled an experiment's table (wall time, workers, where).
RUNS_FILE = "runs.json"


def cell(value: Any, digits: int = 2) -> str:
    """One table cell: ``-`` for None, yes/no for booleans, ``digits`` decimals for floats."""
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.{digits}f}"
    return str(value)


def table(
    rows: Sequence[Mapping[str, Any]],
    columns: Sequence[tuple[str, str, int]],
    *,
    marks: Mapping[str, str] | None = None,
    mark: str = " (fell)",
) -> str:
    """Markdown table of ``rows`` with ``columns`` (key, title, decimals).

    ``marks`` maps a column key to a row key: when that row value is true and the cell has a
    value, ``mark`` is appended to the cell (e.g. a measure taken on a walk that fell).
    """
    marks = marks or {}
    lines = [
        "| " + " | ".join(title for _, title, _ in columns) + " |",
        "|" + "---|" * len(columns),
    ]
    for row in rows:
        cells = []
        for key, _, digits in columns:
            text = cell(row.get(key), digits)
            if key in marks and row.get(marks[key]) and row.get(key) is not None:
                text += mark
            cells.append(text)
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def median(values: Iterable[float | None]) -> float | None:
    """The median of the values that are not None (None when there is none)."""
    kept = [v for v in values if v is not None]
    return statistics.median(kept) if kept else None


def wilson(successes: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """Wilson score interval of a success rate (95 % by default); (0, 1) when ``n`` is 0."""
    if n == 0:
        return 0.0, 1.0
    p = successes / n
    denominator = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / denominator
    half = z * math.sqrt(p * (1.0 - p) / n + z * z / (4 * n * n)) / denominator
    return max(0.0, centre - half), min(1.0, centre + half)


def record_run(out: Path, run, *, command: str, address: str | None = None) -> list[dict]:
    """Append this run of ``command`` (a :class:`~mpcwalk.sweep.SweepRun`: wall time, cases
    run, workers; where it ran) to ``out``'s ``runs.json``; returns every run recorded."""
    from mpcwalk.sweep.cluster import where

    path = Path(out) / RUNS_FILE
    runs = read_runs(out)
    runs.append(
        {
            "command": command,
            "date": datetime.datetime.now().isoformat(timespec="seconds"),
            "wall_time_s": round(run.wall_time_s, 1),
            "cases_run": run.nb_run,
            "cases_resumed": run.nb_resumed,
            "workers": run.workers,
            "where": where(address),
            "machine": f"{platform.machine()}, {os.cpu_count()} cores",
        }
    )
    path.write_text(json.dumps(runs, indent=1) + "\n")
    return runs


def read_runs(out: str | Path) -> list[dict]:
    """The runs recorded in ``out``'s ``runs.json`` (none when it has none)."""
    path = Path(out) / RUNS_FILE
    return json.loads(path.read_text()) if path.exists() else []


def runs_text(runs: list[dict], nb_cases: int, noun: str = "walks") -> str:
    """The runs that filled the table, in words (``noun``: what a case is)."""
    wall = sum(r["wall_time_s"] for r in runs)
    lines = [
        f"- `{r['command']}` ({r['date']}): {r['cases_run']} {noun} in "
        f"{r['wall_time_s'] / 60:.1f} min, {r['workers']} at once, {r['where']} "
        f"({r['machine']})"
        for r in runs
    ]
    return (
        f"{nb_cases} {noun}, {wall / 60:.1f} min of wall time in all:\n\n" + "\n".join(lines) + "\n"
    )


def find_results(name: str, *, start: str | Path | None = None) -> Path | None:
    """The folder ``results/<name>`` of the repository: looked for in the working directory
    (or ``start``) and its parents, then beside the package (a checkout installed in
    editable mode); None when there is none (an installed wheel has no results)."""
    here = Path.cwd() if start is None else Path(start)
    candidates = [here.resolve(), *here.resolve().parents]
    candidates.append(Path(mpcwalk.__file__).resolve().parents[1])
    for folder in candidates:
        path = folder / "results" / name
        if path.is_dir():
            return path
    return None


__all__ = [
    "RUNS_FILE",
    "cell",
    "find_results",
    "median",
    "read_runs",
    "record_run",
    "runs_text",
    "table",
    "wilson",
]
