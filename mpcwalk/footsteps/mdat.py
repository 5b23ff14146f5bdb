"""Footstep path files of paper A (``.mdat``) and plans built from them.

One line per waypoint (a stance of both feet) in the global map frame,
14 numbers separated by spaces or commas::

    xlf ylf zlf qwlf qxlf qylf qzlf xrf yrf zrf qwrf qxrf qyrf qzrf

the left foot's sole-centre position [m] and orientation quaternion
``(w, x, y, z)``, then the right foot's. Blank lines and ``#`` comments are
allowed. Feet are flat: a quaternion may only turn about the vertical.
"""

import math
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import numpy as np

from mpcwalk.exceptions import ConfigurationError, FootstepFileError
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, StepTiming, wrap_angle
from mpcwalk.footsteps.path_follower import PathFollower
from mpcwalk.footsteps.reachability import (
    ATLAS_REACHABILITY,
    CLAMP_TOLERANCE,
    ReachabilityRectangle,
    opening_side,
)

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
#: Largest roll/pitch tilt of a foot, in [rad] (5 deg).
MAX_FOOT_TILT = math.radians(5.0)


@dataclass(frozen=True)
class PathWaypoint:
    """Both feet of one line of a path file.

    Attributes:
        left: Left foot pose, world frame.
        right: Right foot pose, world frame.
        line: One-based line number in its file, if read from one.
    """

    left: Footstep
    right: Footstep
    line: int | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        if self.left.side is not Side.LEFT or self.right.side is not Side.RIGHT:
            raise ConfigurationError("PathWaypoint needs a left Footstep then a right Footstep.")

    def foot(self, side) -> Footstep:
        """Pose of one foot."""
        return self.left if Side.parse(side) is Side.LEFT else self.right


class PathTarget(NamedTuple):
    """One single-foot step of a path, before any clamping.

    Attributes:
        footstep: Global landing.
        waypoint_index: Index of the waypoint it reaches.
        label: Where it comes from, for messages (``"waypoint 3 (line 5)"``).
    """

    footstep: Footstep
    waypoint_index: int
    label: str


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
    w, x, y, z = q / norm
    tilt = math.acos(min(1.0, max(-1.0, 1.0 - 2.0 * (x * x + y * y))))
    if tilt > MAX_FOOT_TILT:
        raise FootstepFileError(
            f"the {side.value} foot is tilted by {math.degrees(tilt):.2f} deg (roll/pitch), but feet "
            f"must be flat (tilt <= {math.degrees(MAX_FOOT_TILT):g} deg); keep only the yaw part "
            "(x = y = 0).",
            path=source,
            line=line,
            field=names[1] if abs(x) >= abs(y) else names[2],
        )
    return Footstep(side, values[offset : offset + 3], quaternion_to_yaw(w, x, y, z))


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


def write_mdat(
    path: str | os.PathLike, waypoints: Sequence[PathWaypoint], *, header: str = ""
) -> None:
    """Write waypoints as a path file (exact round trip through :func:`read_mdat`).

    Args:
        path: Output file.
        waypoints: Stances to write, one per line.
        header: Text written first as ``#`` comment lines.
    """
    lines = [f"# {row}".rstrip() for row in header.splitlines()]
    lines.append("# " + " ".join(MDAT_FIELDS))
    for waypoint in waypoints:
        values = []
        for foot in (waypoint.left, waypoint.right):
            values += [*foot.position, *yaw_to_quaternion(foot.yaw)]
        lines.append(" ".join(repr(float(v)) for v in values))
    Path(path).write_text("\n".join(lines) + "\n")


def _changed(a: Footstep, b: Footstep) -> bool:
    return bool(
        np.max(np.abs(a.position - b.position)) > CLAMP_TOLERANCE
        or abs(float(wrap_angle(a.yaw - b.yaw))) > CLAMP_TOLERANCE
    )


def _mid_frame(waypoint: PathWaypoint) -> Footstep:
    """Frame between the feet: midpoint position, mean yaw."""
    left, right = waypoint.left, waypoint.right
    yaw = right.yaw + 0.5 * float(wrap_angle(left.yaw - right.yaw))
    return Footstep(Side.LEFT, 0.5 * (left.position + right.position), yaw)


def path_targets(
    waypoints: Sequence[PathWaypoint], *, first_swing=None, steps_in_place: bool = False
) -> list[PathTarget]:
    """Alternating single-foot steps that walk through the waypoints.

    From waypoint ``i`` to ``i + 1`` the foot whose pose changed steps; if
    both changed, both step, the first being the foot that keeps the sides
    alternating (for the very first step: ``first_swing``, else the foot on
    the side of the motion, else the right one). An unchanged waypoint is
    skipped, or with ``steps_in_place`` becomes a step in place of the next
    foot in turn (paper A starts with two). When the same foot would move
    twice in a row, or ``first_swing`` is not the first foot to move, a step
    in place of the other foot is inserted.
    """
    if not waypoints:
        raise ConfigurationError("A path needs at least one waypoint (the initial stance).")
    moves = []  # (sides that move, waypoint index); () = step in place
    for i in range(1, len(waypoints)):
        prev, cur = waypoints[i - 1], waypoints[i]
        sides = tuple(s for s in (Side.LEFT, Side.RIGHT) if _changed(prev.foot(s), cur.foot(s)))
        if sides or steps_in_place:
            moves.append((sides, i))
    first = next((m for m in moves if m[0]), None)
    if first_swing is not None:
        last = Side.parse(first_swing).other
    elif first is None:
        last = Side.LEFT  # only steps in place: start with the right foot
    else:
        before, after = waypoints[first[1] - 1], waypoints[first[1]]
        frame = _mid_frame(before)
        one = (
            first[0][0]
            if len(first[0]) == 1
            else opening_side(
                frame.to_local(_mid_frame(after).xy)[1],
                float(wrap_angle(_mid_frame(after).yaw - frame.yaw)),
            )
        )
        in_place_before = moves.index(first)
        last = one.other if in_place_before % 2 == 0 else one
    targets: list[PathTarget] = []
    feet = {Side.LEFT: waypoints[0].left, Side.RIGHT: waypoints[0].right}
    for sides, i in moves:
        line = waypoints[i].line
        label = f"waypoint {i}" + (f" (line {line})" if line is not None else "")
        order = [last.other] if not sides else sorted(sides, key=lambda s: s is last)
        if len(sides) == 1 and sides[0] is last:
            order = [last.other, last]  # keep alternation with a step in place
        for side in order:
            pose = waypoints[i].foot(side) if side in sides else feet[side]
            targets.append(PathTarget(pose, i, label))
            feet[side] = pose
            last = side
    return targets


def plan_from_path(
    waypoints: Sequence[PathWaypoint],
    *,
    rectangle: ReachabilityRectangle = ATLAS_REACHABILITY,
    timing: StepTiming = StepTiming(),
    first_swing=None,
    steps_in_place: bool = False,
    max_extra_steps: int = 10,
) -> FootstepPlan:
    """Footstep plan of a path, walked with paper A's clamping rule in open loop.

    The first waypoint is the initial stance. Targets come from
    :func:`path_targets`; each is clamped into ``rectangle`` around the
    planned support foot and extra steps are inserted until it is reached
    (see :class:`~.path_follower.PathFollower`).

    Raises:
        InfeasibleStep: A target stays out of reach after ``max_extra_steps``.
    """
    targets = path_targets(waypoints, first_swing=first_swing, steps_in_place=steps_in_place)
    follower = PathFollower(
        waypoints[0].left,
        waypoints[0].right,
        [t.footstep for t in targets],
        rectangle,
        labels=[t.label for t in targets],
        max_extra_steps=max_extra_steps,
    )
    return follower.plan(timing)
