"""Pattern generators by name: the names of the command line and of :func:`make_generator`.

:data:`GENERATORS` is one :class:`~mpcwalk.registry.Registry`: each generator module is
imported when its name is first asked for, so that naming a closed form does not load the QP
back-ends. A new generator is one :class:`~mpcwalk.registry.Entry` of :data:`GENERATORS` and
a :class:`~mpcwalk.generators.pattern_generator.PatternGenerator` subclass whose ``name`` is
that entry's name.
"""

import importlib
import inspect
from collections.abc import Callable
from typing import Any

from mpcwalk.exceptions import ConfigurationError, GeneratorNotFound
from mpcwalk.generators.pattern_generator import PatternGenerator
from mpcwalk.registry import Entry, Registry


def _class(module: str, name: str) -> Callable[[], type[PatternGenerator]]:
    """Loader of the class ``name`` of ``mpcwalk.generators.<module>``."""

    def load() -> type[PatternGenerator]:
        generator: type[PatternGenerator] = getattr(
            importlib.import_module(f"mpcwalk.generators.{module}"), name
        )
        return generator

    return load


#: The pattern generators by name, in the order the command line lists them.
GENERATORS: Registry[type[PatternGenerator]] = Registry(
    "pattern generator",
    [
        Entry(
            "analytic",
            "Closed-form LIPM CoM, step by step, open loop (paper M).",
            _class("analytic", "AnalyticGenerator"),
        ),
        Entry(
            "static",
            "CoM above the support foot in single support, quintic shifts in double support.",
            _class("static", "StaticGenerator"),
        ),
        Entry(
            "preview",
            "Kajita's ZMP preview control following the schedule's ZMP reference.",
            _class("preview", "PreviewGenerator"),
        ),
        Entry(
            "mpc",
            "Wieber-style linear MPC: ZMP tracking with ZMP constraints.",
            _class("mpc", "MpcGenerator"),
        ),
        Entry(
            "static-qp",
            "The static gait (paper A) as a receding-horizon QP.",
            _class("static_qp", "StaticQPGenerator"),
        ),
        Entry(
            "mpc-steps",
            "Linear MPC that also places the next footsteps (Herdt et al. 2010).",
            _class("mpc_steps", "FootstepMpcGenerator"),
        ),
        Entry(
            "mpc-nlp",
            "mpc-steps with optimal step timing: next landings and durations from a CasADi NLP.",
            _class("mpc_nlp", "TimingNlpGenerator"),
        ),
        Entry(
            "mpc-hip",
            "mpc-steps with the upper body as a flywheel (the hip strategy, Pratt et al. 2006).",
            _class("mpc_hip", "HipStrategyMpcGenerator"),
        ),
    ],
    list_command="mpcwalk generators",
    not_found=GeneratorNotFound,
)


def generator_names() -> list[str]:
    """Names accepted by :func:`make_generator`."""
    return GENERATORS.names()


def generator_class(name: str) -> type[PatternGenerator]:
    """Class of the generator called ``name``.

    Raises:
        GeneratorNotFound: Unknown name (the message lists the known ones).
    """
    return GENERATORS.load(name)


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


def check_options(cls: Callable[..., Any], options: dict[str, Any], what: str) -> None:
    """Refuse keywords that ``cls`` (a class or a factory) does not take, naming the valid
    ones."""
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
