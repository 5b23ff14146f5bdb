"""Closing the loop on the estimated CoM of a position-controlled robot.

The pattern generator's CoM is the reference of the whole-body IK, i.e. the servo targets.
:class:`DcmFeedback` compares the CoM the estimator computed from the robot's sensors
(:class:`~mpcwalk.estimation.estimated_state.EstimatedState`) with it:

1. **anchoring**: the estimated CoM relative to the estimated soles of the feet in contact is
   placed on their planned poses (a landing a few millimetres off its footstep moves the
   whole robot; balance depends on the CoM relative to the feet);
2. **observer**: the generator may restart from the reference plus ``observer_gain`` times
   the error (closed-form generators ignore it);
3. **DCM feedback**: the desired ZMP is the generator's plus ``dcm_gain`` times the error of
   the divergent component of motion ``xi = c + c_dot / omega`` (the error then decays at
   the rate ``omega (dcm_gain - 1)``), kept ``zmp_margin`` inside the planned support
   polygon. The controller realises it with the servo feed-forward torques, not by moving
   the kinematic reference, so that the servos keep pulling the robot towards the plan. The
   balance stabilizer (:mod:`mpcwalk.control.stabilizers.balance`) adds an integral term to
   that ZMP and an estimated CoM offset to the measurement.

Measured on the bioloid-like robot when its servos had kp = 10 N m/rad (the AX-12A's default
compliance slope; 50 N m/rad since), 20 steps at 0.1 m/s with the
MPC: restarting the generator from the raw measured state (``observer_gain = 1``) makes the
kinematic reference follow every deviation of the robot, the servos stop pushing back and
it sits down within a second (falls within 1.6 s with the DCM feedback, as with 0.5);
without the DCM feedback (open loop) its lateral sway grows
step after step until it falls after about 4 s; with ``dcm_gain`` from 2 to 6 and
``observer_gain`` from 0 to 0.3 it walks. The observer gain costs robustness: with 0.1 the
preview generator's heading drifts by 7 deg over paper M's turning walk (0.05: 0.4 deg), and
paper M's two pushes (0, 5, 0) N for 0.1 s at rest and (10, 5, 0) N for 0.05 s at 3 s topple
the preview walk for any gain from 0.02 up and the MPC walk from 0.05 up, while all three
generators walk through them with 0 (their closed loop is then the DCM feedback alone).
Each generator gives its default share (:attr:`PatternGenerator.observer_gain`): 0.05 for
preview control, 0.02 for the MPCs, whose push recovery it improves (paper M's push sweep,
``experiments/paper_m``): a forward push at the start of single support is survived up to
0.575 N s with 0.02 against 0.425 N s with 0.05, a lateral one up to 0.31 against 0.25 N s.
Feeding the measured DCM error to the MPC as a velocity error, or restarting the MPC from
the full measurement while the reference integrates the same jerk from its own state, both
survive less (0.15 to 0.36 N s forward): on position servos the reference that stays
behind is what pulls the robot back.
"""

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from mpcwalk.control.control_output import ControlOutput
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Side, wrap_angle
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.swing_foot import FeetState
from mpcwalk.generators.pattern_generator import GeneratorOutput
from mpcwalk.models.com_state import ComState


def support_weights(zmp: np.ndarray, feet: FeetState) -> tuple[float, float]:
    """Share of the weight on the left and right feet: all on the support foot in single
    support, else by the position of ``zmp`` [m] along the segment between the feet."""
    if not feet.left.in_contact:
        return 0.0, 1.0
    if not feet.right.in_contact:
        return 1.0, 0.0
    left, right = feet.left.position, feet.right.position
    ax, ay = float(left[0] - right[0]), float(left[1] - right[1])
    dx, dy = float(zmp[0] - right[0]), float(zmp[1] - right[1])
    share = min(1.0, max(0.0, (dx * ax + dy * ay) / (ax * ax + ay * ay)))
    return share, 1.0 - share


def measured_com_state(state: EstimatedState | ComState | None) -> ComState | None:
    """CoM state of what the controller is given: the estimated one
    (:meth:`EstimatedState.com_state`), the ComState itself, or None.

    Raises:
        ConfigurationError: Anything else (a simulation state: pass the estimator's output,
            or its ``oracle`` for a comparison).
    """
    if state is None or isinstance(state, ComState):
        return state
    if isinstance(state, EstimatedState):
        return state.com_state()
    raise ConfigurationError(
        "The controller steps on an EstimatedState (the estimator's output, or a simulation "
        f"state's `.oracle` for a comparison), a ComState or None, got {type(state).__name__}."
    )


def shrink_polygon(vertices: np.ndarray, margin: float) -> np.ndarray:
    """Vertices (k, 2) of the convex polygon of counter-clockwise ``vertices`` with every
    edge moved inwards by ``margin`` [m] (smaller than the polygon's inradius)."""
    edges = np.roll(vertices, -1, axis=0) - vertices
    inward = np.stack([-edges[:, 1], edges[:, 0]], axis=1)
    inward /= np.linalg.norm(inward, axis=1, keepdims=True)
    previous = np.roll(inward, 1, axis=0)
    cosine = np.einsum("ij,ij->i", previous, inward)
    return vertices + margin * (previous + inward) / (1.0 + cosine)[:, None]


def project_into_polygon(vertices: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Nearest point to ``point`` (2,) in the convex polygon of counter-clockwise
    ``vertices`` (k, 2): the point itself when inside, else its projection on the boundary."""
    point = np.asarray(point, dtype=float)
    edges = np.roll(vertices, -1, axis=0) - vertices
    normals = np.stack([edges[:, 1], -edges[:, 0]], axis=1)  # outward for CCW vertices
    if np.all(np.einsum("ij,ij->i", normals, point - vertices) <= 0.0):
        return point.copy()
    lengths = np.einsum("ij,ij->i", edges, edges)
    ratios = np.clip(
        np.einsum("ij,ij->i", point - vertices, edges) / np.maximum(lengths, 1e-300), 0.0, 1.0
    )
    candidates = vertices + ratios[:, None] * edges
    return candidates[np.argmin(np.linalg.norm(candidates - point, axis=1))].copy()


def _check_range(name: str, value: float, low: float, high: float) -> float:
    value = float(value)
    if not low <= value <= high:
        raise ConfigurationError(f"{name} must lie in [{low:g}, {high:g}], got {value!r}.")
    return value


class DcmFeedback:
    """Measured CoM error, generator input and desired ZMP of one control tick.

    Args:
        schedule: Footsteps and contact phases (planned feet and support polygons).
        omega: Natural frequency of the LIPM [1/s].
        observer_gain: Share in [0, 1] of the measured CoM error given to the generator.
        dcm_gain: ZMP shift per metre of DCM error, >= 0.
        zmp_margin: Distance [m] kept between the desired ZMP and the support polygon edges.

    Raises:
        ConfigurationError: A gain or margin out of range.
    """

    def __init__(
        self,
        schedule: ContactSchedule,
        omega: float,
        *,
        observer_gain: float = 0.05,
        dcm_gain: float = 3.0,
        zmp_margin: float = 0.0,
    ) -> None:
        self.schedule = schedule
        self.omega = float(omega)
        self.observer_gain = _check_range("observer_gain", observer_gain, 0.0, 1.0)
        self.dcm_gain = _check_range("dcm_gain", dcm_gain, 0.0, np.inf)
        half_width = 0.5 * min(schedule.foot.length, schedule.foot.width)
        self.zmp_margin = _check_range("zmp_margin", zmp_margin, 0.0, half_width)
        self._shrunk: dict[int, np.ndarray] = {}  # phase index -> its polygon, shrunk

    def set_schedule(self, schedule: ContactSchedule) -> None:
        """Use the feet and polygons of ``schedule`` from now on (moved footsteps)."""
        self.schedule = schedule
        self._shrunk.clear()

    def anchor(
        self,
        measured: ComState,
        sole_positions: np.ndarray,
        sole_yaws: np.ndarray,
        t: float,
        weights: Sequence[float],
    ) -> ComState:
        """The measured CoM state carried with the feet in contact at ``t`` onto their
        planned poses, averaged with ``weights`` (left, right).

        Args:
            measured: Measured CoM state.
            sole_positions: Measured left and right sole positions, shape (2, 3), in [m].
            sole_yaws: Measured left and right sole yaws, shape (2,), in [rad].
            t: Time of the measurement [s].
            weights: Share of the weight on the left and right feet.
        """
        positions, yaws = sole_positions, sole_yaws
        planned = self.schedule.phase(t).feet
        position, velocity, total = np.zeros(2), np.zeros(2), 0.0
        for index, (side, weight) in enumerate(zip((Side.LEFT, Side.RIGHT), weights)):
            if side not in planned or weight <= 0.0:
                continue
            foot = planned[side]
            turn = float(wrap_angle(foot.yaw - yaws[index]))
            c, s = np.cos(turn), np.sin(turn)
            rotation = np.array([[c, -s], [s, c]])
            position += weight * (foot.xy + rotation @ (measured.position - positions[index][:2]))
            velocity += weight * (rotation @ measured.velocity)
            total += weight
        if total <= 0.0:
            return measured
        return ComState.trusted(position / total, velocity / total)

    def observe(
        self,
        measured: ComState,
        state: EstimatedState | None,
        references: ControlOutput,
        t: float,
        com_offset: np.ndarray | None = None,
    ) -> tuple[ComState, np.ndarray]:
        """Generator input and DCM error [m] of an estimate at ``t`` [s] against the
        references of that time (the controller's last output): the estimated CoM anchored to
        the estimated soles when ``state`` is given (weighted by :func:`support_weights` of
        the desired ZMP), plus ``com_offset`` [m] (the robot's CoM from the model's, shape
        (2,)), then :meth:`compare`."""
        if state is not None:
            weights = support_weights(references.zmp_command, references.feet)
            measured = self.anchor(measured, state.sole_positions, state.sole_yaws, t, weights)
        if com_offset is not None and (com_offset[0] or com_offset[1]):
            measured = ComState.trusted(measured.position + com_offset, measured.velocity)
        return self.compare(measured, references.generator)

    def compare(
        self, measured: ComState, reference: GeneratorOutput
    ) -> tuple[ComState, np.ndarray]:
        """Generator input (observer estimate) and DCM error [m], shape (2,), of a measured
        CoM state against the reference of the same time."""
        error_p = measured.position - reference.com
        error_v = measured.velocity - reference.com_velocity
        estimate = ComState.trusted(
            reference.com + self.observer_gain * error_p,
            reference.com_velocity + self.observer_gain * error_v,
            np.array(reference.com_acceleration, dtype=float),
        )
        return estimate, error_p + error_v / self.omega

    def base_acceleration(self, q: np.ndarray, zmp_shift: np.ndarray) -> np.ndarray:
        """Acceleration of the floating base [m/s^2], base frame, shape (3,), that moves the
        CoP of the reference motion's contact wrench by ``zmp_shift`` [m] (LIPM: ``-omega^2``
        times the shift), at the configuration ``q`` (base quaternion x, y, z, w)."""
        rotation = pin.Quaternion(q[3:7]).normalized().matrix()
        shift = -(self.omega**2) * np.array([zmp_shift[0], zmp_shift[1], 0.0])
        return rotation.T @ shift

    def desired_zmp(
        self,
        t: float,
        zmp: np.ndarray,
        dcm_error: np.ndarray | None,
        shift: np.ndarray | None = None,
    ) -> np.ndarray:
        """The generator's ZMP at ``t`` plus the DCM feedback (plus ``shift`` [m], the
        balance stabilizer's integral term), inside the support polygon."""
        desired = np.array(zmp, dtype=float)
        moved = False
        if dcm_error is not None and (dcm_error[0] or dcm_error[1]):
            desired += self.dcm_gain * np.asarray(dcm_error)
            moved = True
        if shift is not None and (shift[0] or shift[1]):
            desired += shift
            moved = True
        return self.clamp(t, desired) if moved else desired

    def clamp(self, t: float, zmp: np.ndarray) -> np.ndarray:
        """``zmp`` moved inside the planned support polygon at ``t``, ``zmp_margin`` from its
        edges."""
        index = self.schedule.phase_at(t)
        polygon = self.schedule.phases[index].polygon
        if (polygon.A @ zmp <= polygon.b - self.zmp_margin).all():
            return zmp
        if index not in self._shrunk:
            self._shrunk[index] = shrink_polygon(polygon.vertices, self.zmp_margin)
        return project_into_polygon(self._shrunk[index], zmp)
