"""Pattern generators by name: the names of the command line and of :func:`make_generator`.

Each generator module is imported when its name is first asked for, so that naming a
closed form does not load the QP back-ends. A new generator is one line of
:data:`GENERATORS` and a :class:`~mpcwalk.generators.pattern_generator.PatternGenerator`
subclass whose ``name`` is that key.
"""

import importlib
import inspect
from typing import Any

from mpcwalk.exceptions import ConfigurationError, GeneratorNotFound
from mpcwalk.generators.pattern_generator import PatternGenerator

#: Generator name -> (module, class). Imported on demand.
GENERATORS: dict[str, tuple[str, str]] = {
    "analytic": ("mpcwalk.generators.analytic", "AnalyticGenerator"),
    "static": ("mpcwalk.generators.static", "StaticGenerator"),
    "preview": ("mpcwalk.generators.preview", "PreviewGenerator"),
    "mpc": ("mpcwalk.generators.mpc", "MpcGenerator"),
    "static-qp": ("mpcwalk.generators.static_qp", "StaticQPGenerator"),
    "mpc-steps": ("mpcwalk.generators.mpc_steps", "FootstepMpcGenerator"),
}


def generator_names() -> list[str]:
    """Names accepted by :func:`make_generator`."""
    return list(GENERATORS)


def generator_class(name: str) -> type[PatternGenerator]:
    """Class of the generator called ``name``.

    Raises:
        GeneratorNotFound: Unknown name (the message lists the known ones).
    """
    if name not in GENERATORS:
        raise GeneratorNotFound(name, generator_names())
    module, cls = GENERATORS[name]
    generator: type[PatternGenerator] = getattr(importlib.import_module(module), cls)
    return generator


def make_generator(name: str, **kwargs: Any) -> PatternGenerator:
    """Instantiate a generator by name, e.g. ``make_generator("mpc", solver="osqp")``.

    Raises:
        GeneratorNotFound: Unknown name.
        ConfigurationError: A keyword the generator does not take (the message lists the
            ones it takes: a closed form has no ``solver``), or a bad value.
    """
    cls = generator_class(name)
    check_options(cls, kwargs, f"generator '{name}'")
    return cls(**kwargs)


def check_options(cls: type, options: dict[str, Any], what: str) -> None:
    """Refuse keywords that ``cls``'s constructor does not take, naming the valid ones."""
    parameters = inspect.signature(cls).parameters
    if any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values()):
        return
    valid = [n for n, p in parameters.items() if p.kind is not p.VAR_POSITIONAL]
    unknown = sorted(set(options) - set(valid))
    if unknown:
        raise ConfigurationError(
            f"The {what} takes no option {', '.join(map(repr, unknown))}; its options are "
            f"{', '.join(valid)}."
        )
