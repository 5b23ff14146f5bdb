"""The results table of a sweep: one CSV row per case, appended as the cases finish.

A sweep's output folder holds ``results.csv`` (the rows: the case's configuration, then what
its run measured, and its ``error``) and ``sweep.json`` (what the sweep is: its name, its
settings and the identifiers of its cases, with their fingerprint). Rows are appended and
flushed one by one, so a sweep killed halfway keeps every case that finished; run again on
the same folder with the same configuration, it runs only the missing cases. A sweep grown
along its axes (a list setting given more values, such as one more controller, and every
earlier case kept) takes over the folder of the smaller one with its rows and runs only the
new cases. A folder holding another configuration is refused unless it is overwritten.
When every case has its row, the table is rewritten in the order of the cases (an
uninterrupted run's order).

Cells: numbers as Python writes them (``repr``, so that they read back exactly), ``True``
and ``False``, lists as JSON, an empty cell for None; :func:`read_rows` reads them back.
"""

import csv
import hashlib
import io
import json
import math
import os
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import ConfigurationError

TABLE_FILE = "results.csv"
MANIFEST_FILE = "sweep.json"


def fingerprint(name: str, settings: dict[str, Any], case_ids: Sequence[str]) -> str:
    """Fingerprint of a sweep's configuration: its name, settings and cases."""
    text = json.dumps(
        {"name": name, "settings": settings, "cases": list(case_ids)},
        sort_keys=True,
        default=str,
    )
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _grown(before: Any, after: Any) -> bool:
    """``after`` is ``before``, or lists holding every value of it and more, or tables with
    the same keys, each grown."""
    if isinstance(before, dict) and isinstance(after, dict):
        return set(before) == set(after) and all(_grown(before[k], after[k]) for k in before)
    if isinstance(before, list) and isinstance(after, list) and before != after:
        return all(value in after for value in before)
    return bool(before == after)


def encode(value: Any) -> str:
    """One cell of the table."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "True" if value else "False"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else str(value)
    if isinstance(value, (int, str)):
        return str(value)
    if isinstance(value, (list, tuple, dict)):
        return json.dumps(value, default=float)
    if hasattr(value, "item"):  # numpy scalars
        return encode(value.item())
    return str(value)


def decode(text: str) -> Any:
    """The value of one cell (:func:`encode`'s inverse for the types it writes)."""
    if text == "":
        return None
    if text in ("True", "False"):
        return text == "True"
    if text[0] in "[{":
        try:
            return json.loads(text)
        except ValueError:
            return text
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def read_rows(path: str | Path) -> list[dict[str, Any]]:
    """The rows of a results table (a partial last line, from a killed sweep, is left out);
    the ``case_id`` stays text (an identifier of hexadecimal digits such as ``"723882e3..."``
    is no number)."""
    text = Path(path).read_text(encoding="utf-8")
    if text and not text.endswith("\n"):
        text = text[: text.rfind("\n") + 1]
    return [
        {k: v if k == "case_id" else decode(v) for k, v in row.items()}
        for row in csv.DictReader(io.StringIO(text))
    ]


class ResultsTable:
    """The table of one sweep in ``out_dir`` (see the module docstring).

    Args:
        out_dir: Output folder (created).
        name: The sweep's name.
        settings: What defines the sweep besides its cases (JSON-ready).
        case_ids: Identifiers of the cases, in order.
        columns: Columns of the table.
        overwrite: Start afresh even when the folder holds another configuration.

    Raises:
        ConfigurationError: The folder holds a sweep of another configuration, and
            ``overwrite`` is false.
    """

    def __init__(
        self,
        out_dir: str | Path,
        *,
        name: str,
        settings: dict[str, Any],
        case_ids: Sequence[str],
        columns: Sequence[str],
        overwrite: bool = False,
    ) -> None:
        self.dir = Path(out_dir)
        self.path = self.dir / TABLE_FILE
        self.manifest_path = self.dir / MANIFEST_FILE
        self.columns = list(columns)
        self.case_ids = list(case_ids)
        self.fingerprint = fingerprint(name, settings, case_ids)
        manifest = {
            "name": name,
            "fingerprint": self.fingerprint,
            "nb_cases": len(case_ids),
            "settings": settings,
            "cases": list(case_ids),
        }
        self.dir.mkdir(parents=True, exist_ok=True)
        old = self._old_fingerprint()
        if old not in (None, self.fingerprint) and not overwrite and self._grows(manifest):
            self.manifest_path.write_text(json.dumps(manifest, indent=1, default=str) + "\n")
            old = self.fingerprint
        if old is not None and old != self.fingerprint and not overwrite:
            raise ConfigurationError(
                f"{self.dir} holds a sweep of another configuration (fingerprint {old}, this "
                f"one {self.fingerprint}); give another output folder, or overwrite it "
                "(--overwrite)."
            )
        if old != self.fingerprint or overwrite or not self.path.exists():
            self.path.unlink(missing_ok=True)
            self.manifest_path.write_text(json.dumps(manifest, indent=1, default=str) + "\n")
            self._write(self.path, [])
        self._repair()

    def _old_fingerprint(self) -> str | None:
        if not self.manifest_path.exists():
            return None if not self.path.exists() else "(unknown)"
        try:
            return str(json.loads(self.manifest_path.read_text())["fingerprint"])
        except (ValueError, KeyError):
            return "(unreadable)"

    def _grows(self, manifest: dict[str, Any]) -> bool:
        """Whether this sweep is the folder's grown along its axes: the same name and
        settings but for lists holding every earlier value and more (in tables too), and
        every earlier case."""
        try:
            old = json.loads(self.manifest_path.read_text())
            old_settings, old_cases = old["settings"], list(old["cases"])
        except (ValueError, KeyError, TypeError):
            return False
        settings = json.loads(json.dumps(manifest["settings"], default=str))
        return (
            old.get("name") == manifest["name"]
            and _grown(old_settings, settings)
            and set(old_cases) <= set(manifest["cases"])
        )

    def _repair(self) -> None:
        """Cut a partial last line (a sweep killed while writing it); rewrite a table
        written with other columns (an older version's) under this one's columns, a column
        it lacked left empty."""
        text = self.path.read_text(encoding="utf-8")
        if text and not text.endswith("\n"):
            self.path.write_text(text[: text.rfind("\n") + 1], encoding="utf-8")
        header = next(csv.reader(io.StringIO(text)), None)
        if header is not None and header != self.columns:
            self._replace(self.rows())

    def _write(self, path: Path, rows: Iterable[dict[str, Any]]) -> None:
        with open(path, "w", newline="", encoding="utf-8") as stream:
            writer = csv.writer(stream)
            writer.writerow(self.columns)
            for row in rows:
                writer.writerow([encode(row.get(c)) for c in self.columns])

    def rows(self) -> list[dict[str, Any]]:
        """The rows written so far."""
        return read_rows(self.path)

    def done(self) -> set[str]:
        """Identifiers of the cases that have their row."""
        return {str(row["case_id"]) for row in self.rows()}

    def append(self, row: dict[str, Any]) -> None:
        """Append one row and flush it to the disk."""
        buffer = io.StringIO()
        csv.writer(buffer).writerow([encode(row.get(c)) for c in self.columns])
        with open(self.path, "a", newline="", encoding="utf-8") as stream:
            stream.write(buffer.getvalue())
            stream.flush()
            os.fsync(stream.fileno())

    def finish(self) -> list[dict[str, Any]]:
        """Once every case has its row: the rows in the order of the cases, the table
        rewritten in that order (atomically). Returns the rows."""
        order = {case_id: i for i, case_id in enumerate(self.case_ids)}
        rows: dict[str, dict[str, Any]] = {}
        for row in self.rows():
            rows.setdefault(str(row["case_id"]), row)
        ordered = sorted(rows.values(), key=lambda row: order.get(str(row["case_id"]), -1))
        if len(ordered) == len(self.case_ids):
            self._replace(ordered)
        return ordered

    def _replace(self, rows: Iterable[dict[str, Any]]) -> None:
        """Rewrite the table with ``rows`` (atomically)."""
        temporary = self.path.with_suffix(".csv.tmp")
        self._write(temporary, rows)
        os.replace(temporary, self.path)


__all__ = ["MANIFEST_FILE", "TABLE_FILE", "ResultsTable", "decode", "encode", "read_rows"]
