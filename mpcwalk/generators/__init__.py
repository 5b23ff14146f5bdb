"""CoM/ZMP pattern generators, all behind :class:`PatternGenerator`."""

import importlib

from mpcwalk.exceptions import GeneratorNotFound
from mpcwalk.generators.pattern_generator import (
    ComState,
    GeneratorOutput,
    Horizon,
    PatternGenerator,
    SolveInfo,
)
from mpcwalk.generators.rollout import Rollout, rollout

#: Generator name -> (module, class). Imported on demand.
_REGISTRY: dict[str, tuple[str, str]] = {
    "analytic": ("mpcwalk.generators.analytic", "AnalyticGenerator"),
    "static": ("mpcwalk.generators.static", "StaticGenerator"),
    "preview": ("mpcwalk.generators.preview", "PreviewGenerator"),
    "mpc": ("mpcwalk.generators.mpc", "MpcGenerator"),
    "static-qp": ("mpcwalk.generators.static_qp", "StaticQPGenerator"),
    "mpc-steps": ("mpcwalk.generators.mpc_steps", "FootstepMpcGenerator"),
}


def generator_names() -> list[str]:
    """Names accepted by :func:`make_generator`."""
    return list(_REGISTRY)


def generator_class(name: str) -> type:
    """Class of the generator called ``name``."""
    if name not in _REGISTRY:
        raise GeneratorNotFound(name, generator_names())
    module, cls = _REGISTRY[name]
    return getattr(importlib.import_module(module), cls)


def make_generator(name: str, **kwargs) -> PatternGenerator:
    """Instantiate a generator by name, e.g. ``make_generator("mpc", solver="osqp")``."""
    return generator_class(name)(**kwargs)


__all__ = [
    "ComState",
    "GeneratorOutput",
    "Horizon",
    "PatternGenerator",
    "Rollout",
    "SolveInfo",
    "generator_class",
    "generator_names",
    "make_generator",
    "rollout",
]
