"""Faults, inputs and outputs (``mpcwalk experiment run faults``): bad inputs refused
cleanly, faults survived or stopped cleanly with their results written, interrupts with
their partial results, atomic outputs; the repository's test cases of each, counted per
kind.

- :mod:`~mpcwalk.experiments.faults.tally`: one test file run by pytest, its cases per kind;
- :mod:`~mpcwalk.experiments.faults.experiment`: the experiment of the registry.
"""
