"""The wheel works: built offline, installed without dependencies into a throwaway folder, it
lists and walks the robots from another working directory, with nothing read beside the
source tree."""

import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from mpcwalk.robot.loading import robot_names

ROOT = Path(__file__).resolve().parents[1]
#: What the build reads: the package, its data folders and the metadata files.
SOURCES = ("pyproject.toml", "README.md", "LICENSE", "mpcwalk", "robots")
#: Data files the library reads at run time: source folder -> folder in the installed package.
DATA = {
    "robots": ("mpcwalk/robot/data", ("*.xml", "presets/*.toml")),
    "mpcwalk/experiments": (
        "mpcwalk/experiments",
        ("*/config.toml", "paper_a/paths/*.mdat", "paper_a/paths/*.toml"),
    ),
    "mpcwalk/terrain": ("mpcwalk/terrain", ("examples/*.toml",)),
}

pytestmark = pytest.mark.slow


def run(command, *, cwd, env=None, timeout=600):
    """Run ``command``; fail with its output unless it exits with 0."""
    result = subprocess.run(
        [str(c) for c in command], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout
    )
    assert result.returncode == 0, (
        f"{command} exited with {result.returncode}\n{result.stdout}\n{result.stderr}"
    )
    return result


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel, built offline from a copy of the sources (the work tree stays clean)."""
    base = tmp_path_factory.mktemp("wheel")
    source = base / "source"
    source.mkdir()
    ignore = shutil.ignore_patterns("__pycache__", "*.egg-info", "build", "dist")
    for name in SOURCES:
        path = ROOT / name
        if path.is_dir():
            shutil.copytree(path, source / name, ignore=ignore)
        else:
            shutil.copy2(path, source / name)
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check"]
    run(
        [
            *pip,
            "wheel",
            "--no-deps",
            "--no-build-isolation",
            "--no-index",
            "-w",
            base / "dist",
            source,
        ],
        cwd=base,
    )
    (built,) = (base / "dist").glob("mpcwalk-*.whl")
    return built


@pytest.fixture(scope="module")
def installed(wheel, tmp_path_factory):
    """``(target, env, workdir)``: the wheel installed with ``--target``, an environment that
    imports mpcwalk from there (the test environment's packages for the dependencies), and an
    empty working directory away from the source tree."""
    base = tmp_path_factory.mktemp("installed")
    target, workdir = base / "target", base / "work"
    workdir.mkdir()
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check"]
    run([*pip, "install", "--no-deps", "--no-index", "--target", target, wheel], cwd=base)
    env = {key: value for key, value in os.environ.items() if not key.startswith("PYTHON")}
    env["PYTHONPATH"] = str(target)
    env["MPLBACKEND"] = "Agg"
    return target, env, workdir


def test_the_wheel_ships_every_module_and_every_data_file(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    modules = {
        path.relative_to(ROOT).as_posix()
        for path in (ROOT / "mpcwalk").rglob("*.py")
        if "__pycache__" not in path.parts
    }
    assert modules <= names, sorted(modules - names)
    assert "mpcwalk/py.typed" in names
    for folder, (package, patterns) in DATA.items():
        files = {
            f"{package}/{path.relative_to(ROOT / folder).as_posix()}"
            for pattern in patterns
            for path in (ROOT / folder).glob(pattern)
        }
        assert files and files <= names, sorted(files - names)
    # every experiment of the registry ships its configuration
    from mpcwalk.experiments.catalog import EXPERIMENTS

    for name in EXPERIMENTS:
        package = EXPERIMENTS.load(name).package  # e.g. mpcwalk.experiments.robustness
        assert package.replace(".", "/") + "/config.toml" in names, name
    assert any(name.endswith(".dist-info/licenses/LICENSE") for name in names)


def test_the_installed_package_and_its_data_come_from_the_target(installed):
    target, env, workdir = installed
    code = (
        "import json, mpcwalk\n"
        "from mpcwalk.robot.loading import ROBOTS_DIR\n"
        "from mpcwalk.experiments.paper_m.config import DEFAULT_CONFIG\n"
        "from mpcwalk.experiments.paper_a.config import PATHS_DIR as EXPERIMENT_DIR\n"
        "print(json.dumps([mpcwalk.__file__, str(ROBOTS_DIR), str(DEFAULT_CONFIG),"
        " str(EXPERIMENT_DIR), DEFAULT_CONFIG.is_file(),"
        " sorted(p.name for p in EXPERIMENT_DIR.glob('*.mdat') or ()) +"
        " sorted(p.name for p in EXPERIMENT_DIR.glob('*.toml'))]))\n"
    )
    result = run([sys.executable, "-c", code], cwd=workdir, env=env)
    package, robots, config, paths, config_exists, mdat = json.loads(result.stdout)
    for path in (package, robots, config, paths):
        assert Path(path).is_relative_to(target), path
    assert config_exists and mdat == ["ramp.mdat", "straight.mdat", "turning.mdat", "ramp.toml"]


def test_mpcwalk_robots_lists_every_robot(installed):
    target, env, workdir = installed
    result = run([target / "bin" / "mpcwalk", "robots"], cwd=workdir, env=env)
    listed = [line.split()[0] for line in result.stdout.splitlines() if line.strip()]
    assert sorted(listed) == sorted(robot_names())
    assert {"bioloid-like", "atlas-like"} <= set(listed)


@pytest.mark.parametrize("robot", ["bioloid-like", "atlas-like"])
def test_a_two_second_walk_runs_from_the_wheel(installed, robot):
    _target, env, workdir = installed
    out = workdir / robot
    command = [sys.executable, "-m", "mpcwalk", "walk", "--robot", robot, "--duration", 2]
    run([*command, "--out", out], cwd=workdir, env=env)
    metrics = json.loads((out / "metrics.json").read_text())
    assert isinstance(metrics, dict) and metrics  # exit 0: the robot did not fall
