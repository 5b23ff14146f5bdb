"""Markdown tables of the experiment reports (paper A, paper M)."""

from collections.abc import Mapping, Sequence
from typing import Any


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
