"""What an experiment is: :class:`Experiment`, one small protocol every experiment answers.

An experiment has a ``name`` (the one ``mpcwalk experiment run NAME`` takes, and its folder
``results/NAME``), a one-line ``summary``, and:

- its configuration, :meth:`Experiment.config`: a frozen dataclass read from the
  ``config.toml`` shipped beside its code (:func:`read_config`), whose ``[quick]`` table
  gives the small variant the test suite runs (``quick=True``);
- its cases, :meth:`Experiment.cases`, and the :class:`~mpcwalk.sweep.Sweep` that runs them
  (:meth:`Experiment.sweep`): each case a Ray task of the sweep engine, its row streamed
  into ``results.csv`` as it finishes, so that a run stopped half-way runs only its missing
  cases when the same command is given again;
- :meth:`Experiment.run`: the sweep into a folder, then :meth:`Experiment.figures` and
  :meth:`Experiment.report` once every case has its row;
- :meth:`Experiment.report`: ``report.md`` from the table in the folder, with the command
  that made it (``runs.json``, :func:`~mpcwalk.experiments.reporting.record_run`);
- :meth:`Experiment.figures`: the figures of the table, their file names.

The registry of the experiments is :data:`mpcwalk.experiments.catalog.EXPERIMENTS`.
"""

import json
import sys
from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.package_data import package_data_dir
from mpcwalk.sweep import Sweep, SweepRun, read_rows, run_sweep

#: The file of an experiment's configuration, beside its code.
CONFIG_FILE = "config.toml"


def config_path(package: str) -> Path:
    """The ``config.toml`` of the experiment package ``package`` (e.g.
    ``"mpcwalk.experiments.paper_m"``), wherever pip installed it."""
    return package_data_dir(package) / CONFIG_FILE


def read_toml(path: str | Path) -> dict[str, Any]:
    """The TOML file at ``path`` as a dictionary.

    Raises:
        ConfigurationError: No such file, or not TOML.
    """
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # the tomli package is tomllib before Python 3.11
        import tomli as tomllib

    try:
        with open(path, "rb") as stream:
            return tomllib.load(stream)
    except OSError as error:
        raise ConfigurationError(
            f"Expected an experiment's TOML configuration at {path}, found none ({error}); "
            "give the path of an existing file."
        ) from None
    except tomllib.TOMLDecodeError as error:
        raise ConfigurationError(
            f"Expected TOML in {path}: {error}; fix the line it names."
        ) from None


def read_config(path: str | Path, *, quick: bool) -> tuple[dict[str, Any], dict[str, Any]]:
    """An experiment's TOML table (without its ``[quick]`` table) and, when ``quick``, its
    ``[quick]`` table (empty otherwise): the experiment applies the second over the first."""
    data = read_toml(path)
    quick_table = data.pop("quick", {})
    return data, (quick_table if quick else {})


def mode_name(quick: bool) -> str:
    """``"quick"`` or ``"full"``."""
    return "quick" if quick else "full"


@dataclass(frozen=True)
class ExperimentRun:
    """What :meth:`Experiment.run` did.

    Attributes:
        sweep: The run of its sweep (cases run, resumed, wall time, rows).
        report: The ``report.md`` written, None while cases are missing.
        figures: The figures written (file names in the folder).
    """

    sweep: SweepRun
    report: Path | None
    figures: tuple[str, ...] = ()

    @property
    def complete(self) -> bool:
        """Every case has its row."""
        return self.sweep.complete


class Experiment(ABC):
    """One experiment (see the module docstring); subclasses set ``name``, ``summary`` and
    ``package`` and implement :meth:`config`, :meth:`cases`, :meth:`sweep` and
    :meth:`report`."""

    #: Its name: ``mpcwalk experiment run NAME``, ``results/NAME``.
    name: str = ""
    #: One line for ``mpcwalk experiment list``.
    summary: str = ""
    #: Its package, where its ``config.toml`` lies.
    package: str = ""

    @property
    def config_file(self) -> Path:
        """The shipped ``config.toml``."""
        return config_path(self.package)

    @abstractmethod
    def config(self, *, quick: bool = False) -> Any:
        """The configuration (a frozen dataclass) of the shipped file; ``quick``: its small
        variant."""

    @abstractmethod
    def cases(self, config: Any) -> tuple[Any, ...]:
        """The cases of ``config`` (each with ``case_id`` and ``to_columns()``)."""

    @abstractmethod
    def sweep(self, config: Any, out: str | Path | None = None) -> Sweep:
        """The cases of ``config`` as a sweep of the engine (``out``: the results folder,
        for cases that draw a figure of their walk there)."""

    @abstractmethod
    def report(self, out: str | Path) -> Path:
        """Write ``report.md`` into ``out`` from the table there; returns its path."""

    def figures(self, out: str | Path) -> list[str]:
        """Write the figures of the table in ``out``; their file names (none by default)."""
        return []

    def check(self, config: Any) -> None:
        """Refuse a configuration before anything runs (nothing to check by default).

        Raises:
            MpcwalkError: A named error saying what is wrong and the fix.
        """

    def run(
        self,
        out: str | Path,
        *,
        quick: bool = False,
        workers: int | None = None,
        address: str | None = None,
        progress: bool = True,
        overwrite: bool = False,
        command: str | None = None,
    ) -> ExperimentRun:
        """Run the cases that have no row yet in ``out``'s table; once all have one, write
        the figures and ``report.md``.

        Args:
            out: The results folder (created).
            quick: The small variant of the configuration.
            workers: Cases at once (local: Ray's CPU slots; None: one per core).
            address: Ray cluster (None: ``RAY_ADDRESS``, else a local Ray instance).
            progress: Show a progress bar.
            overwrite: Start afresh in a folder holding another configuration.
            command: The command line recorded in ``runs.json`` and the report (default:
                the ``mpcwalk experiment run`` command of these arguments).
        """
        from mpcwalk.experiments.reporting import record_run

        config = self.config(quick=quick)
        self.check(config)
        out = Path(out)
        run = run_sweep(
            self.sweep(config, out),
            out,
            workers=workers,
            address=address,
            overwrite=overwrite,
            progress=progress,
        )
        record_run(out, run, command=command or self.command(out, quick=quick), address=address)
        if not run.complete:
            return ExperimentRun(run, None)
        figures = tuple(self.figures(out))
        return ExperimentRun(run, self.report(out), figures)

    def command(self, out: str | Path, *, quick: bool = False, workers: int | None = None) -> str:
        """The command that runs this experiment into ``out``."""
        words = ["mpcwalk", "experiment", "run", self.name]
        words += ["--quick"] if quick else []
        words += ["--workers", str(workers)] if workers else []
        return " ".join([*words, "--out", str(out)])


def read_table(out: str | Path) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """The settings (``sweep.json``) and the rows (``results.csv``) of an experiment's
    folder.

    Raises:
        ConfigurationError: The folder holds no finished table.
    """
    out = Path(out)
    manifest, rows = out / "sweep.json", out / "results.csv"
    if not (manifest.exists() and rows.exists()):
        raise ConfigurationError(
            f"Expected an experiment's table in {out} (sweep.json and results.csv), found "
            "none; run `mpcwalk experiment run NAME --out` into it first."
        )
    return json.loads(manifest.read_text()).get("settings", {}), read_rows(rows)


def settings_of(config: Any) -> dict[str, Any]:
    """A configuration's fields as JSON (the sweep's fingerprint)."""
    from dataclasses import asdict

    return json.loads(json.dumps(asdict(config), default=str))


def unknown_keys(values: Mapping[str, Any], known, where: str) -> None:
    """Refuse keys of a TOML table that are not fields.

    Raises:
        ConfigurationError: Names the unknown keys and the known ones.
    """
    unknown = sorted(set(values) - set(known))
    if unknown:
        raise ConfigurationError(
            f"Unknown key(s) {unknown} in [{where}]; the keys are {sorted(known)}."
        )


__all__ = [
    "CONFIG_FILE",
    "Experiment",
    "ExperimentRun",
    "config_path",
    "mode_name",
    "read_config",
    "read_table",
    "read_toml",
    "settings_of",
    "unknown_keys",
]
