"""Timed work on Ray: one actor holding one CPU, one call at a time, under a hard limit.

The benchmarks time solves and ticks: two timed calls must never share a core, and nothing
else of the benchmark may run beside them. A :class:`TimingWorker` is a Ray actor that
reserves one CPU slot of the Ray instance (``num_cpus=1``, so no task of a sweep lands
there), runs with one thread per numerical library and its output silenced, and runs the
calls it is given one after the other. A call over its hard limit has its actor killed and
replaced (a back-end with no time limit of its own, or stuck); so has a call whose actor
dies. :func:`run_isolated` runs one call on a fresh actor.
"""

import os
import warnings
from collections.abc import Callable
from typing import Any

from mpcwalk.exceptions import MpcwalkError
from mpcwalk.sweep.cluster import ensure_ray, import_ray


class TimedCallFailed(MpcwalkError, RuntimeError):
    """A timed call ran over its hard limit, or its worker died."""

    def __init__(self, reason: str) -> None:
        self.reason = reason
        super().__init__(f"The timed call failed: {reason}")


class _TimingActor:
    """The actor's body: an optional target object made once, calls on demand."""

    def __init__(self, factory: Callable[[], Any] | None, silence: bool) -> None:
        if silence:  # solver banners
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 1)
            os.dup2(devnull, 2)
            warnings.simplefilter("ignore")
        self.target = None if factory is None else factory()

    def call(self, function: str | Callable[..., Any], args: tuple) -> Any:
        if isinstance(function, str):
            return getattr(self.target, function)(*args)
        return function(*args)


class TimingWorker:
    """One timing actor (see the module docstring).

    Args:
        factory: Module-level callable making the object whose methods :meth:`submit` may
            name (e.g. a case runner that caches its problems); None: plain functions only.
        silence: Silence the actor's standard output and error.
        address: Ray cluster (None: ``RAY_ADDRESS``, else local).
    """

    def __init__(
        self,
        factory: Callable[[], Any] | None = None,
        *,
        silence: bool = True,
        address: str | None = None,
    ) -> None:
        ensure_ray(address=address)
        self._ray = import_ray()
        self._factory, self._silence = factory, silence
        self._actor: Any = None
        self.restart()

    def restart(self) -> None:
        """Kill the actor (if any) and start a fresh one."""
        if self._actor is not None:
            self._ray.kill(self._actor)
        actor_class = self._ray.remote(num_cpus=1, max_restarts=0)(_TimingActor)
        self._actor = actor_class.remote(self._factory, self._silence)

    def submit(self, function: str | Callable[..., Any], *args: Any) -> Any:
        """Start a call (a method name of the factory's object, or a module-level function);
        its Ray object reference."""
        return self._actor.call.remote(function, args)

    def result(self, ref: Any, *, hard_limit: float | None = None) -> Any:
        """The result of a started call.

        Raises:
            TimedCallFailed: Over ``hard_limit`` [s] (the actor is then replaced), or the
                actor died (replaced too).
            Exception: The call's own exception.
        """
        ray = self._ray
        try:
            return ray.get(ref, timeout=hard_limit)
        except ray.exceptions.GetTimeoutError:
            self.restart()
            raise TimedCallFailed(f"over the hard time limit of {hard_limit:g} s") from None
        except ray.exceptions.RayTaskError as error:
            raise error.as_instanceof_cause() from None
        except ray.exceptions.RayError as error:
            self.restart()
            raise TimedCallFailed(f"the worker died ({type(error).__name__})") from error

    def call(
        self, function: str | Callable[..., Any], *args: Any, hard_limit: float | None = None
    ) -> Any:
        """Run one call and return its result (see :meth:`result`)."""
        return self.result(self.submit(function, *args), hard_limit=hard_limit)

    def close(self) -> None:
        """Stop the actor."""
        if self._actor is not None:
            self._ray.kill(self._actor)
            self._actor = None


def run_isolated(function: Callable[..., Any], *args: Any, address: str | None = None) -> Any:
    """Call ``function(*args)`` on a fresh timing actor (one CPU, nothing beside it) and
    return its result."""
    worker = TimingWorker(address=address)
    try:
        return worker.call(function, *args)
    finally:
        worker.close()


def wait_any(refs: list[Any], timeout: float) -> list[Any]:
    """The references among ``refs`` ready within ``timeout`` [s]: the first one, and every
    other one ready by then."""
    ray = import_ray()
    ready, rest = ray.wait(refs, num_returns=1, timeout=max(0.0, timeout))
    if ready and rest:
        more, _ = ray.wait(rest, num_returns=len(rest), timeout=0)
        ready += more
    return ready


__all__ = ["TimedCallFailed", "TimingWorker", "run_isolated", "wait_any"]
