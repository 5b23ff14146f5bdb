"""The offline solves of the solver benchmark: one case solved and checked, and the timed
solves on Ray timing actors."""
