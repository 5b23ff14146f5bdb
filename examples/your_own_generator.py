"""Your own pattern generator: one behind the protocol from scratch, run on the LIPM, and one
derived from the linear MPC, registered by name and walked in MuJoCo.

    python examples/your_own_generator.py
"""

import numpy as np

import mpcwalk
from mpcwalk import (
    LIPM,
    ContactSchedule,
    PatternGenerator,
    VelocityCommand,
    VelocityPlanner,
    rollout,
    support_margins,
)
from mpcwalk.generators.mpc import MpcGenerator
from mpcwalk.generators.registry import GENERATORS
from mpcwalk.registry import Entry


class DcmToSupport(PatternGenerator):
    """Steers the DCM to the centre of the current support (a teaching example: no
    preview, no constraint; the QP generators do better)."""

    name = "dcm-to-support"

    def __init__(self, *, lipm: LIPM = LIPM(), control_period: float = 0.01, gain: float = 3.0):
        super().__init__(lipm=lipm, control_period=control_period)
        self.gain = gain

    def _reset(self, schedule, initial_state):
        self._com = np.array(initial_state.position, dtype=float)
        self._velocity = np.array(initial_state.velocity, dtype=float)
        return self._advance(0.0, dt=0.0)

    def _step(self, measured):
        if measured is not None:  # closed loop: start from the measured CoM
            self._com, self._velocity = measured.position.copy(), measured.velocity.copy()
        return self._advance(self.time + self.control_period, dt=self.control_period)

    def _advance(self, t, dt):
        omega = self.lipm.omega
        target = self.schedule.zmp_reference([t])[0]
        dcm = self._com + self._velocity / omega
        zmp = dcm + (1.0 + self.gain / omega) * (dcm - target)  # dcm' = -gain (dcm - target)
        acceleration = omega**2 * (self._com - zmp)
        self._com = self._com + dt * self._velocity + 0.5 * dt**2 * acceleration
        self._velocity = self._velocity + dt * acceleration
        state = np.vstack([self._com, self._velocity, omega**2 * (self._com - zmp)])
        return self._output(t, state)


schedule = ContactSchedule(VelocityPlanner().plan(VelocityCommand(0.05, 0.0, 0.0), nb_steps=4))
walk = rollout(DcmToSupport(lipm=LIPM(com_height=0.23)), schedule)
print(
    f"on the LIPM: {len(walk.times)} ticks, CoM {walk.com[0].round(3)} -> {walk.com[-1].round(3)} m"
)

margins = support_margins(schedule, walk.times, walk.zmp)
print(f"its ZMP leaves the feet by up to {-1000 * margins.min():.0f} mm: nothing constrains it")


class SmoothMpc(MpcGenerator):
    """The linear MPC with ten times its jerk weight: smoother, slower to react."""

    name = "smooth-mpc"
    default_parameters = MpcGenerator.default_parameters.replace(
        jerk_weight=10 * MpcGenerator.default_parameters.jerk_weight
    )


# in MuJoCo: registered by name (an entry: name, summary, class), the walk runner finds it
GENERATORS.register(Entry(SmoothMpc.name, "The linear MPC, smoother.", lambda: SmoothMpc))
# the mpc controller (closed loop, balance, heading hold) with this generator: a "custom" one
spec = mpcwalk.WalkSpec.build(
    "bioloid-like", generator=SmoothMpc.name, command=(0.1, 0.0, 0.0), nb_steps=4
)
result = mpcwalk.run_walk(spec)
m = result.metrics
print(
    f"{SmoothMpc.name} in MuJoCo: fell {m.fell}, CoP margin p5 {1000 * m.cop_margin_p05_m:.1f} mm"
)
