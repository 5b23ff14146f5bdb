"""Footstep path files of paper A (``.mdat``).

One line per waypoint (a stance of both feet) in the global map frame,
14 numbers separated by spaces or commas::

    xlf ylf zlf qwlf qxlf qylf qzlf xrf yrf zrf qwrf qxrf qyrf qzrf

the left foot's sole-centre position [m] and orientation quaternion
``(w, x, y, z)``, then the right foot's. Blank lines and ``#`` comments are
allowed. A quaternion is normalised (its norm must be 1 to
:data:`QUATERNION_NORM_TOLERANCE`) and read as the footstep's yaw, roll and pitch
(``Rz(yaw) Ry(pitch) Rx(roll)``, see :mod:`~mpcwalk.footsteps.rotations`): a foot may
stand on a tilted tread, up to 45 deg of roll and of pitch; the height ``z`` is the
footstep's. A flat quaternion (``x = y = 0``) gives a flat footstep, exactly as the
yaw alone. :func:`write_mdat` writes all 14 numbers back (exact round trip).

The steps and the plan that walk a path are in :mod:`~mpcwalk.footsteps.path_plan`
(re-exported here).
"""

import math
import os
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from mpcwalk.exceptions import ConfigurationError, FootstepFileError
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side
from mpcwalk.footsteps.path_plan import PathTarget, PathWaypoint, path_targets, plan_from_path
from mpcwalk.footsteps.rotations import MAX_FOOTSTEP_TILT, quaternion_rpy

__all__ = [
    "MAX_FOOT_TILT",
    "MAX_MDAT_BYTES",
    "MDAT_FIELDS",
    "QUATERNION_NORM_TOLERANCE",
    "PathTarget",
    "PathWaypoint",
    "parse_mdat",
    "path_targets",
    "plan_from_path",
    "quaternion_to_yaw",
    "read_mdat",
    "write_mdat",
    "yaw_to_quaternion",
]

#: Field order of one line.
MDAT_FIELDS = (
    "xlf",
    "ylf",
    "zlf",
    "qwlf",
    "qxlf",
    "qylf",
    "qzlf",
    "xrf",
    "yrf",
    "zrf",
    "qwrf",
    "qxrf",
    "qyrf",
    "qzrf",
)
#: Allowed deviation of a quaternion's norm from 1.
QUATERNION_NORM_TOLERANCE = 1e-3
#: Largest roll and largest pitch of a foot, in [rad] (45 deg, as any footstep).
MAX_FOOT_TILT = MAX_FOOTSTEP_TILT


def quaternion_to_yaw(w: float, x: float, y: float, z: float) -> float:
    """Heading about the vertical of a (normalised) quaternion, in [rad]."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def yaw_to_quaternion(yaw: float):
    """Quaternion ``(w, x, y, z)`` of a pure yaw rotation."""
    return (math.cos(0.5 * yaw), 0.0, 0.0, math.sin(0.5 * yaw))


def _foot(values, offset: int, side: Side, source: str, line: int) -> Footstep:
    q = np.array(values[offset + 3 : offset + 7])
    names = MDAT_FIELDS[offset + 3 : offset + 7]
    norm = float(np.linalg.norm(q))
    if abs(norm - 1.0) > QUATERNION_NORM_TOLERANCE:
        raise FootstepFileError(
            f"the {side.value} foot quaternion ({', '.join(names)}) = ({', '.join(f'{v:g}' for v in q)}) "
            f"has norm {norm:.6g}, but a unit quaternion is expected (tolerance "
            f"{QUATERNION_NORM_TOLERANCE:g}); normalise it.",
            path=source,
            line=line,
            field=names[0],
        )
    roll, pitch, yaw = quaternion_rpy(*(q / norm))
    for name, angle, field in (("roll", roll, names[1]), ("pitch", pitch, names[2])):
        if abs(angle) > MAX_FOOT_TILT:
            raise FootstepFileError(
                f"the {side.value} foot has a {name} of {math.degrees(angle):.2f} deg, beyond the "
                f"+-{math.degrees(MAX_FOOT_TILT):g} deg a foothold may have; check the quaternion "
                "(w, x, y, z order, scalar first) or step on a less steep tread.",
                path=source,
                line=line,
                field=field,
            )
    return Footstep(side, values[offset : offset + 3], yaw, roll, pitch)


def parse_mdat(text: str, *, source: str = "<string>") -> list[PathWaypoint]:
    """Waypoints of a path given as text.

    Args:
        text: File content.
        source: Name used in error messages.

    Raises:
        FootstepFileError: Naming the file, line and field of the problem.
    """
    waypoints = []
    for number, raw in enumerate(text.splitlines(), start=1):
        content = raw.split("#", 1)[0].strip()
        if not content:
            continue
        tokens = [t for t in re.split(r"[\s,]+", content) if t]
        if len(tokens) != len(MDAT_FIELDS):
            missing = MDAT_FIELDS[len(tokens)] if len(tokens) < len(MDAT_FIELDS) else None
            raise FootstepFileError(
                f"expected {len(MDAT_FIELDS)} numbers ({' '.join(MDAT_FIELDS)}), got {len(tokens)}.",
                path=source,
                line=number,
                field=missing,
            )
        values = []
        for name, token in zip(MDAT_FIELDS, tokens):
            try:
                value = float(token)
            except ValueError:
                raise FootstepFileError(
                    f"'{token}' is not a number.", path=source, line=number, field=name
                ) from None
            if not math.isfinite(value):
                raise FootstepFileError(
                    f"'{token}' is not a finite number.", path=source, line=number, field=name
                )
            values.append(value)
        waypoints.append(
            PathWaypoint(
                _foot(values, 0, Side.LEFT, source, number),
                _foot(values, 7, Side.RIGHT, source, number),
                number,
            )
        )
    if not waypoints:
        raise FootstepFileError(
            "no waypoint found; a path file needs at least one line of 14 numbers "
            f"({' '.join(MDAT_FIELDS)}).",
            path=source,
        )
    return waypoints


#: Largest path file read [bytes] (1 MB: several thousand steps).
MAX_MDAT_BYTES = 1_000_000


def read_mdat(path_or_text: str | os.PathLike) -> list[PathWaypoint]:
    """Waypoints of a path file, or of its text.

    A ``Path``, or a one-line string naming an existing file or ending in
    ``.mdat``, is read as a file; any other string is parsed as content.
    """
    if not isinstance(path_or_text, (str, os.PathLike)):
        raise ConfigurationError(
            f"read_mdat takes a file path or the file's text, got {type(path_or_text).__name__}."
        )
    is_file = isinstance(path_or_text, os.PathLike) or (
        "\n" not in path_or_text
        and (os.path.isfile(path_or_text) or path_or_text.strip().endswith(".mdat"))
    )
    if not is_file:
        return parse_mdat(str(path_or_text))
    path = Path(path_or_text)
    try:
        if path.exists() and not path.is_file():
            raise FootstepFileError(
                "not a regular file (a path file is a text file of 14 numbers per line).",
                path=str(path),
            )
        size = path.stat().st_size
        if size > MAX_MDAT_BYTES:
            raise FootstepFileError(
                f"{size} bytes, beyond the {MAX_MDAT_BYTES} bytes a path file may have "
                f"(about {MAX_MDAT_BYTES // 150} steps); split the path.",
                path=str(path),
            )
        data = path.read_bytes()
    except OSError as error:
        raise FootstepFileError(
            f"cannot read the path file: {error.strerror or error}.", path=str(path_or_text)
        ) from None
    try:
        text = data.decode("utf-8-sig")  # a byte-order mark is accepted
    except UnicodeDecodeError as error:
        raise FootstepFileError(
            f"not UTF-8 text (byte {error.start} is 0x{data[error.start]:02x}); a path file is "
            "a text file of 14 numbers per line.",
            path=str(path),
        ) from None
    if "\x00" in text:
        raise FootstepFileError(
            "binary content (a NUL byte); a path file is a text file.", path=str(path)
        )
    return parse_mdat(text, source=str(path_or_text))


def _stances(source) -> list[PathWaypoint]:
    """Waypoints of a plan (its stances), of stances (dicts side -> Footstep) or waypoints."""
    if isinstance(source, FootstepPlan):
        source = source.stances()
    if isinstance(source, (str, bytes)) or not isinstance(source, Sequence):
        raise ConfigurationError(
            f"write_mdat takes a FootstepPlan, stances (dicts side -> Footstep) or "
            f"PathWaypoints, got {type(source).__name__}."
        )
    waypoints = []
    for item in source:
        if isinstance(item, dict):
            item = PathWaypoint(item[Side.LEFT], item[Side.RIGHT])
        if not isinstance(item, PathWaypoint):
            raise ConfigurationError(
                f"write_mdat writes stances (dicts side -> Footstep) or PathWaypoints, got "
                f"a {type(item).__name__}; pass plan.stances() for a plan."
            )
        waypoints.append(item)
    return waypoints


def write_mdat(
    path: str | os.PathLike,
    waypoints: "Sequence[PathWaypoint] | Sequence[dict[Side, Footstep]] | FootstepPlan",
    *,
    header: str = "",
) -> None:
    """Write stances as a path file, all 14 numbers of each (exact round trip through
    :func:`read_mdat`: positions to the last bit, angles to 1e-15 rad).

    Args:
        path: Output file.
        waypoints: Stances to write, one per line: PathWaypoints, dicts side -> Footstep
            (``plan.stances()``), or a FootstepPlan (its stances: the initial one and one
            after each step, which :func:`~mpcwalk.footsteps.path_plan.plan_from_path`
            walks again).
        header: Text written first as ``#`` comment lines.
    """
    lines = [f"# {row}".rstrip() for row in header.splitlines()]
    lines.append("# " + " ".join(MDAT_FIELDS))
    for waypoint in _stances(waypoints):
        values: list[float] = []
        for foot in (waypoint.left, waypoint.right):
            values += [*foot.position, *foot.quaternion]
        lines.append(" ".join(repr(float(v)) for v in values))
    Path(path).write_text("\n".join(lines) + "\n")
