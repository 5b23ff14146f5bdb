"""Open a walk's output folder (``metrics.json``, ``walk_log.npz`` and, for its terrain,
``spec.toml`` of ``mpcwalk walk``) in the browser viewer."""

import json
from pathlib import Path

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import FootGeometry, StepTiming
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.robot import load_robot
from mpcwalk.viewer.walk_viewer import WalkViewer
from mpcwalk.walking.footstep_planning import plan_walk_footsteps
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.specification import SPEC_FILE, read_spec


def open_walk(folder: str | Path, *, port: int = 8080, host: str = "127.0.0.1") -> WalkViewer:
    """The viewer of the walk written in ``folder``: its robot, its log, and its plan made
    again from the configuration in ``metrics.json`` (the footsteps as planned, before any
    adaptation; the landed soles are the log's).

    Raises:
        ConfigurationError: Not the output folder of a walk.
    """
    folder = Path(folder)
    metrics_file, log_file = folder / "metrics.json", folder / "walk_log.npz"
    for path in (metrics_file, log_file):
        if not path.is_file():
            raise ConfigurationError(
                f"{folder} is not the output folder of a walk: no {path.name} (run mpcwalk "
                "walk ... --out DIR, then mpcwalk replay DIR)."
            )
    try:
        config = json.loads(metrics_file.read_text())["config"]
    except (ValueError, KeyError) as error:
        raise ConfigurationError(f"{metrics_file} is not a walk's metrics: {error}.") from None
    robot = load_robot(config["robot"])
    timing = StepTiming(
        step_duration=config["step_duration_s"],
        double_support_ratio=config["double_support_ratio"],
    )
    command = config.get("command")
    plan = plan_walk_footsteps(
        robot,
        command=None if command is None else (command["vx"], command["vy"], command["vyaw"]),
        path=config.get("path"),
        nb_steps=config.get("nb_steps")
        or max(1, round((config.get("duration_s") or 1.0) / timing.step_duration)),
        timing=timing,
    )
    schedule = ContactSchedule(plan, FootGeometry(*robot.sole_size))
    pushes = [(p[0], p[1], p[2:5]) for p in config.get("pushes", [])]
    spec_file = folder / SPEC_FILE  # the walk, for its terrain
    terrain = read_spec(spec_file).world.terrain if spec_file.is_file() else None
    log = WalkLog.load(log_file)
    return WalkViewer(robot, log, schedule, pushes=pushes, port=port, host=host, terrain=terrain)
