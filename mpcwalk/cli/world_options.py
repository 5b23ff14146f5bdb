"""The options of ``mpcwalk walk`` that describe the world the robot walks in: its
sensors, how the simulated robot differs from the controller's model, the ground and the
terrain (:func:`add_world_options`), and the specification fields they give
(:func:`world_fields`).

``--terrain FILE`` reads a terrain file (:mod:`mpcwalk.terrain.terrain_file`) before anything
runs: a file that is missing, not TOML or not a terrain is refused with the reason (exit 2).
A name without a folder or suffix that is no file names a shipped terrain
(:func:`shipped_terrains`: ``--terrain stairs_and_slope``).
"""

import argparse
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import ConfigurationError, TerrainError

S = argparse.SUPPRESS

#: Package whose folder ``examples/`` holds the shipped terrain files.
_TERRAIN_PACKAGE = "mpcwalk.terrain"


def _examples_dir() -> Path | None:
    """Folder of the shipped terrain files, or None when mpcwalk is not installed with it."""
    from mpcwalk.exceptions import PackageDataNotFound
    from mpcwalk.robot.package_data import package_data_dir

    try:
        folder = package_data_dir(_TERRAIN_PACKAGE) / "examples"
    except PackageDataNotFound:
        return None
    return folder if folder.is_dir() else None


def shipped_terrains() -> tuple[str, ...]:
    """Names of the terrain files shipped with mpcwalk (``--terrain NAME``)."""
    folder = _examples_dir()
    return tuple(sorted(p.stem for p in folder.glob("*.toml"))) if folder else ()


def read_terrain_option(text: str) -> Any:
    """The :class:`~mpcwalk.terrain.Terrain` of ``--terrain``: a file, else a shipped one.

    Raises:
        TerrainError: No such file or shipped terrain, or a file that is not a terrain (the
            message says why and where).
    """
    from mpcwalk.terrain import read_terrain

    path = Path(text)
    folder = _examples_dir()
    shipped = folder / f"{text}.toml" if folder is not None else None
    if not path.exists() and shipped is not None and shipped.is_file() and path.name == text:
        path = shipped
    try:
        return read_terrain(path)
    except TerrainError as error:
        if path.exists():
            raise
        names = ", ".join(shipped_terrains()) or "none installed"
        raise TerrainError(f"--terrain {text}: {error} The shipped terrains: {names}.") from None


def add_world_options(p: argparse.ArgumentParser) -> None:
    """The options of the world: sensors, the simulated robot, the ground, the terrain."""
    world = p.add_argument_group(
        "sensors and world",
        "The controller walks on the state estimated from the robot's sensors (IMU, encoders, "
        "foot force/torque sensors, with the noise of the robot's sensor model and one control "
        "period of latency); the simulated robot may differ from the controller's model.",
    )
    world.add_argument(
        "--noise-scale",
        type=float,
        default=S,
        metavar="X",
        help="factor on the noise and bias of the sensor model (0: exact sensors; default: 1)",
    )
    world.add_argument(
        "--latency",
        type=float,
        default=S,
        metavar="S",
        help="sensing-to-"
        "actuation latency [s], a multiple of --control-period (default: one "
        "control period)",
    )
    world.add_argument(
        "--ideal",
        action="store_true",
        default=S,
        help="exact sensors, no "
        "latency, the controller on the simulator's ground truth (with --state "
        "estimator: the estimator on exact sensors)",
    )
    world.add_argument(
        "--state",
        choices=("estimator", "oracle"),
        default=S,
        help="what the "
        "controller reads: the state estimated from the sensors, or the "
        "simulator's ground truth, for comparison (default: estimator; oracle "
        "with --ideal)",
    )
    world.add_argument(
        "--mass-scale",
        type=float,
        default=S,
        metavar="X",
        help="factor on the torso mass of the simulated robot, not of the controller's model "
        "(default: 1)",
    )
    world.add_argument(
        "--com-offset",
        default=S,
        metavar="DX,DY",
        help="shift of the torso's CoM of the simulated robot [m], forward and left (default: 0,0)",
    )
    world.add_argument(
        "--friction",
        type=float,
        default=S,
        metavar="MU",
        help="friction coefficient of the feet on the floor (default: the robot model's)",
    )
    world.add_argument(
        "--friction-cone",
        choices=("pyramidal", "elliptic"),
        default=S,
        help="the simulator's friction cone (default: MuJoCo's pyramid); with --impratio 10, "
        "elliptic keeps loaded soles from creeping down slopes",
    )
    world.add_argument(
        "--impratio",
        type=float,
        default=S,
        metavar="R",
        help="MuJoCo's ratio of frictional to normal constraint impedance, in [1, 100] "
        "(default: 1)",
    )
    world.add_argument(
        "--servo-strength",
        type=float,
        default=S,
        metavar="X",
        help="factor on the servos' gains and torque limits of the simulated robot (default: 1)",
    )
    world.add_argument(
        "--actuation",
        choices=("position", "torque"),
        default=S,
        help="how the joints are driven: the robot's position servos fed by the IK, or torque "
        "motors with its torque limits fed by the whole-body inverse dynamics (default: "
        "position)",
    )
    world.add_argument(
        "--ground-tilt",
        type=float,
        default=S,
        metavar="DEG",
        help="slope of the simulated ground [deg], up towards --ground-tilt-direction",
    )
    world.add_argument(
        "--ground-tilt-direction",
        type=float,
        default=S,
        metavar="DEG",
        help="azimuth of the uphill direction [deg] (0: the robot's forward, 90: its left)",
    )
    world.add_argument(
        "--ground-roughness",
        type=float,
        default=S,
        metavar="M",
        help="largest height of the ground's random bumps [m] (a height field; 0: flat)",
    )
    world.add_argument(
        "--seed",
        type=int,
        default=S,
        metavar="N",
        help="seed of the sensor noise and the bumps (default: 0)",
    )
    world.add_argument(
        "--terrain",
        default=S,
        metavar="FILE",
        help="terrain file (TOML: [[stairs]], [[slope]], [[platform]], [[stones]], [[rough]] "
        "laid along the robot's initial heading), or the name of a shipped one ("
        + ", ".join(shipped_terrains())
        + "); a terrain that does not fit the robot is refused (exit 2)",
    )


def world_fields(given: dict[str, Any]) -> dict[str, Any]:
    """The specification fields of the world options given that are not fields under their
    own name: ``com_offset`` (from ``DX,DY``) and ``terrain`` (read from its file).

    Raises:
        MpcwalkError: A bad CoM offset, or a terrain file that is not one.
    """
    fields: dict[str, Any] = {}
    if "com_offset" in given:
        fields["com_offset"] = _com_offset(given["com_offset"])
    if "terrain" in given:
        fields["terrain"] = read_terrain_option(given["terrain"])
    return fields


def _com_offset(text: Any) -> tuple[float, float]:
    try:
        dx, dy = (float(part) for part in str(text).split(","))
    except ValueError:
        raise ConfigurationError(
            f"--com-offset takes two numbers DX,DY in metres, got {str(text)!r}; "
            "e.g. --com-offset 0.01,0 shifts the torso's CoM 1 cm forward."
        ) from None
    return dx, dy


__all__ = ["add_world_options", "read_terrain_option", "shipped_terrains", "world_fields"]
