"""The robustness matrix (``mpcwalk experiment run robustness``): every controller, on every
robot, in worlds that are not the model; its terrain factors alone
(``mpcwalk experiment run robustness_terrain``).

- :mod:`~mpcwalk.experiments.robustness.config`: robots, controllers, factors and ranges
  (``config.toml``);
- :mod:`~mpcwalk.experiments.robustness.factors`: the factors and the worlds of each robot;
- :mod:`~mpcwalk.experiments.robustness.terrains`: the terrain factors' terrains, scaled to
  the robot, and the steps that cross them;
- :mod:`~mpcwalk.experiments.robustness.worlds`: the walks of the worlds, the skipped ones;
- :mod:`~mpcwalk.experiments.robustness.cells`: which rows make a cell, success rates;
- :mod:`~mpcwalk.experiments.robustness.goals`: the goals of the QP controllers;
- :mod:`~mpcwalk.experiments.robustness.report`,
  :mod:`~mpcwalk.experiments.robustness.terrain_report` and
  :mod:`~mpcwalk.experiments.robustness.plots`: the report and its heat maps;
- :mod:`~mpcwalk.experiments.robustness.experiment`: the experiments of the registry.

Each robot's nominal command is one where paper M's engine (``paper-m``) walks unperturbed,
as the paper reports it walking (0.1 m/s on its small humanoid), so that its rows are a
reference: 0.1 m/s on ``bioloid-like``, ``g1`` and ``atlas-like`` (``paper-m`` falls on the
last two at 0.15 and 0.2 m/s), 0.15 m/s on ``talos`` and ``romeo``.
"""
