"""The ``mpcwalk`` command line: one small module per command, each parsing its options,
building what the library takes (a walk specification, an experiment's options) and calling
the library; input checking at this boundary.

- :mod:`~mpcwalk.cli.walk` (with :mod:`~mpcwalk.cli.walk_options`): ``mpcwalk walk``;
- :mod:`~mpcwalk.cli.plan`: ``mpcwalk plan``;
- :mod:`~mpcwalk.cli.lists`: ``mpcwalk generators|controllers|stabilizers|solvers``;
- :mod:`~mpcwalk.cli.robots`: ``mpcwalk robots [check NAME]``;
- :mod:`~mpcwalk.cli.replay`: ``mpcwalk replay DIR``;
- :mod:`~mpcwalk.cli.bench` (with :mod:`~mpcwalk.cli.bench_solvers`): ``mpcwalk bench
  ticks|ik|loop|solvers``;
- :mod:`~mpcwalk.cli.experiment`: ``mpcwalk experiment list|run``.
"""

from mpcwalk.cli.main import build_parser, main

__all__ = ["build_parser", "main"]
