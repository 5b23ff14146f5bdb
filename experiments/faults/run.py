"""The table of issue 13: bad inputs refused cleanly, faults survived or stopped cleanly with
their results written, interrupts with their partial results, atomic outputs.

Usage (from the repository root)::

    python experiments/faults/run.py --out results/faults

Runs the suite's cases (``tests/test_bad_inputs.py``, ``tests/test_faults.py``,
``tests/test_outputs.py``: each asserts the named error, the exit code and the files left
in --out) and counts them per kind into ``--out/README.md``.
"""

import argparse
import sys
from collections import Counter
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FILES = ("tests/test_bad_inputs.py", "tests/test_faults.py", "tests/test_outputs.py")

#: Kind of a case, from its test's name, and what a pass means.
KINDS = {
    "test_bad_cli_input": ("bad inputs, command line", "exit 2, a named error, nothing created"),
    "test_bad_api_input": ("bad inputs, Python API", "a named MpcwalkError, nothing run"),
    "test_negative_numbers": ("inputs that must be accepted", "runs"),
    "test_a_path_file_with": ("inputs that must be accepted", "runs"),
    "test_a_faulty_solve": ("faults injected, survived", "walks, faults counted, no NaN out"),
    "test_nan_and_dropped": ("faults injected, survived", "walks, faults counted, no NaN out"),
    "test_a_back_end_that": ("faults injected, stopped", "exit 3, log and metrics written"),
    "test_a_long_sensor": ("faults injected, stopped", "outcome stopped, log written"),
    "test_fault_monitor": ("fault bookkeeping", "counts and bound"),
    "test_sigint": ("interrupts", "exit 130, partial log and metrics written"),
    "test_atomic": ("outputs", "atomic writes"),
    "test_metrics_are": ("outputs", "metrics.json last"),
    "test_an_earlier": ("outputs", "earlier run refused unless --overwrite"),
    "test_an_internal": ("outputs", "exit 4, one line, traceback saved"),
    "test_mujoco": ("outputs", "MuJoCo's log under --out"),
}


class _Tally:
    def __init__(self) -> None:
        self.tried: Counter = Counter()
        self.passed: Counter = Counter()

    def pytest_runtest_logreport(self, report) -> None:
        if report.when != "call" and not (report.when == "setup" and report.failed):
            return
        name = report.nodeid.split("::")[-1]
        for prefix, (kind, _) in KINDS.items():
            if name.startswith(prefix):
                self.tried[kind] += 1
                self.passed[kind] += int(report.passed)
                return


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "results" / "faults")
    args = parser.parse_args(argv)
    tally = _Tally()
    code = pytest.main(
        ["-q", "-p", "no:cacheprovider", *(str(ROOT / f) for f in FILES)], plugins=[tally]
    )
    meaning: dict[str, list[str]] = {}
    for kind, what in KINDS.values():
        meaning.setdefault(kind, []).append(what)
    lines = [
        "# Faults, inputs and outputs",
        "",
        "Made by `python experiments/faults/run.py --out results/faults`: the cases of "
        + ", ".join(f"`{f}`" for f in FILES)
        + ", each asserting the named error, the exit code and the files left in `--out`.",
        "",
        "| kind | tried | passed | a pass means |",
        "|---|---:|---:|---|",
    ]
    for kind in dict.fromkeys(kind for kind, _ in KINDS.values()):
        what = "; ".join(dict.fromkeys(meaning[kind]))
        lines.append(f"| {kind} | {tally.tried[kind]} | {tally.passed[kind]} | {what} |")
    lines += [
        "",
        "Exit codes of `mpcwalk`: 0 walked (or success), 1 the robot fell, 2 bad input (before "
        "anything ran), 3 the controller stopped the walk (faults beyond its bound), 4 internal "
        "error (one line; the traceback in `--out/traceback.txt`, `--debug` prints it), 130 "
        "interrupted (the partial walk's log and `metrics.json` with `interrupted: true`).",
        "",
    ]
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "README.md").write_text("\n".join(lines))
    print("\n".join(lines))
    return int(code)


if __name__ == "__main__":
    sys.exit(main())
