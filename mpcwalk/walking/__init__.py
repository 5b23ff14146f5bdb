"""Walks in MuJoCo: a walk's specification (:mod:`~mpcwalk.walking.specification`), the one
controller builder (:mod:`~mpcwalk.walking.controller_builder`), the set-up checked before
anything runs (:mod:`~mpcwalk.walking.walk_setup`), :func:`~mpcwalk.walking.runner.run_walk`,
the control loop, the per-tick log, the metrics (:mod:`~mpcwalk.walking.metrics`), figures,
outputs, and walks as the cases of a sweep (:mod:`~mpcwalk.walking.sweep_cases`)."""
