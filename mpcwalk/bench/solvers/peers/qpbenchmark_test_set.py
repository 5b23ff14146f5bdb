"""The walking QPs as a qpbenchmark ``TestSet`` (needs ``pip install mpcwalk[bench]``)."""

import os
from collections.abc import Iterable, Iterator
from pathlib import Path

import qpbenchmark
from qpbenchmark import Problem


class WalkingTestSet(qpbenchmark.TestSet):
    """Walking MPC QPs exported by :func:`~mpcwalk.bench.solvers.peers.qpbenchmark_export.export_test_set`.

    qpbenchmark builds test sets without arguments: a launcher subclass sets
    :attr:`data_dir` (see the ``mpcwalk_qpbenchmark.py`` the export writes).

    Args:
        data_dir: Directory of the ``.npz`` problems (default: :attr:`data_dir`).
        solvers: Keep only these qpsolvers names (default: all qpbenchmark knows).
        time_limit: Time limit of one solve, in [s] (default: :attr:`time_limit`).
    """

    data_dir: str | Path = ""
    time_limit: float = 1.0
    solvers: set[str]

    def __init__(
        self,
        data_dir: str | Path | None = None,
        *,
        solvers: Iterable[str] | None = None,
        time_limit: float | None = None,
    ) -> None:
        if data_dir is not None:
            self.data_dir = data_dir
        if time_limit is not None:
            self.time_limit = float(time_limit)
        super().__init__()
        if solvers is not None:
            self.solvers = set(self.solvers) & set(solvers)

    @property
    def description(self) -> str:
        return (
            "Walking model predictive control QPs of mpcwalk: CoM jerk over the horizon, "
            "ZMP (and CoM) in the support polygons, sampled along 20-step walks of a "
            "small humanoid (dense and sparse formulations)."
        )

    @property
    def title(self) -> str:
        return "mpcwalk walking MPC test set"

    @property
    def sparse_only(self) -> bool:
        return False

    def define_tolerances(self, runtime: float | None = None) -> None:
        """qpbenchmark's four levels, with this set's time limit."""
        super().define_tolerances(runtime=self.time_limit if runtime is None else runtime)

    def __iter__(self) -> Iterator[Problem]:
        directory = str(self.data_dir)
        for name in sorted(os.listdir(directory)):
            if name.endswith(".npz"):
                yield Problem.load(os.path.join(directory, name))
