"""Every script of examples/ runs as a user would run it, from another folder."""

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
#: script -> (arguments, a line its output must hold)
EXPECTED = {
    "plan_on_the_lipm.py": ((), "smallest ZMP margin"),
    "walk_a_robot.py": ((), "fell: False"),
    "your_own_robot.py": (("robot",), "my-biped"),
    "your_own_generator.py": ((), "smooth-mpc in MuJoCo: fell False"),
    "compare_qp_backends.py": ((), "quadprog     fell False"),
    "sweep_on_ray.py": (("sweep",), "12 walks run, 0 already there, 0 errors"),
}


def test_every_example_is_tested():
    assert sorted(p.name for p in EXAMPLES.glob("*.py")) == sorted(EXPECTED)


@pytest.mark.slow
@pytest.mark.parametrize("script", sorted(EXPECTED))
def test_the_example_runs(script, tmp_path):
    arguments, expected = EXPECTED[script]
    result = subprocess.run(
        [sys.executable, str(EXAMPLES / script), *(str(tmp_path / a) for a in arguments)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stderr[-3000:]
    assert expected in result.stdout, result.stdout
