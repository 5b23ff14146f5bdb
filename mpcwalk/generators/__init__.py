"""CoM/ZMP pattern generators, all behind :class:`PatternGenerator`."""

import importlib
from typing import Dict, List, Tuple

from ..exceptions import GeneratorNotFound
from .pattern_generator import ComState, GeneratorOutput, Horizon, PatternGenerator, SolveInfo
from .rollout import Rollout, rollout

#: Generator name -> (module, class). Imported on demand.
_REGISTRY: Dict[str, Tuple[str, str]] = {
    "analytic": (".analytic", "AnalyticGenerator"),
    "static": (".static", "StaticGenerator"),
    "preview": (".preview", "PreviewGenerator"),
    "mpc": (".mpc", "MpcGenerator"),
    "static-qp": (".static_qp", "StaticQPGenerator"),
    "mpc-steps": (".mpc_steps", "FootstepMpcGenerator"),
}


def generator_names() -> List[str]:
    """Names accepted by :func:`make_generator`."""
    return list(_REGISTRY)


def generator_class(name: str) -> type:
    """Class of the generator called ``name``."""
    if name not in _REGISTRY:
        raise GeneratorNotFound(name, generator_names())
    module, cls = _REGISTRY[name]
    return getattr(importlib.import_module(module, __name__), cls)


def make_generator(name: str, **kwargs) -> PatternGenerator:
    """Instantiate a generator by name, e.g. ``make_generator("mpc", solver="osqp")``."""
    return generator_class(name)(**kwargs)


__all__ = [
    "ComState", "GeneratorOutput", "Horizon", "PatternGenerator", "Rollout", "SolveInfo",
    "generator_class", "generator_names", "make_generator", "rollout",
]
