"""Exceptions raised by mpcwalk.

Every error the library raises on purpose derives from :class:`MpcwalkError`.
Messages say what was expected, what came, and how to fix it.
"""

from collections.abc import Mapping, Sequence
from typing import Any


class MpcwalkError(Exception):
    """Root of all mpcwalk errors."""


class ConfigurationError(MpcwalkError, ValueError):
    """A parameter has a value outside its valid range (e.g. a negative step duration)."""


class InfeasibleCommand(MpcwalkError, ValueError):
    """A velocity command lies beyond what the robot's legs can achieve."""

    def __init__(self, name: str, value: float, limit: float, unit: str = "") -> None:
        self.name = name
        self.value = value
        self.limit = limit
        unit_str = f" {unit}" if unit else ""
        super().__init__(
            f"Velocity command {name}={value:g}{unit_str} exceeds its limit "
            f"|{name}| <= {limit:g}{unit_str}; lower the command or raise the limit "
            "(longer legs, longer steps or shorter step duration)."
        )


class InfeasibleStep(MpcwalkError, ValueError):
    """A footstep cannot be reached from the current support foot."""


class FootstepFileError(MpcwalkError, ValueError):
    """A footstep path file (.mdat) is malformed.

    Attributes:
        path: File name (or ``"<string>"``).
        line: One-based line number, or None for whole-file problems.
        field: Name of the offending field, or None.
    """

    def __init__(
        self,
        message: str,
        *,
        path: str = "<string>",
        line: int | None = None,
        field: str | None = None,
    ) -> None:
        self.path = path
        self.line = line
        self.field = field
        where = path if line is None else f"{path}:{line}"
        if field is not None:
            where += f" (field '{field}')"
        super().__init__(f"{where}: {message}")


class TerrainError(ConfigurationError):
    """A terrain (its features, its file) is malformed, or does not fit the robot that
    should walk it."""


class SpecFileError(ConfigurationError):
    """A walk specification file (``spec.toml``) is missing, not TOML, or holds a part,
    field or value the specification refuses.

    Attributes:
        path: The file.
    """

    def __init__(self, message: str, *, path: str = "<spec>") -> None:
        self.path = path
        super().__init__(f"{path}: {message}")


class NotRegistered(MpcwalkError, ValueError):
    """A name asked of a registry (:class:`mpcwalk.registry.Registry`) is unknown, or known
    but not installed here.

    Attributes:
        kind: What the registry holds (``"stabilizer"``).
        name: The name asked for.
        available: The names available on this installation.
        installable: Known names that are not installed -> how to install them.
        install: How to install ``name`` when it is known but not installed, else "".
        list_command: The command that lists the registry.
    """

    def __init__(
        self,
        kind: str,
        name: str,
        available: Sequence[str],
        installable: Mapping[str, str] | None = None,
        *,
        install: str = "",
        list_command: str = "",
    ) -> None:
        self.kind = kind
        self.name = name
        self.available = list(available)
        self.installable = dict(installable or {})
        self.install = install
        self.list_command = list_command
        names = ", ".join(self.available) or "(none)"
        if install:
            message = (
                f"The {kind} '{name}' is not installed; install it with `{install}`, or "
                f"choose one of {names}."
            )
        else:
            message = f"Unknown {kind} '{name}'; available: {names}"
            if self.installable:
                groups: dict[str, list[str]] = {}  # install command, <name> for the name
                for known, how in self.installable.items():
                    groups.setdefault(how.replace(known, "<name>"), []).append(known)
                hints = ", ".join(f"{', '.join(n)} (`{how}`)" for how, n in groups.items())
                message += f"; installable: {hints}"
            message += "."
        if list_command:
            message += f" ({list_command} lists them.)"
        Exception.__init__(self, message)


class SolverNotFound(NotRegistered):
    """The requested QP solver is unknown or not installed.

    Attributes:
        solver: The name asked for (also ``name``).
    """

    def __init__(
        self,
        solver: str,
        available: Sequence[str],
        installable: Mapping[str, str] | None = None,
        *,
        install: str = "",
    ) -> None:
        self.solver = solver
        super().__init__(
            "solver",
            solver,
            available,
            installable,
            install=install,
            list_command="mpcwalk solvers",
        )


class _NotInRegistry(NotRegistered):
    """A :class:`NotRegistered` of one registry, whose kind and listing command are class
    attributes; called as the registry's ``not_found`` (name, available names, installable
    names, install hint)."""

    registry_kind = ""
    registry_list_command = ""

    def __init__(
        self,
        name: str,
        available: Sequence[str],
        installable: Mapping[str, str] | None = None,
        install: str = "",
    ) -> None:
        super().__init__(
            self.registry_kind,
            name,
            available,
            installable,
            install=install,
            list_command=self.registry_list_command,
        )


class GeneratorNotFound(_NotInRegistry):
    """The requested pattern generator name is unknown."""

    registry_kind = "pattern generator"
    registry_list_command = "mpcwalk generators"


class StabilizerNotFound(_NotInRegistry):
    """The requested stabilizer name is unknown."""

    registry_kind = "stabilizer"
    registry_list_command = "mpcwalk stabilizers"


class NoSolutionFound(MpcwalkError):
    """A QP solver returned no solution.

    Attributes:
        solver: Name of the solver.
        status: The solver's own status, as a string.
        problem: The problem that failed, for inspection.
    """

    def __init__(self, solver: str, status: str = "", problem: Any = None) -> None:
        self.solver = solver
        self.status = status
        self.problem = problem
        super().__init__(
            f"QP solver '{solver}' found no solution (status: {status or 'unknown'}). "
            "The support polygon constraints may be infeasible from the current state; "
            "check the footsteps and the measured CoM state."
        )


class ControllerStopped(MpcwalkError):
    """The controller stopped the walk: too many fallback ticks in a row (faults beyond its
    bound, :mod:`mpcwalk.control.faults`). A controlled stop, not bad input: the walk's log
    and metrics are written (outcome ``stopped``, exit code 3).

    Attributes:
        reason: Why, in words.
    """

    def __init__(self, reason: str) -> None:
        self.reason = reason
        super().__init__(f"The controller stopped the walk: {reason}.")


class NotReset(MpcwalkError, RuntimeError):
    """A generator was stepped before :meth:`reset` gave it a schedule."""


class RobotNotFound(MpcwalkError, ValueError):
    """The requested robot has no preset, or its description is not installed."""

    def __init__(self, name: str, available: Sequence[str], reason: str = "") -> None:
        self.name = name
        self.available = list(available)
        why = f" ({reason})" if reason else ""
        super().__init__(
            f"Unknown robot '{name}'{why}; choose one of {', '.join(self.available) or '(none)'}."
        )


class FrameNotFound(MpcwalkError, LookupError):
    """A frame (Pinocchio frame, MuJoCo site or URDF link) does not exist in a robot."""

    def __init__(self, frame: str, available: Sequence[str], robot: str = "") -> None:
        self.frame = frame
        self.available = sorted(available)
        where = f" in robot '{robot}'" if robot else ""
        super().__init__(
            f"Frame '{frame}' not found{where}; the frames that exist are: "
            f"{', '.join(self.available)}."
        )


class PackageDataNotFound(MpcwalkError, FileNotFoundError):
    """The data shipped with mpcwalk (robot descriptions, presets, experiment configs) is
    not installed as a folder beside the package."""

    def __init__(self, package: str, reason: str) -> None:
        self.package = package
        super().__init__(
            f"mpcwalk's data package '{package}' was expected installed with mpcwalk, but "
            f"{reason}; install mpcwalk with pip (`pip install -e .` in a checkout of the "
            "repository, or from a wheel) instead of putting its source on sys.path."
        )


class SimulationModelError(ConfigurationError):
    """A figure of the simulated world lies outside its range: a noise, bias, resolution or
    latency of the sensor model (:class:`~mpcwalk.sim.sensing.model.SensorModel`), or a
    trunk mass, CoM offset, friction, servo strength, friction cone or impedance ratio of the
    model mismatch
    (:class:`~mpcwalk.sim.model_mismatch.ModelMismatch`).

    Attributes:
        model: The class of the figure (``"SensorModel"``, ``"ModelMismatch"``).
        field: Name of the offending field.
        value: The value it was given.
    """

    def __init__(self, model: str, field: str, value: Any, expected: str, fix: str) -> None:
        self.model = model
        self.field = field
        self.value = value
        super().__init__(f"{model}.{field} must be {expected}, got {value!r}; {fix}.")


class SimulationUnstable(MpcwalkError, RuntimeError):
    """MuJoCo's integration diverged (non-finite or huge accelerations)."""

    def __init__(self, time: float, timestep: float) -> None:
        self.time = time
        super().__init__(
            f"The MuJoCo simulation diverged at t = {time:.3f} s (bad accelerations, positions "
            f"or velocities); lower the physics time step (now {timestep:g} s) or the actuator "
            "gains, or check the joint targets for jumps."
        )


class RenderingUnavailable(MpcwalkError, RuntimeError):
    """No headless OpenGL backend works on this machine, so no video can be rendered."""

    def __init__(self, failures: dict[str, str]) -> None:
        self.failures = dict(failures)
        tried = "; ".join(f"{name}: {why}" for name, why in self.failures.items())
        super().__init__(
            f"Cannot render offscreen: no OpenGL backend works here ({tried}). Enable one: "
            "EGL with a GPU driver or Mesa (Debian/Ubuntu: `apt-get install libegl1 libgl1 "
            "libegl-mesa0`), or software OSMesa (`apt-get install libosmesa6`) and start "
            "Python with MUJOCO_GL=osmesa; or run without --video."
        )


class VideoDependencyMissing(MpcwalkError, ImportError):
    """The MP4 encoder (``imageio-ffmpeg``) is not installed."""

    def __init__(self) -> None:
        super().__init__(
            "Writing MP4 videos needs the package imageio-ffmpeg (it ships an ffmpeg binary); "
            "install it with `pip install imageio-ffmpeg`, or run without --video."
        )


class PushFormatError(MpcwalkError, ValueError):
    """A push string is not ``"T,DURATION,FX,FY,FZ"`` (five numbers, duration > 0)."""

    def __init__(self, text: str, problem: str) -> None:
        self.text = text
        self.problem = problem
        super().__init__(
            f"Push '{text}' is malformed: {problem}. Expected 'T,DURATION,FX,FY,FZ': start "
            "time [s] >= 0, duration [s] > 0 and the force [N] in the world frame, e.g. "
            "'3.0,0.05,10,5,0'."
        )


class LegUnreachable(MpcwalkError, ValueError):
    """A sole target is farther from (or closer to) the hip than the leg can reach.

    Attributes:
        side: ``"left"`` or ``"right"``.
        distance: Distance from the hip centre to the ankle of the target, in [m].
        leg_length: Largest reach, thigh + shank, in [m].
        minimum_length: Smallest reach, |thigh - shank|, in [m].
    """

    def __init__(
        self, side: str, distance: float, leg_length: float, minimum_length: float
    ) -> None:
        self.side, self.distance = side, distance
        self.leg_length, self.minimum_length = leg_length, minimum_length
        where = "beyond the leg length" if distance > leg_length else "closer than the minimum"
        limit = leg_length if distance > leg_length else minimum_length
        super().__init__(
            f"The {side} sole target puts the ankle {distance:.4f} m from the hip centre, "
            f"{where} {limit:.4f} m (thigh + shank = {leg_length:.4f} m); bring the target "
            "closer to the hip (lower the torso or shorten the step)."
        )
