"""The sweep engine's throughput and its scaling: an experiment's cases run with 1, then 2
workers, on a local Ray instance and on a Ray cluster of one node per worker on this machine.

``mpcwalk experiment scaling NAME [--quick] [--workers 1 2] [--repeats N] --out DIR`` runs
:func:`measure_throughput` and writes ``scaling.md`` and ``scaling.json`` (:func:`write_scaling`).
Each sweep starts from a fresh Ray: a local instance with ``workers`` CPU slots, or a
:func:`~mpcwalk.sweep.local_cluster` of ``workers`` nodes of one CPU slot each, joined by its
address as a remote cluster would be. Ray's start (and the cluster's nodes) is timed apart;
the sweep's wall time holds the rest: the workers' start, their first imports and robot
loads, the cases, the rows coming back. The throughput is the cases a minute of the sweep's
wall time, and per core (divided by the workers).
"""

import contextlib
import datetime
import json
import os
import platform
import statistics
import tempfile
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.reporting import table
from mpcwalk.sweep import Sweep, ensure_ray, local_cluster, run_sweep, shutdown
from mpcwalk.sweep.cluster import ADDRESS_VARIABLE, check_workers

#: Where a sweep of the measurement runs.
PLACES = ("local", "cluster")

_PLACE_WORDS = {
    "local": "local Ray instance",
    "cluster": "local cluster (one node per worker)",
}


@dataclass(frozen=True)
class ThroughputRun:
    """One sweep of the measurement.

    Attributes:
        place: ``"local"`` (a local Ray instance) or ``"cluster"`` (a cluster of ``workers``
            nodes on this machine, one CPU slot each).
        workers: Cases run at once (the CPU slots).
        repeat: Index of the repetition.
        cases: Cases run.
        errors: Rows with an error.
        nodes: Ray nodes that ran cases.
        start_s: Ray's start: the instance, or the cluster's nodes and the connection [s].
        sweep_s: Wall time of the sweep once Ray is up [s].
        busy_s: Sum of the cases' wall times in the workers [s].
        cpu_s: Sum of the cases' processor times in the workers [s].
    """

    place: str
    workers: int
    repeat: int
    cases: int
    errors: int
    nodes: int
    start_s: float
    sweep_s: float
    busy_s: float
    cpu_s: float

    @property
    def per_minute(self) -> float:
        """Cases a minute of the sweep's wall time."""
        return 60.0 * self.cases / self.sweep_s

    @property
    def per_minute_per_core(self) -> float:
        """Cases a minute and a core (a worker)."""
        return self.per_minute / self.workers

    @property
    def per_cpu_minute(self) -> float:
        """Cases a minute of the workers' processor time in them: the throughput of a core
        of one's own, whatever else ran on the machine."""
        return 60.0 * self.cases / self.cpu_s

    @property
    def cpu_share(self) -> float:
        """Share of the cases' wall time their worker spent on a processor (below 1: the
        core was shared, with another worker or other work)."""
        return self.cpu_s / self.busy_s

    @property
    def busy_share(self) -> float:
        """Share of the workers' time spent in cases (the rest: start, imports, waits)."""
        return self.busy_s / (self.sweep_s * self.workers)


def measure_throughput(
    sweep: Sweep,
    *,
    workers: Sequence[int] = (1, 2),
    places: Sequence[str] = PLACES,
    repeats: int = 1,
    progress: bool = False,
) -> list[ThroughputRun]:
    """Run ``sweep`` at every place and number of workers, ``repeats`` times (interleaved:
    a slow spell of the machine spreads over them); each sweep into a fresh temporary folder,
    on a fresh Ray.

    Raises:
        ConfigurationError: A bad number of workers or repeats, an unknown place, or
            ``RAY_ADDRESS`` set (the local runs would go to that cluster).
    """
    for count in (*workers, repeats):
        check_workers(count)
    unknown = sorted(set(places) - set(PLACES))
    if unknown or not places or not workers:
        raise ConfigurationError(
            f"Expected places among {list(PLACES)} and at least one number of workers, got "
            f"places {list(places)} and workers {list(workers)}; fix the arguments."
        )
    if os.environ.get(ADDRESS_VARIABLE):
        raise ConfigurationError(
            f"{ADDRESS_VARIABLE} is set ({os.environ[ADDRESS_VARIABLE]}): the local runs of the "
            f"measurement would go to that cluster; unset it (env -u {ADDRESS_VARIABLE} ...)."
        )
    runs = []
    for repeat in range(repeats):
        for place in places:
            for count in workers:
                runs.append(_measure(sweep, place, count, repeat, progress))
    return runs


def _measure(sweep: Sweep, place: str, workers: int, repeat: int, progress: bool):
    shutdown()
    with tempfile.TemporaryDirectory() as folder, contextlib.ExitStack() as stack:
        start = time.perf_counter()
        address = None
        if place == "cluster":
            address = stack.enter_context(local_cluster(nodes=workers, cpus_per_node=1))
        ensure_ray(address=address, workers=workers)
        started = time.perf_counter() - start
        run = run_sweep(sweep, folder, workers=workers, address=address, progress=progress)
        shutdown()
    return ThroughputRun(
        place=place,
        workers=workers,
        repeat=repeat,
        cases=run.nb_run,
        errors=run.nb_errors,
        nodes=len({row.get("node") for row in run.rows} - {None}),
        start_s=started,
        sweep_s=run.wall_time_s,
        busy_s=sum(float(row.get("wall_time_s") or 0.0) for row in run.rows),
        cpu_s=sum(float(row.get("cpu_time_s") or 0.0) for row in run.rows),
    )


def summary_rows(runs: Sequence[ThroughputRun]) -> list[dict[str, Any]]:
    """One row per place and number of workers: the medians over the repetitions, the
    speed-up over the fewest workers at the same place, and the ratio of the local
    instance's sweep time to this one's at the same number of workers."""
    groups: dict[tuple[str, int], list[ThroughputRun]] = {}
    for run in runs:
        groups.setdefault((run.place, run.workers), []).append(run)
    rows: list[dict[str, Any]] = []
    for (place, workers), group in groups.items():

        def med(name: str, group=group) -> float:
            return statistics.median(getattr(run, name) for run in group)

        rows.append(
            {
                "place": place,
                "workers": workers,
                "repeats": len(group),
                "cases": group[0].cases,
                "errors": max(run.errors for run in group),
                "nodes": max(run.nodes for run in group),
                "start_s": med("start_s"),
                "sweep_s": med("sweep_s"),
                "per_minute": med("per_minute"),
                "per_minute_per_core": med("per_minute_per_core"),
                "busy_share": med("busy_share"),
                "per_cpu_minute": med("per_cpu_minute"),
                "cpu_share": med("cpu_share"),
            }
        )
    for row in rows:
        same_place = [r for r in rows if r["place"] == row["place"]]
        base = min(same_place, key=lambda r: r["workers"])
        row["speed_up"] = base["sweep_s"] / row["sweep_s"]
        local = [r for r in rows if r["place"] == "local" and r["workers"] == row["workers"]]
        row["local_over_this"] = local[0]["sweep_s"] / row["sweep_s"] if local else None
    return rows


_COLUMNS = (
    ("place_words", "where", 0),
    ("workers", "workers", 0),
    ("nodes", "nodes used", 0),
    ("start_s", "Ray's start [s]", 1),
    ("sweep_s", "sweep [s]", 1),
    ("per_minute", "walks/min", 1),
    ("per_minute_per_core", "walks/min/core", 1),
    ("speed_up", "speed-up", 2),
    ("busy_share", "busy share", 2),
    ("per_cpu_minute", "walks/CPU-min", 1),
    ("cpu_share", "CPU share", 2),
    ("local_over_this", "local/this (sweep time)", 2),
)


def scaling_text(runs: Sequence[ThroughputRun], *, command: str, what: str) -> str:
    """The report of a measurement (markdown): what ran, where, the table of medians."""
    rows = [{**row, "place_words": _PLACE_WORDS[row["place"]]} for row in summary_rows(runs)]
    repeats = max(row["repeats"] for row in rows)
    errors = sum(row["errors"] for row in rows)
    return (
        f"Throughput of the sweep engine on {what}, run by `{command}` "
        f"(median of {repeats} run{'s' if repeats > 1 else ''} each, interleaved). Each sweep "
        "starts on a fresh Ray: a local instance with one CPU slot per worker, or a cluster "
        "of one node per worker (one CPU slot each) started on this machine "
        "(`mpcwalk.sweep.local_cluster`, Ray's `cluster_utils`) and joined by its address, "
        "as a remote cluster is. Ray's start is timed apart; the sweep's time holds the "
        "workers' start, their imports and robot loads, the walks and the rows coming back. "
        "Walks/min/core: walks a minute of the sweep's time, divided by the workers; "
        "speed-up: over 1 worker at the same place; busy share: the walks' own time over "
        "the workers' time; walks/CPU-min: walks a minute of the processor time the "
        "workers spent in them (what a core of one's own would give); CPU share: that "
        "processor time over the walks' wall time (below 1: the core was shared); "
        "local/this: the local instance's sweep time over this one's."
        f"{' Rows with an error: ' + str(errors) + '.' if errors else ''}\n\n"
        + table(rows, _COLUMNS)
    )


def machine_words(before: Sequence[float], after: Sequence[float]) -> str:
    """The machine and its load averages (1, 5, 15 min) before and after the runs."""

    def load(values: Sequence[float]) -> str:
        return " / ".join(f"{v:.2f}" for v in values)

    return (
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
        f"load average (1 / 5 / 15 min) {load(before)} before the runs, {load(after)} after "
        "(a load above the cores' count means other work shared the machine)"
    )


def write_scaling(
    out: str | Path,
    runs: Sequence[ThroughputRun],
    *,
    command: str,
    what: str,
    machine: str,
) -> Path:
    """Write ``scaling.md`` and ``scaling.json`` (every run and the medians) into ``out``;
    returns the path of ``scaling.md``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    date = datetime.datetime.now().isoformat(timespec="seconds")
    text = scaling_text(runs, command=command, what=what) + f"\nMachine: {machine}; {date}.\n"
    record = {
        "command": command,
        "date": date,
        "machine": machine,
        "cases": what,
        "summary": summary_rows(runs),
        "runs": [
            {
                **asdict(run),
                "per_minute": run.per_minute,
                "per_minute_per_core": run.per_minute_per_core,
                "busy_share": run.busy_share,
                "per_cpu_minute": run.per_cpu_minute,
                "cpu_share": run.cpu_share,
            }
            for run in runs
        ],
    }
    (out / "scaling.json").write_text(json.dumps(record, indent=1) + "\n")
    path = out / "scaling.md"
    path.write_text(text)
    return path


__all__ = [
    "PLACES",
    "ThroughputRun",
    "machine_words",
    "measure_throughput",
    "scaling_text",
    "summary_rows",
    "write_scaling",
]
