"""The terrain experiment (``mpcwalk experiment run terrain``): per robot, the controllers
on stairs (the largest rise climbed, by bisection), slopes up and down, stepping stones and
a rough patch, against the issue's goals.

- :mod:`~mpcwalk.experiments.terrain.config`: the configuration (``config.toml``);
- :mod:`~mpcwalk.experiments.terrain.walks`: the terrains sized for each robot, one walk;
- :mod:`~mpcwalk.experiments.terrain.cases`: the cases, the bisection, the sweep;
- :mod:`~mpcwalk.experiments.terrain.report`, :mod:`~mpcwalk.experiments.terrain.goals`
  and :mod:`~mpcwalk.experiments.terrain.plots`: the report, the goals and the figures;
- :mod:`~mpcwalk.experiments.terrain.experiment`: the experiment of the registry.
"""
