"""The experiments: one subpackage each, behind one protocol
(:class:`~mpcwalk.experiments.protocol.Experiment`) and one registry
(:data:`~mpcwalk.experiments.catalog.EXPERIMENTS`), run by ``mpcwalk experiment run NAME``
into ``results/NAME``.

Shared by all: :mod:`~mpcwalk.experiments.survival` (when a walk survives, and the largest
push it survives), :mod:`~mpcwalk.experiments.reporting` (tables, medians, Wilson intervals,
run records). The command line is :mod:`mpcwalk.cli.experiment`.
"""
