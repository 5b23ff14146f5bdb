"""Faults, inputs and outputs as an experiment of the registry (``faults``): the repository's
fault tests run file by file, their cases counted per kind."""

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mpcwalk.experiments.faults.tally import KINDS, find_repository, run_test_file, tally
from mpcwalk.experiments.protocol import (
    Experiment,
    mode_name,
    read_config,
    read_table,
    settings_of,
    unknown_keys,
)
from mpcwalk.experiments.reporting import read_runs, runs_text
from mpcwalk.sweep import Sweep


@dataclass(frozen=True)
class FaultsConfig:
    """The test files run (relative to the repository) and a pytest ``-k`` expression."""

    files: tuple[str, ...]
    select: str = ""
    mode: str = "full"


@dataclass(frozen=True)
class FileCase:
    """One test file of the repository at ``root``."""

    root: str
    file: str
    select: str = ""

    @property
    def case_id(self) -> str:
        """The file and the selection."""
        return f"{self.file}::{self.select}" if self.select else self.file

    def to_columns(self) -> dict[str, Any]:
        """Columns of the results table."""
        return {"case_id": self.case_id, "file": self.file, "select": self.select}


def run_test_file_case(case: FileCase) -> dict[str, Any]:
    """Run one test file (in a worker): ``(name, passed)`` of each of its cases."""
    return {"cases": run_test_file(Path(case.root), case.file, case.select)}


class Faults(Experiment):
    """Bad inputs refused, faults survived or stopped cleanly, interrupts, atomic outputs."""

    name = "faults"
    summary = "bad inputs refused, faults survived or stopped cleanly, interrupts, outputs"
    package = "mpcwalk.experiments.faults"

    def config(self, *, quick: bool = False) -> FaultsConfig:
        data, small = read_config(self.config_file, quick=quick)
        unknown_keys(data, ("files", "select"), "faults")
        unknown_keys(small, ("files", "select"), "quick")
        values = {**data, **small}
        return FaultsConfig(tuple(values["files"]), str(values.get("select", "")), mode_name(quick))

    def check(self, config: FaultsConfig) -> None:
        find_repository()

    def cases(self, config: FaultsConfig) -> tuple[FileCase, ...]:
        root = str(find_repository())
        return tuple(FileCase(root, file, config.select) for file in config.files)

    def sweep(self, config: FaultsConfig, out: str | Path | None = None) -> Sweep:
        return Sweep(
            name="faults",
            cases=self.cases(config),
            runner=run_test_file_case,
            columns=("cases",),
            settings=settings_of(config),
        )

    def report(self, out: str | Path) -> Path:
        out = Path(out)
        settings, rows = read_table(out)
        tried, passed = tally((name, ok) for row in rows for name, ok in (row.get("cases") or []))
        meaning: dict[str, list[str]] = {}
        for kind, what in KINDS.values():
            meaning.setdefault(kind, []).append(what)
        lines = [
            "# Faults, inputs and outputs",
            "",
            runs_text(read_runs(out), len(rows), "test files"),
            "The cases of "
            + ", ".join(f"`{row['file']}`" for row in rows)
            + (f" selected by `-k '{settings['select']}'`" if settings.get("select") else "")
            + ", each asserting the named error, the exit code and the files left in `--out`.",
            "",
            "| kind | tried | passed | a pass means |",
            "|---|---:|---:|---|",
        ]
        for kind in dict.fromkeys(kind for kind, _ in KINDS.values()):
            if tried[kind]:
                what = "; ".join(dict.fromkeys(meaning[kind]))
                lines.append(f"| {kind} | {tried[kind]} | {passed[kind]} | {what} |")
        lines += [
            "",
            "Exit codes of `mpcwalk`: 0 walked (or success), 1 the robot fell, 2 bad input "
            "(before anything ran), 3 the controller stopped the walk (faults beyond its "
            "bound), 4 internal error (one line; the traceback in `--out/traceback.txt`, "
            "`--debug` prints it), 130 interrupted (the partial walk's log and `metrics.json` "
            "with `interrupted: true`).",
            "",
        ]
        path = out / "report.md"
        path.write_text("\n".join(lines))
        return path


__all__ = ["Faults", "FaultsConfig", "FileCase", "run_test_file_case"]
