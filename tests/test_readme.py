"""The README as a new user reads it: every Python snippet runs alone, in a fresh interpreter,
and the names it shows exist."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

import mpcwalk

README = Path(__file__).resolve().parent.parent / "README.md"
SNIPPETS = re.findall(r"^```python\n(.*?)^```", README.read_text(), re.MULTILINE | re.DOTALL)


def test_the_readme_has_python_snippets():
    assert len(SNIPPETS) >= 2


@pytest.mark.parametrize("index", range(len(SNIPPETS)))
def test_readme_snippet_runs_alone(index, tmp_path):
    """Each snippet in its own interpreter (nothing imported before it), from another folder."""
    completed = subprocess.run(
        [sys.executable, "-c", SNIPPETS[index]],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert completed.returncode == 0, completed.stderr
    assert completed.stdout.strip(), "a snippet prints what it computed"
    assert not completed.stderr.strip(), completed.stderr  # a library is quiet


def test_dir_lists_the_lazy_exports():
    names = dir(mpcwalk)
    for name in ("run_walk", "WalkMetrics", "load_robot", "MpcGenerator", "__version__"):
        assert name in names
    assert set(mpcwalk.__all__) <= set(names)


def test_readme_names_every_generator():
    text = README.read_text()
    assert "any of the five" not in text
    for name in mpcwalk.generator_names():
        assert f"| `{name}` |" in text
    assert len(mpcwalk.generator_names()) == 8
