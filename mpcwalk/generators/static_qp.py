"""Paper A's static gait as a QP (reformulation (b)).

Paper A keeps the CoM ground projection inside the support polygon and moves
it over the support foot before lifting the other one. Here the same rule is
a hard constraint of the walking QP: at every sample the CoM projection (and
the ZMP) stays inside the support polygon with a margin; the CoM rows use the
single-support foot from one sampling period before single support begins
(see :meth:`~mpcwalk.qp.schedule_tables.ScheduleTables.com_phases`). The
cost is quasi-static (CoM jerk and velocity) plus a pull towards the support
foot centre that acts in single support only, so the QP itself decides when,
inside each double support, to shift the CoM: nothing is scripted in time.
The gait needs slow timing (paper A: 12 s per step); with paper M's 0.5 s
steps the CoM cannot cross to the next foot in 0.05 s and the QP is
infeasible.
"""

from typing import ClassVar

from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.mpc import MpcGenerator
from mpcwalk.generators.static_timing import check_static_timing
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.parameters import MpcParameters


class StaticQPGenerator(MpcGenerator):
    """Static gait (paper A) as a receding-horizon QP.

    Same arguments as :class:`~mpcwalk.generators.mpc.MpcGenerator`; the
    defaults differ (:attr:`default_parameters`): no ZMP tracking, CoM
    velocity and jerk penalised, CoM pulled to the support centre in single
    support only, CoM projection constrained with ``com_margin`` (0.01 m
    suits the small humanoid's 0.10 x 0.06 m feet; set it per robot).

    Measured with T = 4 s, r_ds = 0.5 (4-step walks, straight, turning and
    sideways): the CoM stays 18-25 mm inside the feet (margin 10 mm), within
    7-11 mm of the support foot centre in single support, and the ZMP within
    9 mm of the CoM. A CoM weight of 10 instead of 100 leaves it up to 23 mm
    from the foot centre, a weight of 1 up to 40 mm (the corner of the
    allowed region).
    """

    #: Its CoM stays over the support foot too, so it gets the static gait's damped IK (without
    #: it ``g1`` fell in its first step: 7 steps, 0.33 cm landing error with it).
    holds_com_over_support: ClassVar[bool] = True

    name: ClassVar[str] = "static-qp"
    #: Paper A's timing: 12 s per step (r_ds 0.2: 2.4 s to move the CoM between the feet).
    default_timing: ClassVar[tuple[float, float] | None] = (12.0, 0.2)
    #: The measured CoM error does not reach the quasi-static QP's state (the DCM feedback
    #: still shifts the ZMP): with the MPC's 0.02 the estimate's slow world-frame drift over
    #: paper A's 12 s steps (2 cm after 100 s) walked its CoM off the feet at step 10 of 18.
    observer_gain: ClassVar[float] = 0.0

    @classmethod
    def check_timing(cls, schedule: ContactSchedule, lipm: LIPM) -> None:
        """Refuse a double support too short for the CoM shifts (see
        :mod:`mpcwalk.generators.static_timing`)."""
        check_static_timing(schedule, lipm, cls.name)

    #: Quasi-static: the CoM velocity is damped towards zero.
    track_walking_velocity: ClassVar[bool] = False
    #: None: the static gait has its own horizon (the presets' ``mpc_*`` keys are for
    #: walking at speed).
    PRESET_KEYS: ClassVar[dict[str, tuple[str, type]]] = {}

    default_parameters: ClassVar[MpcParameters] = MpcParameters(
        sampling_period=0.1,  # [s]
        horizon=16,  # 1.6 s
        zmp_weight=0.0,
        jerk_weight=1e-4,  # [s^6/m^2]
        velocity_weight=1.0,  # [s^2/m^2]
        com_weight=100.0,  # [1/m^2], single support only
        com_weight_single_support_only=True,
        zmp_margin=0.0,  # [m]
        com_margin=0.01,  # [m]
    )
