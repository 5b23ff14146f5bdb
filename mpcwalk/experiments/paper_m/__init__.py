"""Paper M's experiments on the bioloid-like robot, for every controller of the comparison:
the turning walk, the disturbances F1 and F2, the push sweep and the speed search
(``mpcwalk experiment run paper_m``).

- :mod:`~mpcwalk.experiments.paper_m.config`: the parameters (``config.toml``);
- :mod:`~mpcwalk.experiments.paper_m.walks`: the controllers and each kind of walk;
- :mod:`~mpcwalk.experiments.paper_m.push_grid`: the push sweep's grid and summary;
- :mod:`~mpcwalk.experiments.paper_m.cases`: the push cells and speed searches on the sweep
  engine;
- :mod:`~mpcwalk.experiments.paper_m.run`: everything in one call;
- :mod:`~mpcwalk.experiments.paper_m.table` and :mod:`~mpcwalk.experiments.paper_m.plots`:
  the report and the figures;
- :mod:`~mpcwalk.experiments.paper_m.experiment`: the experiment of the registry.
"""
