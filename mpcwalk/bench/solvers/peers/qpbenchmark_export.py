"""Export the walking QPs as a qpbenchmark test set.

Each problem is saved as ``data/<name>.npz`` in the layout of
``qpsolvers.Problem.save`` (arrays ``P, q, G, h, A, b, lb, ub``; a missing
one stored as an empty object, which ``Problem.load`` reads back as None),
compressed. Next to ``data/`` a launcher ``mpcwalk_qpbenchmark.py`` defines
the test set class qpbenchmark's command line expects (``MpcwalkQpbenchmark``,
a :class:`~mpcwalk.bench.solvers.peers.qpbenchmark_test_set.WalkingTestSet`), so that::

    python mpcwalk_qpbenchmark.py run            # all solvers, all settings
    qpbenchmark mpcwalk_qpbenchmark.py run --settings mid_accuracy

run the set with qpbenchmark itself (``pip install mpcwalk[bench]``).
"""

from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np
import qpsolvers
import scipy.sparse as sp

from mpcwalk.bench.solvers.problems.families import WalkingProblem, get_family

#: Keys of a qpsolvers problem file.
PROBLEM_KEYS = ("P", "q", "G", "h", "A", "b", "lb", "ub")
#: File name of the launcher (qpbenchmark derives the class name from it).
LAUNCHER_NAME = "mpcwalk_qpbenchmark.py"

_LAUNCHER = '''"""qpbenchmark test set of mpcwalk's walking QPs (from `mpcwalk bench solvers`).

Run it with qpbenchmark (pip install "mpcwalk[bench]"):

    python mpcwalk_qpbenchmark.py run [--settings mid_accuracy] [--solver daqp]
    python mpcwalk_qpbenchmark.py report --author <name>
"""

import os

from mpcwalk.bench.solvers.peers.qpbenchmark_test_set import WalkingTestSet

HERE = os.path.dirname(os.path.abspath(__file__))


class MpcwalkQpbenchmark(WalkingTestSet):
    """The walking QPs in data/ next to this file."""

    data_dir = os.path.join(HERE, "data")
    time_limit = {time_limit!r}


if __name__ == "__main__":
    from qpbenchmark.benchmark import main

    main(test_set_path=os.path.abspath(__file__),
         results_path=os.path.join(HERE, "results", "qpbenchmark_results.csv"))
'''


def problem_name(problem: WalkingProblem, formulation: str) -> str:
    """Name of an exported problem (the file stem), e.g. ``"mpc-turning-n32-k345-dense"``."""
    return f"{problem.name}-{formulation}"


def build_problem(problem: WalkingProblem, formulation: str, qp=None) -> qpsolvers.Problem:
    """The QP of ``problem`` in qpsolvers form (CSC matrices).

    Args:
        problem: The walking problem.
        formulation: ``"dense"`` or ``"sparse"``.
        qp: A QP object of the problem's structure to reuse (built if None).
    """
    family = get_family(problem.family)
    if qp is None:
        qp = family.build_qp(problem.horizon, formulation, problem.control_period)
    family.update_qp(qp, problem.state, problem.time, problem.schedule())
    out = qp.problem(dense=False)
    return qpsolvers.Problem(*(_copy(getattr(out, k)) for k in PROBLEM_KEYS))


def _copy(M):
    """A copy the QP object's later updates cannot change."""
    return None if M is None else (M.copy() if sp.issparse(M) else np.array(M))


def save_problem(problem: qpsolvers.Problem, path: Path) -> None:
    """Save in ``qpsolvers.Problem.save``'s layout, compressed."""
    arrays: dict[str, Any] = {}
    for key in PROBLEM_KEYS:
        value = getattr(problem, key)
        if value is None:
            arrays[key] = np.array(None)
        else:
            arrays[key] = value.toarray() if sp.issparse(value) else np.asarray(value, dtype=float)
    np.savez_compressed(path, **arrays)


def load_problem(path: Path) -> qpsolvers.Problem:
    """Read a problem file (what qpbenchmark's ``Problem.load`` does)."""
    return qpsolvers.Problem.load(str(path))


def export_test_set(
    problems: Iterable[tuple[WalkingProblem, str]],
    out_dir: Path,
    *,
    time_limit: float = 1.0,
) -> list[str]:
    """Write ``out_dir/data/*.npz`` and the launcher; return the problem names.

    Args:
        problems: ``(problem, formulation)`` pairs.
        out_dir: Test set directory.
        time_limit: Time limit of one solve in the test set, in [s].
    """
    out_dir = Path(out_dir)
    data = out_dir / "data"
    data.mkdir(parents=True, exist_ok=True)
    names, qps = [], {}
    for problem, formulation in problems:
        key = problem.qp_key + (formulation,)
        if key not in qps:
            qps[key] = get_family(problem.family).build_qp(
                problem.horizon, formulation, problem.control_period
            )
        name = problem_name(problem, formulation)
        save_problem(build_problem(problem, formulation, qps[key]), data / f"{name}.npz")
        names.append(name)
    launcher = _LAUNCHER.replace("{time_limit!r}", repr(float(time_limit)))
    (out_dir / LAUNCHER_NAME).write_text(launcher)
    return names
