"""Outputs never lie: atomic writes, ``metrics.json`` last, an earlier run refused unless
``--overwrite``, SIGINT writes the partial walk, an internal error is one line and a saved
traceback (exit 4), MuJoCo's log stays under ``--out``."""

import json
import os
import signal
import subprocess
import sys
import time

import pytest

import mpcwalk.walking.outputs as outputs
from mpcwalk.cli import main
from mpcwalk.walking.outputs import write_atomic, write_json

ARGS = ["walk", "--robot", "bioloid-like", "--no-progress"]


def test_atomic_write_leaves_the_old_file_when_the_writer_fails(tmp_path):
    path = tmp_path / "metrics.json"
    write_json(path, {"run": 1})

    def broken(tmp):
        tmp.write_text('{"run": 2, "trunc')
        raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        write_atomic(path, broken)
    assert json.loads(path.read_text()) == {"run": 1}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["metrics.json"]  # no temporary file


@pytest.mark.parametrize(
    "umask, mode",
    [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)],
    ids=["umask-022", "umask-077", "umask-002"],
)
def test_files_written_in_place_get_the_umask_s_permissions(tmp_path, umask, mode):
    """A walk's files are created as ``open`` creates them (a results folder others read),
    not with the owner-only permissions of a private temporary file."""
    previous = os.umask(umask)
    try:
        write_json(tmp_path / "metrics.json", {"run": 1})
        write_atomic(tmp_path / "walk_log.npz", lambda tmp: tmp.write_bytes(b"log"))
    finally:
        os.umask(previous)
    for path in tmp_path.iterdir():
        assert path.stat().st_mode & 0o777 == mode, (path.name, oct(path.stat().st_mode))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["metrics.json", "walk_log.npz"]


def test_metrics_are_written_last(tmp_path, monkeypatch, capsys):
    order = []
    real = outputs.write_atomic

    def spy(path, write):
        order.append(path.name)
        return real(path, write)

    monkeypatch.setattr(outputs, "write_atomic", spy)  # write_json writes through it too
    assert main(ARGS + ["--steps", "1", "--out", str(tmp_path / "w")]) == 0
    # the walk's specification first, the metrics last
    assert order[-1] == "metrics.json" and order[:2] == ["spec.toml", "walk_log.npz"]
    assert len(order) == len(set(order)) >= 4


def test_an_earlier_run_is_refused_unless_overwrite(tmp_path, capsys):
    out = tmp_path / "w"
    assert main(ARGS + ["--steps", "1", "--out", str(out)]) == 0
    first = (out / "metrics.json").read_text()
    assert main(ARGS + ["--steps", "2", "--out", str(out)]) == 2
    assert "holds an earlier run" in capsys.readouterr().err
    assert (out / "metrics.json").read_text() == first
    assert main(ARGS + ["--steps", "2", "--out", str(out), "--overwrite"]) == 0
    assert json.loads((out / "metrics.json").read_text())["steps_planned"] == 3


def test_an_internal_error_is_one_line_and_a_saved_traceback(tmp_path, monkeypatch, capsys):
    def bug(*args, **kwargs):
        raise ZeroDivisionError("a bug")

    monkeypatch.setattr("mpcwalk.walking.runner.run_walk", bug)
    out = tmp_path / "w"
    assert main(ARGS + ["--steps", "1", "--out", str(out)]) == 4
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "internal error: ZeroDivisionError: a bug" in err
    assert "Traceback" not in err and str(out / "traceback.txt") in err
    assert "ZeroDivisionError" in (out / "traceback.txt").read_text()
    assert not (out / "metrics.json").exists()
    assert main(["--debug"] + ARGS + ["--steps", "1", "--out", str(tmp_path / "d")]) == 4
    assert "Traceback" in capsys.readouterr().err


def test_mujoco_warnings_go_under_out(tmp_path, monkeypatch):
    import mujoco
    import numpy as np

    from mpcwalk.walking.outputs import MUJOCO_LOG_FILE, log_mujoco_messages

    monkeypatch.chdir(tmp_path)
    out = tmp_path / "w"
    out.mkdir()
    previous = mujoco.get_mju_user_warning()
    xml = '<mujoco><worldbody><body><freejoint/><geom size="0.1"/></body></worldbody></mujoco>'
    model = mujoco.MjModel.from_xml_string(xml)

    def diverge():
        data = mujoco.MjData(model)
        data.qpos[:] = np.nan  # a diverged simulation: MuJoCo warns
        mujoco.mj_step(model, data)

    with log_mujoco_messages(out):
        diverge()
        (out / MUJOCO_LOG_FILE).unlink()
        out.rmdir()  # the log cannot be written: the warning goes to the standard error
        diverge()
    assert mujoco.get_mju_user_warning() is previous  # restored after the walk
    out.mkdir()
    with log_mujoco_messages(out):
        diverge()
    assert "The simulation is unstable" in (out / MUJOCO_LOG_FILE).read_text()
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()


@pytest.mark.slow
def test_sigint_writes_the_partial_walk(tmp_path):
    out = tmp_path / "w"
    command = [sys.executable, "-m", "mpcwalk", *ARGS, "--steps", "200", "--out", str(out)]
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    process = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        # a runner started in the background ignores SIGINT, and its children inherit that
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    time.sleep(10.0)  # imports and a few seconds of the 100 s walk (about 20 s of wall time)
    process.send_signal(signal.SIGINT)
    stdout, stderr = process.communicate(timeout=120)
    assert process.returncode == 130, stderr
    assert "Traceback" not in stderr and "INTERRUPTED" in stdout
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["interrupted"] is True and metrics["outcome"] == "interrupted"
    assert 0.0 < metrics["time_simulated_s"] < metrics["time_planned_s"]
    assert (out / "walk_log.npz").exists()
