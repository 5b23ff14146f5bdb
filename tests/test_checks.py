"""The house rules, enforced: import contracts, what the low rooms may load, the size of the
package root and of its modules, and a packaging list that misses no package."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "mpcwalk"
MAX_ROOT_MODULES = 6
MAX_MODULE_LINES = 400

#: Modules whose import must load neither MuJoCo nor Pinocchio (a generator runs without a
#: robot), and modules whose import must not load MuJoCo (the IK and the controller run on
#: Pinocchio alone).
WITHOUT_MUJOCO_AND_PINOCCHIO = (
    "mpcwalk.generators.mpc",
    "mpcwalk.models",
    "mpcwalk.footsteps",
    "mpcwalk.gait",
    "mpcwalk.qp",
)
WITHOUT_MUJOCO = ("mpcwalk.ik", "mpcwalk.control")


def modules_loaded_by(module: str) -> set[str]:
    """Top-level names of the modules that ``import module`` loads, in a fresh interpreter."""
    code = f"import sys, {module}; print(' '.join(sorted(sys.modules)))"
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=300
    )
    assert result.returncode == 0, result.stderr
    return {name.split(".")[0] for name in result.stdout.split()}


def test_the_import_contracts_hold():
    """The layers and forbidden contracts of ``[tool.importlinter]`` (also run by the test
    command as ``lint-imports``)."""
    code = (
        "import sys; from importlinter.cli import lint_imports; "
        f"sys.exit(lint_imports(config_filename={str(ROOT / 'pyproject.toml')!r}, "
        "no_cache=True, no_logo=True))"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=600
    )
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.parametrize("module", WITHOUT_MUJOCO_AND_PINOCCHIO)
def test_generators_and_the_rooms_below_load_neither_mujoco_nor_pinocchio(module):
    loaded = modules_loaded_by(module)
    assert "mujoco" not in loaded
    assert "pinocchio" not in loaded


@pytest.mark.parametrize("module", WITHOUT_MUJOCO)
def test_the_ik_and_the_controller_load_no_mujoco(module):
    assert "mujoco" not in modules_loaded_by(module)


def test_the_package_root_holds_at_most_six_modules():
    modules = sorted(path.name for path in PACKAGE.glob("*.py"))
    assert len(modules) <= MAX_ROOT_MODULES, modules


def test_no_module_is_over_400_lines():
    long = {
        path.relative_to(ROOT).as_posix(): count
        for path in PACKAGE.rglob("*.py")
        if (count := len(path.read_text(encoding="utf-8").splitlines())) > MAX_MODULE_LINES
    }
    assert not long, long


def test_the_packaging_lists_every_package_and_maps_the_data_folders():
    """``[tool.setuptools] packages`` is written by hand (the data folders are mapped into the
    package): a package missing there would be missing from the wheel."""
    setuptools = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    mapped = setuptools["package-dir"]
    on_disk = {
        ".".join(path.parent.relative_to(ROOT).parts)
        for path in PACKAGE.rglob("__init__.py")
        if "__pycache__" not in path.parts
    }
    assert set(setuptools["packages"]) == on_disk | set(mapped)
    for package, folder in mapped.items():
        assert (ROOT / folder / "__init__.py").is_file(), (package, folder)


def test_ci_runs_exactly_the_readme_test_command():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    command = next(line for line in ci.splitlines() if line.startswith("python3 -m venv"))
    assert f"\n{command}\n" in readme
    for check in ("ruff check .", "ruff format --check .", "mypy", "lint-imports", "pytest"):
        assert check in command


def test_notebooks_are_committed_without_outputs():
    """The suite executes the notebooks; git keeps their sources only."""
    for path in sorted((ROOT / "notebooks").glob("*.ipynb")):
        cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
        for cell in cells:
            if cell["cell_type"] == "code":
                assert cell["outputs"] == [] and cell["execution_count"] is None, path.name
