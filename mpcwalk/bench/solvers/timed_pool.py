"""Worker processes that run benchmark cases under a hard time limit.

Each worker is a separate process (``spawn``) with single-threaded numerical
libraries and its output silenced (solver banners); it solves one case at a
time. A case that runs past its hard limit (a back-end with no time limit of
its own, or stuck) gets its worker killed and replaced, and becomes a failed
row; so does a case whose worker crashes. Following qpbenchmark's known
timeouts, once two cases of a group (formulation, back-end, level, start,
horizon) have timed out, the rest of that group and of every longer horizon
is recorded as skipped timeouts without being run (cold timeouts also skip the
warm cases, whose first warm-up solve is a cold one).
"""

import contextlib
import multiprocessing
import os
import time
import warnings
from collections import deque
from collections.abc import Callable, Iterable
from multiprocessing.connection import wait

from mpcwalk.bench.solvers.case_runner import CaseRunner, SolverCase, make_row
from mpcwalk.walking.processes import single_thread_environment

#: Timeouts in a group after which the rest of the group is skipped.
TIMEOUTS_BEFORE_SKIP = 2


def _worker_main(conn) -> None:  # pragma: no cover - runs in the child
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    os.dup2(devnull, 2)
    warnings.simplefilter("ignore")
    runner = CaseRunner()
    while True:
        try:
            case = conn.recv()
        except EOFError:
            return
        if case is None:
            return
        conn.send(runner.run(case))


class _Worker:
    def __init__(self, context) -> None:
        parent, child = context.Pipe()
        with single_thread_environment():
            self.process = context.Process(target=_worker_main, args=(child,), daemon=True)
            self.process.start()
        child.close()
        self.conn = parent
        self.case: SolverCase | None = None
        self.deadline = 0.0

    def stop(self, kill: bool = False) -> None:
        if kill:
            self.process.kill()
        else:
            with contextlib.suppress(OSError, BrokenPipeError):
                self.conn.send(None)
        self.process.join(timeout=5.0)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()
        self.conn.close()


class TimedPool:
    """Run :class:`SolverCase` objects in ``nb_workers`` processes.

    Args:
        nb_workers: Worker processes (1: no two timed solves overlap).
        setup_allowance: Seconds added to each case's hard limit for work that
            is not timed (QP construction, CasADi code generation), in [s].
    """

    def __init__(self, nb_workers: int = 1, *, setup_allowance: float = 5.0) -> None:
        self.nb_workers = max(1, int(nb_workers))
        self.setup_allowance = setup_allowance
        self._context = multiprocessing.get_context("spawn")

    def hard_limit(self, case: SolverCase) -> float:
        """Wall time after which the worker of ``case`` is killed, in [s]."""
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
            cases: Cases; give those of a group one after the other, by
                increasing horizon, for the skip rule to save time.
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

        workers = [_Worker(self._context) for _ in range(self.nb_workers)]
        try:
            while pending or any(w.case is not None for w in workers):
                for worker in workers:
                    while worker.case is None and pending:
                        case = pending.popleft()
                        limit = saturated.get(case.group[:-1])
                        if limit is not None and case.problem.horizon >= limit:
                            record(
                                make_row(
                                    case,
                                    runtime=case.level.runtime,
                                    found=False,
                                    status="skipped: timeouts in this group",
                                    timeout=True,
                                ),
                                case,
                            )
                            continue
                        worker.conn.send(case)
                        worker.case = case
                        worker.deadline = time.monotonic() + self.hard_limit(case)
                busy = [w for w in workers if w.case is not None]
                if not busy:
                    continue
                timeout = max(0.0, min(w.deadline for w in busy) - time.monotonic())
                ready = wait([w.conn for w in busy], timeout=timeout)
                for i, worker in enumerate(workers):
                    if worker.case is None:
                        continue
                    case = worker.case
                    if worker.conn in ready:
                        try:
                            row = worker.conn.recv()
                        except (EOFError, OSError):
                            row = make_row(
                                case,
                                runtime=case.level.runtime,
                                found=False,
                                status="error: worker crashed",
                            )
                            worker.stop(kill=True)
                            workers[i] = worker = _Worker(self._context)
                        worker.case = None
                        record(row, case)
                    elif time.monotonic() > worker.deadline:
                        worker.stop(kill=True)
                        workers[i] = _Worker(self._context)
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
                worker.stop(kill=worker.case is not None)
            bar.close()
        return rows
