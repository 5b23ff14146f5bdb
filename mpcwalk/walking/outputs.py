"""Outputs that never lie: the output folder checked before anything runs, files written
atomically (a temporary name, then a rename), ``metrics.json`` last, MuJoCo's own log kept
under the output folder.
"""

import json
import os
import secrets
import sys
import tempfile
import traceback
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import ConfigurationError

#: Written last by a finished (or cleanly stopped or interrupted) run.
METRICS_FILE = "metrics.json"
#: Where an internal error's traceback goes.
TRACEBACK_FILE = "traceback.txt"
#: MuJoCo's warnings and errors.
MUJOCO_LOG_FILE = "mujoco_log.txt"


def _nearest_existing(path: Path) -> Path:
    current = path
    while not current.exists():
        if current.parent == current:
            break
        current = current.parent
    return current


def check_out_dir(out: Any, *, overwrite: bool = False, option: str = "--out") -> Path:
    """The output folder as a Path, checked without creating anything.

    Raises:
        ConfigurationError: Empty, an existing file (or a path through one), a folder that
            cannot be written, or a folder holding an earlier run's ``metrics.json`` (unless
            ``overwrite``).
    """
    text = str(out) if out is not None else ""
    if not text.strip():
        raise ConfigurationError(
            f"{option} must name an output folder, got {text!r}; e.g. {option} out/walk."
        )
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise ConfigurationError(
            f"{option} {path} exists and is not a folder; give a folder (it is created)."
        )
    existing = _nearest_existing(path)
    if not existing.is_dir():
        raise ConfigurationError(
            f"{option} {path} cannot be created: {existing} is a file, not a folder."
        )
    if not os.access(existing, os.W_OK | os.X_OK):
        raise ConfigurationError(
            f"{option} {path} cannot be written ({existing} is not writable); choose a "
            "folder you can write to."
        )
    if not path.exists():  # can a folder be made there? (made and removed at once)
        try:
            os.rmdir(tempfile.mkdtemp(dir=existing, prefix=".mpcwalk-check-"))
        except OSError as error:
            raise ConfigurationError(
                f"{option} {path} cannot be created in {existing}: {error.strerror or error}."
            ) from None
    if (path / METRICS_FILE).exists() and not overwrite:
        raise ConfigurationError(
            f"{option} {path} holds an earlier run ({METRICS_FILE}); give another folder, "
            "or --overwrite to replace it."
        )
    return path


def check_video_path(video: Any) -> Path:
    """The video file's path, checked before the walk (its folder exists and is writable)."""
    path = Path(str(video))
    if path.exists() and path.is_dir():
        raise ConfigurationError(f"video={path} is a folder; give an .mp4 file's path.")
    folder = path.parent
    if not folder.is_dir() or not os.access(folder, os.W_OK | os.X_OK):
        raise ConfigurationError(
            f"video={path} cannot be written: {folder} is not a writable folder."
        )
    return path


def write_atomic(path: Path, write: Callable[[Path], Any]) -> Path:
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it to ``path``:
    a reader never sees a half-written file. ``tmp`` keeps ``path``'s suffix, and is created
    as ``open`` creates a file (its permissions the process's umask's, not the owner-only
    ones of a private temporary file)."""
    path = Path(path)
    tmp = _new_file(path.parent, f".{path.stem}.", f".tmp{path.suffix}")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


def _new_file(folder: Path, prefix: str, suffix: str) -> Path:
    """A new empty file ``folder/prefix<random>suffix``, created exclusively (never one that
    exists) with the permissions the umask leaves of ``rw-rw-rw-``."""
    while True:
        tmp = folder / f"{prefix}{secrets.token_hex(6)}{suffix}"
        try:
            os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
        except FileExistsError:
            continue
        return tmp


def write_json(path: Path, data: Any) -> Path:
    """``data`` as indented JSON at ``path``, atomically."""
    return write_atomic(path, lambda tmp: tmp.write_text(json.dumps(data, indent=2) + "\n"))


def save_traceback(out: Path | None, error: BaseException) -> Path | None:
    """Write ``error``'s traceback under ``out`` (None when it cannot be written there)."""
    if out is None:
        return None
    try:
        out.mkdir(parents=True, exist_ok=True)
        text = "".join(traceback.format_exception(type(error), error, error.__traceback__))
        return write_atomic(out / TRACEBACK_FILE, lambda tmp: tmp.write_text(text))
    except OSError:
        return None


@contextmanager
def log_mujoco_messages(out: Path) -> Iterator[Path]:
    """Within the block, MuJoCo's warnings go to ``out/mujoco_log.txt`` instead of
    ``MUJOCO_LOG.TXT`` in the working directory (to the standard error when that file cannot
    be written); the previous handler is restored on leaving. Yields the log's path."""
    import mujoco

    log = out / MUJOCO_LOG_FILE

    def warn(message: str) -> None:
        try:
            with open(log, "a", encoding="utf-8") as stream:
                stream.write(f"WARNING: {message}\n")
        except OSError:  # an exception here would abort the process inside MuJoCo
            sys.stderr.write(f"MuJoCo warning: {message}\n")

    previous = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(warn)
    try:
        yield log
    finally:
        mujoco.set_mju_user_warning(previous)


def write_walk_outputs(result: Any, out: Path, *, log_format: str = "npz") -> list[Path]:
    """A walk's results in ``out``, each atomically: ``spec.toml`` (the resolved
    specification), on a terrain ``terrain.toml`` (its terrain file, ``--terrain``), the
    per-tick log, the figures (on a terrain also ``side_view.png``; the video is written
    during the walk), then ``metrics.json`` last. Returns the paths written."""
    from functools import partial

    from mpcwalk.terrain import terrain_to_toml
    from mpcwalk.walking.figures import plot_estimator, plot_walk_over_time, plot_walk_top_view
    from mpcwalk.walking.side_view import plot_walk_side_view
    from mpcwalk.walking.specification import SPEC_FILE, spec_to_toml
    from mpcwalk.walking.specification.records import TERRAIN_FILE

    out.mkdir(parents=True, exist_ok=True)
    (out / METRICS_FILE).unlink(missing_ok=True)  # --overwrite: no stale metrics meanwhile
    spec_text = spec_to_toml(result.spec)
    written = [write_atomic(out / SPEC_FILE, lambda tmp: tmp.write_text(spec_text, "utf-8"))]
    terrain = result.spec.world.terrain
    if terrain is not None:
        text = terrain_to_toml(terrain)
        written.append(write_atomic(out / TERRAIN_FILE, lambda tmp: tmp.write_text(text)))
    log_path = out / f"walk_log.{log_format}"
    written.append(write_atomic(log_path, lambda tmp: result.log.save(tmp)))
    plan = result.spec.plan
    what = str(plan.path) if plan.path is not None else "path"
    if plan.command is not None:
        vx, vy, vyaw = plan.command
        what = f"v = ({vx:g} m/s, {vy:g} m/s, {vyaw:g} rad/s)"
    title = f"{result.robot}, {result.generator}: {what}, T = {result.config.step_duration_s:g} s"
    if len(result.log):
        import matplotlib.pyplot as plt

        plots = [("top_view.png", plot_walk_top_view), ("com_cop.png", plot_walk_over_time)]
        if result.config.state_source == "estimator":
            plots.append(("estimator.png", plot_estimator))
        if terrain is not None:
            plots.append(("side_view.png", partial(plot_walk_side_view, terrain=terrain)))
        for name, plot in plots:
            figure = plot(result.schedule, result.log, title=title)
            written.append(write_atomic(out / name, partial(figure.savefig, dpi=120)))
            plt.close(figure)
    if result.spec.run.video is not None:
        written.append(Path(result.spec.run.video))
    written.append(write_json(out / METRICS_FILE, result.to_dict()))
    return written
