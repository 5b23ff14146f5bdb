"""The timed solves of the benchmark, on Ray timing actors, each under a hard time limit.

Each of ``nb_workers`` timing actors (:class:`~mpcwalk.sweep.timing.TimingWorker`: one CPU
slot of the Ray instance, single-threaded numerical libraries, output silenced) holds a
:class:`~mpcwalk.bench.solvers.solves.cases.CaseSolver` and solves one case at a time. A case
that runs past its hard limit (a back-end with no time limit of its own, or stuck) gets its
actor killed and replaced, and becomes a failed row; so does a case whose actor dies.
Following qpbenchmark's known timeouts, once two cases of a group (formulation, back-end,
level, start, horizon) have timed out, the rest of that group and of every longer horizon is
recorded as skipped timeouts without being run (cold timeouts also skip the warm cases,
whose first warm-up solve is a cold one).
"""

import time
from collections import deque
from collections.abc import Callable, Iterable

from mpcwalk.bench.solvers.solves.cases import CaseSolver, SolverCase, make_row
from mpcwalk.sweep.timing import TimedCallFailed, TimingWorker, wait_any

#: Timeouts in a group after which the rest of the group is skipped.
TIMEOUTS_BEFORE_SKIP = 2


class TimedSolves:
    """Solve :class:`SolverCase` objects on ``nb_workers`` timing actors.

    Args:
        nb_workers: Timing actors (1: no two timed solves overlap).
        setup_allowance: Seconds added to each case's hard limit for work that is not
            timed (QP construction, CasADi code generation), in [s].
        address: Ray cluster (None: ``RAY_ADDRESS``, else local).
    """

    def __init__(
        self, nb_workers: int = 1, *, setup_allowance: float = 5.0, address: str | None = None
    ) -> None:
        self.nb_workers = max(1, int(nb_workers))
        self.setup_allowance = setup_allowance
        self.address = address

    def hard_limit(self, case: SolverCase) -> float:
        """Wall time after which the actor of ``case`` is killed, in [s]."""
        return case.nb_solves * 2.0 * case.level.runtime + self.setup_allowance

    def run(
        self,
        cases: Iterable[SolverCase],
        *,
        progress: bool = True,
        desc: str = "solves",
        on_row: Callable[[dict], None] | None = None,
    ) -> list[dict]:
        """Rows of all ``cases``, in completion order.

        Args:
            cases: Cases; give those of a group one after the other, by increasing
                horizon, for the skip rule to save time.
            progress: Show a tqdm progress bar.
            desc: Label of the bar.
            on_row: Called with each row as it comes.
        """
        from tqdm import tqdm

        pending = deque(cases)
        rows: list[dict] = []
        timeouts: dict[tuple, int] = {}
        saturated: dict[tuple, int] = {}  # group without horizon -> smallest skipped horizon
        bar = tqdm(total=len(pending), desc=desc, disable=not progress, smoothing=0.05)

        def record(row: dict, case: SolverCase) -> None:
            if row["timeout"]:
                timeouts[case.group] = timeouts.get(case.group, 0) + 1
                if timeouts[case.group] >= TIMEOUTS_BEFORE_SKIP:
                    # A warm case starts with a cold solve: cold timeouts saturate both.
                    starts = ("cold", "warm") if case.start == "cold" else ("warm",)
                    for start in starts:
                        key = case.group[:3] + (start,)
                        saturated[key] = min(
                            saturated.get(key, case.problem.horizon), case.problem.horizon
                        )
            rows.append(row)
            if on_row is not None:
                on_row(row)
            bar.update(1)

        workers = [TimingWorker(CaseSolver, address=self.address) for _ in range(self.nb_workers)]
        running: dict = {}  # reference -> (worker, case, deadline)
        try:
            while pending or running:
                busy = {id(worker) for worker, _, _ in running.values()}
                for worker in workers:
                    while id(worker) not in busy and pending:
                        case = pending.popleft()
                        limit = saturated.get(case.group[:-1])
                        if limit is not None and case.problem.horizon >= limit:
                            record(_skipped(case), case)
                            continue
                        deadline = time.monotonic() + self.hard_limit(case)
                        running[worker.submit("solve", case)] = (worker, case, deadline)
                        busy.add(id(worker))
                if not running:
                    continue
                first = min(deadline for _, _, deadline in running.values())
                ready = wait_any(list(running), first - time.monotonic())
                for ref in ready:
                    worker, case, _ = running.pop(ref)
                    try:
                        row = worker.result(ref)
                    except TimedCallFailed:
                        row = make_row(
                            case,
                            runtime=case.level.runtime,
                            found=False,
                            status="error: worker crashed",
                        )
                    record(row, case)
                for ref, (worker, case, deadline) in list(running.items()):
                    if ref not in ready and time.monotonic() > deadline:
                        del running[ref]
                        worker.restart()
                        record(
                            make_row(
                                case,
                                runtime=case.level.runtime,
                                found=False,
                                status="killed: over the hard time limit",
                                timeout=True,
                            ),
                            case,
                        )
        finally:
            for worker in workers:
                worker.close()
            bar.close()
        return rows


def _skipped(case: SolverCase) -> dict:
    return make_row(
        case,
        runtime=case.level.runtime,
        found=False,
        status="skipped: timeouts in this group",
        timeout=True,
    )


__all__ = ["TIMEOUTS_BEFORE_SKIP", "TimedSolves"]
