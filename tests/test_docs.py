"""The documentation site: it builds without a warning, its Python snippets run, and its
generated reference pages match the code."""

import argparse
import importlib.util
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = sorted(DOCS.rglob("*.md"))
BLOCK = re.compile(r"^```python\n(.*?)^```", re.MULTILINE | re.DOTALL)


def _generator():
    spec = importlib.util.spec_from_file_location(
        "generate_reference", DOCS / "generate_reference.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("page", [p for p in PAGES if BLOCK.search(p.read_text())], ids=str)
def test_the_python_snippets_of_each_page_run(page, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    namespace: dict = {"__name__": "__docs__"}
    for block in BLOCK.findall(page.read_text()):
        exec(compile(block, str(page), "exec"), namespace)


def test_the_metrics_reference_is_generated_from_the_code():
    generated = _generator().metrics_page()
    assert (DOCS / "reference" / "metrics.md").read_text() == generated, (
        "docs/reference/metrics.md is out of date: run python docs/generate_reference.py"
    )


def test_every_command_and_option_is_in_the_cli_reference():
    from mpcwalk.cli import build_parser

    page = (DOCS / "reference" / "cli.md").read_text()
    generator = _generator()

    def check(prefix: str, parser: argparse.ArgumentParser) -> None:
        for action in parser._actions:
            for option in action.option_strings:
                assert option in page, f"{prefix} {option} is missing from docs/reference/cli.md"
        for name, sub in generator._subparsers(parser):
            assert f"`{prefix} {name}`" in page, f"{prefix} {name}: run docs/generate_reference.py"
            check(f"{prefix} {name}", sub)

    check("mpcwalk", build_parser())


@pytest.mark.slow
def test_the_site_builds_strictly(tmp_path):
    mkdocs = shutil.which("mkdocs", path=str(Path(sys.executable).parent)) or "mkdocs"
    result = subprocess.run(
        [mkdocs, "build", "--strict", "--site-dir", str(tmp_path / "site")],
        cwd=ROOT,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr[-3000:]
    assert (tmp_path / "site" / "reference" / "metrics" / "index.html").exists()
    for notebook in (ROOT / "notebooks").glob("*.ipynb"):  # rendered, not executed
        assert (tmp_path / "site" / "notebooks" / notebook.stem / "index.html").exists()
    assert "WARNING" not in result.stderr


def test_the_notebooks_find_the_committed_results_from_any_folder(tmp_path):
    from mpcwalk.experiments.reporting import find_results

    found = find_results("solvers", start=tmp_path)
    assert found is not None and found == ROOT / "results" / "solvers"
    assert find_results("no-such-results", start=tmp_path) is None
