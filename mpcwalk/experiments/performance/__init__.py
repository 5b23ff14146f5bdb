"""Where a control tick's time goes (``mpcwalk experiment run performance``): whole walks
under ``cProfile``, the loop's time split per part.

- :mod:`~mpcwalk.experiments.performance.profile`: one walk profiled;
- :mod:`~mpcwalk.experiments.performance.experiment`: the experiment of the registry.
"""
