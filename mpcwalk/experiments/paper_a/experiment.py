"""Paper A's comparison as an experiment of the registry (``paper_a``)."""

from pathlib import Path

from mpcwalk.experiments.paper_a.config import PaperAConfig, load_config
from mpcwalk.experiments.paper_a.run import PathWalk, paper_a_sweep, write_figures, write_table
from mpcwalk.experiments.protocol import Experiment, read_table
from mpcwalk.experiments.reporting import read_runs, runs_text
from mpcwalk.sweep import Sweep


class PaperA(Experiment):
    """Foot placement accuracy of every controller on paper A's straight and turning paths,
    and on the 3D ramp path."""

    name = "paper_a"
    summary = "paper A's foot placement table on the straight, turning and 3D ramp paths"
    package = "mpcwalk.experiments.paper_a"

    def config(self, *, quick: bool = False) -> PaperAConfig:
        return load_config(self.config_file, quick=quick)

    def cases(self, config: PaperAConfig) -> tuple[PathWalk, ...]:
        return paper_a_sweep(config).cases

    def sweep(self, config: PaperAConfig, out: str | Path | None = None) -> Sweep:
        return paper_a_sweep(config, out)

    def figures(self, out: str | Path) -> list[str]:
        return write_figures(out)

    def report(self, out: str | Path) -> Path:
        from mpcwalk.experiments.paper_a.table import format_table

        out = Path(out)
        settings, rows = read_table(out)
        table = write_table(out)
        failed = [f"- `{row['case_id']}`: {row['error']}" for row in rows if row.get("error")]
        figures = sorted(p.name for p in out.glob("*.png"))
        parts = [
            "# Paper A reproduced: foot placement accuracy\n",
            runs_text(read_runs(out), len(rows)),
            f"Robot `{settings['robot']}`, paths {', '.join(settings['paths'])} "
            "(`mpcwalk/experiments/paper_a/paths/`), steps kept: "
            f"{settings['nb_steps'] or 'all'} (T >= 3 s: {settings['slow_nb_steps'] or 'as the others'}). "
            "Every controller walks with paper A's state machine re-aiming each step from the "
            "estimated support foot. Errors: landed sole (ground truth) against the planned "
            "(file) pose, in the middle of the next single support (paper A's Fig. 8), in 3D "
            "on a path with a terrain file beside it (`ramp.toml` for `ramp`); "
            "margins: signed distance to the planned support polygon.\n",
            format_table(table),
        ]
        if failed:
            parts += ["Walks that could not run:\n", "\n".join(failed) + "\n"]
        parts += ["\n".join(f"![{name}]({name})" for name in figures) + "\n"]
        path = out / "report.md"
        path.write_text("\n".join(parts))
        return path


__all__ = ["PaperA"]
