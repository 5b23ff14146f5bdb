"""The LIPM's push-recovery map (``mpcwalk experiment run capture_map``): the reference the
controllers' push maps are drawn against.

- :mod:`~mpcwalk.experiments.capture_map.cells`: the map of one robot;
- :mod:`~mpcwalk.experiments.capture_map.plots`: its polar plots;
- :mod:`~mpcwalk.experiments.capture_map.experiment`: the experiment of the registry.
"""
