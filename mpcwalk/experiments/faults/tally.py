"""The tally of the faults experiment: each case of the repository's fault tests run by
pytest in a subprocess, its outcome read from pytest's JUnit XML, counted per kind."""

import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree
from collections import Counter
from collections.abc import Iterable
from pathlib import Path

import mpcwalk
from mpcwalk.exceptions import ConfigurationError

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


def find_repository(start: str | Path | None = None) -> Path:
    """The checkout of mpcwalk whose ``tests/`` the experiment runs: the working directory
    (or ``start``) or a parent holding ``tests/test_faults.py``, else the folder beside the
    package (an editable install).

    Raises:
        ConfigurationError: None found (an installed wheel has no tests).
    """
    here = (Path.cwd() if start is None else Path(start)).resolve()
    for folder in [here, *here.parents, Path(mpcwalk.__file__).resolve().parents[1]]:
        if (folder / "tests" / "test_faults.py").is_file():
            return folder
    raise ConfigurationError(
        f"The faults experiment runs the test files of a checkout of mpcwalk, but none was "
        f"found from {here} (an installed wheel has no tests); run it from the repository."
    )


def run_test_file(root: Path, file: str, select: str = "") -> list[tuple[str, bool]]:
    """Run one test file of ``root`` with pytest (``select``: a ``-k`` expression) in a
    subprocess; ``(test name, passed)`` of each case."""
    with tempfile.TemporaryDirectory() as folder:
        report = Path(folder) / "junit.xml"
        command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider"]
        command += ["-o", "addopts=", f"--junitxml={report}", str(root / file)]
        command += ["-k", select] if select else []
        subprocess.run(command, cwd=root, capture_output=True, text=True, check=False)
        if not report.exists():
            return []
        cases = []
        for case in ElementTree.parse(report).getroot().iter("testcase"):
            failed = any(child.tag in ("failure", "error") for child in case)
            skipped = any(child.tag == "skipped" for child in case)
            if not skipped:
                cases.append((case.get("name", ""), not failed))
        return cases


def kind_of(name: str) -> str | None:
    """The kind of a test case (:data:`KINDS`), from its name; None for the others."""
    for prefix, (kind, _) in KINDS.items():
        if name.startswith(prefix):
            return kind
    return None


def tally(cases: Iterable[tuple[str, bool]]) -> tuple[Counter, Counter]:
    """Cases tried and passed per kind."""
    tried: Counter = Counter()
    passed: Counter = Counter()
    for name, ok in cases:
        kind = kind_of(name)
        if kind is not None:
            tried[kind] += 1
            passed[kind] += int(ok)
    return tried, passed


__all__ = ["KINDS", "find_repository", "kind_of", "run_test_file", "tally"]
