"""The push maps (``mpcwalk experiment run push_map``): the largest push each controller
survives per direction, phase and walking speed, against ``paper-m`` and against the LIPM's
capture bounds of the same cell.

- :mod:`~mpcwalk.experiments.push_map.cases`: the grid, one cell's bisection, the sweep;
- :mod:`~mpcwalk.experiments.push_map.report` and :mod:`~mpcwalk.experiments.push_map.plots`:
  the report, polar plots and heat maps;
- :mod:`~mpcwalk.experiments.push_map.experiment`: the experiment of the registry (one map
  per robot).
"""
