"""Paper A's experiments (``mpcwalk experiment run paper_a``): every controller on the
straight and turning ``.mdat`` paths of ``paths/`` and the 3D ramp path (on the terrain file
beside it), atlas-like robot, one table of foot placement accuracy.

- :mod:`~mpcwalk.experiments.paper_a.config`: the controllers and paths (``config.toml``);
- :mod:`~mpcwalk.experiments.paper_a.walks`: one controller on one path, its row;
- :mod:`~mpcwalk.experiments.paper_a.table`: the table and the placement-error figure;
- :mod:`~mpcwalk.experiments.paper_a.run`: the walks on the sweep engine;
- :mod:`~mpcwalk.experiments.paper_a.make_paths`: writes the ``.mdat`` paths again;
- :mod:`~mpcwalk.experiments.paper_a.experiment`: the experiment of the registry.
"""
