"""Walks in worker processes: one robot loaded per process, a progress bar over the tasks.

The experiments of paper M run hundreds of short, independent walks (the push-recovery
sweep, the speed search). :func:`run_tasks` spreads them over processes with
:class:`concurrent.futures.ProcessPoolExecutor` (``spawn``, single-threaded numerical
libraries); a task is a module-level function and its arguments, and gets the robot from
:func:`worker_robot`, which loads it once per process.
"""

import multiprocessing
import os
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from typing import Any

from mpcwalk.exceptions import ConfigurationError, MpcwalkError

_ROBOTS: dict[str, Any] = {}


class WorkerProcessDied(MpcwalkError, RuntimeError):
    """A worker process of :func:`run_tasks` ended abruptly."""

    def __init__(self, workers: int) -> None:
        self.workers = workers
        super().__init__(
            f"A worker process (of {workers}) ended abruptly. Workers are spawned and import "
            "the calling script again: in a script, call run_tasks under "
            '`if __name__ == "__main__":`; otherwise run with workers=1 to see the error.'
        )


Task = tuple[Callable[..., Any], tuple]
"""A task: a module-level function and its (picklable) positional arguments."""


def worker_robot(name: str):
    """The robot called ``name``, loaded once per process (without meshes)."""
    if name not in _ROBOTS:
        from mpcwalk.robot.loading import load_robot

        _ROBOTS[name] = load_robot(name, visual=False)
    return _ROBOTS[name]


def default_workers() -> int:
    """Worker processes by default: one per core."""
    return os.cpu_count() or 1


def _call(function: Callable[..., Any], args: tuple) -> Any:
    return function(*args)


def run_tasks(
    tasks: Sequence[Task],
    *,
    workers: int | None = None,
    progress: bool = True,
    description: str = "walks",
) -> list[Any]:
    """Run tasks, in parallel when ``workers > 1``; results in the order of ``tasks``.

    Args:
        tasks: ``(function, args)`` pairs; the function must be importable (module level).
        workers: Worker processes (default: :func:`default_workers`); 1 runs the tasks in
            this process.
        progress: Show a tqdm progress bar over the tasks.
        description: Label of the progress bar.

    Worker processes are spawned: they import the calling script again, so a script must
    call this under ``if __name__ == "__main__":`` (a notebook need not).

    Raises:
        ConfigurationError: ``workers`` is not a positive integer.
        WorkerProcessDied: A worker process ended abruptly (killed, or a script without the
            ``__main__`` guard).
    """
    from tqdm import tqdm

    workers = default_workers() if workers is None else workers
    if not isinstance(workers, int) or workers < 1:
        raise ConfigurationError(f"workers must be a positive integer, got {workers!r}.")
    results: list[Any] = [None] * len(tasks)
    bar = tqdm(total=len(tasks), desc=description, disable=not progress)
    try:
        if workers == 1 or len(tasks) <= 1:
            for i, (function, args) in enumerate(tasks):
                results[i] = function(*args)
                bar.update(1)
            return results
        from mpcwalk.walking.processes import single_thread_environment

        context = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(
            max_workers=min(workers, len(tasks)), mp_context=context
        ) as executor:
            with single_thread_environment():  # the workers start at the first submit
                futures = {
                    executor.submit(_call, function, args): i
                    for i, (function, args) in enumerate(tasks)
                }
            try:
                for future in as_completed(futures):
                    results[futures[future]] = future.result()
                    bar.update(1)
            except BrokenProcessPool as error:
                raise WorkerProcessDied(workers) from error
        return results
    finally:
        bar.close()
