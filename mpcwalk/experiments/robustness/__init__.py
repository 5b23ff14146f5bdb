"""The robustness matrix (``mpcwalk experiment run robustness``): every controller, on every
robot, in worlds that are not the model.

- :mod:`~mpcwalk.experiments.robustness.config`: robots, controllers, factors and ranges
  (``config.toml``);
- :mod:`~mpcwalk.experiments.robustness.worlds`: the worlds of each robot and their walks;
- :mod:`~mpcwalk.experiments.robustness.cells`: which rows make a cell, success rates;
- :mod:`~mpcwalk.experiments.robustness.report` and
  :mod:`~mpcwalk.experiments.robustness.plots`: the report and its heat maps;
- :mod:`~mpcwalk.experiments.robustness.experiment`: the experiment of the registry.
"""
