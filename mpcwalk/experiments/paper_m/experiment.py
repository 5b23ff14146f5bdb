"""Paper M's comparison as an experiment of the registry (``paper_m``)."""

import json
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.paper_m.config import PaperMConfig, load_config
from mpcwalk.experiments.protocol import Experiment, ExperimentRun
from mpcwalk.sweep import Sweep


class PaperM(Experiment):
    """Turning, disturbances, push sweep and speed of every controller (paper M)."""

    name = "paper_m"
    summary = "paper M's turning walk, disturbances, push sweep and speed, every controller"
    package = "mpcwalk.experiments.paper_m"

    def config(self, *, quick: bool = False) -> PaperMConfig:
        return load_config(self.config_file, quick=quick)

    def _controllers(self, config: PaperMConfig) -> dict[str, Any]:
        from mpcwalk.experiments.paper_m.walks import CONTROLLERS, controller_availability

        availability = controller_availability(CONTROLLERS)
        names = config.controllers or tuple(CONTROLLERS)
        return {n: CONTROLLERS[n] for n in names if availability.get(n) is None}

    def check(self, config: PaperMConfig) -> None:
        from mpcwalk.experiments.paper_m.walks import CONTROLLERS

        unknown = sorted(set(config.controllers or ()) - set(CONTROLLERS))
        if unknown:
            raise ConfigurationError(
                f"Paper M compares the controllers {sorted(CONTROLLERS)}, got {unknown}; "
                "name some of those in its configuration."
            )

    def cases(self, config: PaperMConfig) -> tuple[Any, ...]:
        from mpcwalk.experiments.paper_m.cases import paper_m_cases

        return paper_m_cases(config, self._controllers(config))

    def sweep(self, config: PaperMConfig, out: str | Path | None = None) -> Sweep:
        from mpcwalk.experiments.paper_m.cases import paper_m_sweep

        return paper_m_sweep(config, self._controllers(config))

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
        """The push cells and speed searches on the sweep engine (resumable), then the
        turning and disturbance walks, the figures and ``report.md``
        (:func:`~mpcwalk.experiments.paper_m.run.run_paper_m`)."""
        from mpcwalk.experiments.paper_m.run import run_paper_m
        from mpcwalk.sweep import SweepRun, read_rows

        config = self.config(quick=quick)
        self.check(config)
        out = Path(out)
        results = run_paper_m(
            out,
            config,
            workers=workers,
            address=address,
            progress=progress,
            overwrite=overwrite,
            command=command or self.command(out, quick=quick),
        )
        runs = json.loads((out / "runs.json").read_text())[-1]
        rows = read_rows(out / "results.csv")
        nb_cases = len(json.loads((out / "sweep.json").read_text())["cases"])
        sweep = SweepRun(
            tuple(rows),
            nb_cases,
            runs["cases_run"],
            runs["cases_resumed"],
            runs["wall_time_s"],
            runs["workers"],
            results is not None,
        )
        if results is None:
            return ExperimentRun(sweep, None)
        return ExperimentRun(sweep, out / "report.md", tuple(results.get("figures", ())))

    def report(self, out: str | Path) -> Path:
        from mpcwalk.experiments.paper_m.table import format_report

        path = Path(out) / "report.md"
        path.write_text(format_report(self._results(out)))
        return path

    def figures(self, out: str | Path) -> list[str]:
        """The figures the run drew (the walks' logs are not kept): their file names."""
        return list(self._results(out).get("figures", []))

    def _results(self, out: str | Path) -> dict[str, Any]:
        path = Path(out) / "results.json"
        if not path.exists():
            raise ConfigurationError(
                f"Expected paper M's results.json in {out}, found none; run `mpcwalk "
                "experiment run paper_m --out` into it first."
            )
        return json.loads(path.read_text())


__all__ = ["PaperM"]
