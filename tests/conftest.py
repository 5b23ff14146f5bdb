"""Shared test helpers: robots loaded once per session, walks of a specification on them, and
the walk loop of generators and controllers.

Test modules use the fixtures, or import the helpers where a module-level cached function
needs them (``from conftest import get_robot, walk, walk_outputs``).
"""

import functools
from collections.abc import Callable
from typing import Any

import pytest

from mpcwalk.robot import Robot
from mpcwalk.robot.loading import load_robot


@functools.cache
def get_robot(name: str = "bioloid-like") -> Robot:
    """Robot ``name``, loaded once per test session, without meshes (same kinematics and
    physics, faster). Shared: do not modify it."""
    return load_robot(name, visual=False)


def walk(robot: str = "bioloid-like", controller: Any = None, **fields: Any) -> Any:
    """The :class:`~mpcwalk.walking.result.WalkResult` of ``run_walk`` of
    ``WalkSpec.build(robot, controller=controller, **fields)`` (a controller name or a
    ``ControllerSpec``, None: ``mpc``; any field of the specification by its name), on the
    session's copy of the robot (:func:`get_robot`)."""
    from mpcwalk.walking.runner import run_walk
    from mpcwalk.walking.specification import WalkSpec

    spec = WalkSpec.build(robot, controller=controller, **fields)
    return run_walk(spec, robot=get_robot(robot))


def walk_outputs(walker, *reset_args, measured: Callable[[Any], Any] | None = None) -> list:
    """Outputs of a whole walk of a pattern generator or a controller.

    Args:
        walker: Anything with ``reset(*reset_args)``, ``step(measurement)`` and ``done``.
        reset_args: Arguments of ``reset`` (a generator's schedule; none for a controller).
        measured: ``measured(last_output)`` gives the measurement of the next tick; None: open
            loop (``step()`` without argument).

    Returns:
        The output of ``reset`` followed by the output of every tick.
    """
    outputs = [walker.reset(*reset_args)]
    while not walker.done:
        outputs.append(walker.step() if measured is None else walker.step(measured(outputs[-1])))
    return outputs


@pytest.fixture(scope="session")
def robot_loader() -> Callable[[str], Robot]:
    """:func:`get_robot`: robots by name, loaded once per session."""
    return get_robot


@pytest.fixture(scope="session")
def bioloid() -> Robot:
    """The small humanoid of paper M (``bioloid-like``), loaded once per session."""
    return get_robot("bioloid-like")


@pytest.fixture(scope="session")
def atlas() -> Robot:
    """The large humanoid of paper A (``atlas-like``), loaded once per session."""
    return get_robot("atlas-like")


def _plain(value: Any) -> Any:
    """``value`` with numpy scalars and arrays as Python numbers and lists (a test report is
    sent between the suite's worker processes, which cannot send numpy objects)."""
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    if hasattr(value, "tolist"):
        return value.tolist()
    return value


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """Recorded test properties as plain Python values."""
    outcome = yield
    report = outcome.get_result()
    report.user_properties = [(key, _plain(value)) for key, value in report.user_properties]
