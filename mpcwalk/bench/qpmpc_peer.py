"""The peer: the same LIPM walking MPC written with ``qpmpc`` (Apache-2.0).

The problem has the same dynamics (cart-table, x and y stacked: 6 states, 2 jerk
inputs), the same horizon and sampling period, and the same hard constraints
(the ZMP of every future sample inside that sample's support polygon). The cost
takes qpmpc's form: stage state cost towards ``[p_ref, 0, 0]`` per axis (CoM
over the ZMP reference, at rest), terminal cost on the last sample and a jerk
regularisation. Each tick follows qpmpc's path for a time-varying problem:
update the problem, build ``MPCQP`` and call ``qpsolvers.solve_problem``.
"""

import numpy as np

from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.pattern_generator import GeneratorOutput, PatternGenerator, SolveInfo
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.com_state import ComState

#: Back-ends that take sparse matrices (qpmpc's ``sparse`` flag, as its docs advise).
_SPARSE_SOLVERS = ("osqp", "clarabel", "piqp", "highs", "scs", "qpalm", "proxqp")


class QpmpcPeer(PatternGenerator):
    """Linear walking MPC on ``qpmpc`` (benchmark peer, not registered as a generator).

    Args:
        solver: qpsolvers back-end name.
        sampling_period: MPC sampling period, in [s].
        horizon: Number of samples.
        state_weight: Stage state cost weight.
        terminal_weight: Terminal cost weight.
        jerk_weight: Input cost weight.
        zmp_margin: Polygons shrunk by this margin, in [m].
    """

    name = "qpmpc"

    def __init__(
        self,
        *,
        solver: str = "osqp",
        sampling_period: float = 0.05,
        horizon: int = 32,
        state_weight: float = 1.0,
        terminal_weight: float = 1.0,
        jerk_weight: float = 1e-6,
        zmp_margin: float = 0.0,
        **kwargs,
    ) -> None:
        super().__init__(**kwargs)
        import qpmpc  # noqa: F401  (checked at construction)

        self.solver = solver
        self.sampling_period = sampling_period
        self.horizon = horizon
        self.state_weight = state_weight
        self.terminal_weight = terminal_weight
        self.jerk_weight = jerk_weight
        self.zmp_margin = zmp_margin
        self.model = CartTable(self.lipm, sampling_period)
        self.plant = CartTable(self.lipm, self.control_period)
        self.A = np.kron(np.eye(2), self.model.A)
        self.B = np.kron(np.eye(2), self.model.B.reshape(3, 1))
        self.Czmp = np.kron(np.eye(2), self.model.C.reshape(1, 3))  # (2, 6)

    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        self.state = initial_state.as_cart_table()
        return self._output(0.0, self.state)

    def _step(self, measured: ComState | None) -> GeneratorOutput:
        from qpmpc import MPCQP, MPCProblem
        from qpsolvers import solve_problem

        t = self.time
        if measured is not None:
            self.state = measured.as_cart_table(default_acceleration=self.state[2])
        N = self.horizon
        times = t + self.sampling_period * np.arange(N)
        Apoly, bpoly = self.current_schedule.halfplanes(times)
        # Stage 0 is the current state, which no input can change: qpmpc would
        # turn a current ZMP off the polygon into an infeasible QP, so it is
        # left unconstrained (our MPC constrains samples 1..N, the same).
        C_list = [np.zeros((Apoly.shape[1], 6))] + [Apoly[k] @ self.Czmp for k in range(1, N)]
        e_list = [np.ones(Apoly.shape[1])] + [bpoly[k] - self.zmp_margin for k in range(1, N)]
        ref = self.current_schedule.zmp_reference(times)  # qpmpc's stage k is x_k, k = 0..N-1
        targets = np.zeros((N, 6))
        targets[:, 0], targets[:, 3] = ref[:, 0], ref[:, 1]
        x0 = self.state.T.reshape(6)  # [cx, vx, ax, cy, vy, ay]
        problem = MPCProblem(
            transition_state_matrix=self.A,
            transition_input_matrix=self.B,
            ineq_state_matrix=C_list,
            ineq_input_matrix=None,
            ineq_vector=e_list,
            nb_timesteps=N,
            terminal_cost_weight=self.terminal_weight,
            stage_state_cost_weight=self.state_weight,
            stage_input_cost_weight=self.jerk_weight,
            initial_state=x0,
            goal_state=targets[-1],
            target_states=targets.ravel(),
        )
        qp = MPCQP(problem, sparse=self.solver in _SPARSE_SOLVERS)
        sol = solve_problem(qp.problem, solver=self.solver)
        if sol.found and sol.x is not None:
            jerk = sol.x[:2]
        else:
            jerk = np.zeros(2)
        self.state = self.plant.integrate(self.state, jerk, self.control_period)
        return self._output(
            t + self.control_period,
            self.state,
            horizon=None,
            solve=SolveInfo(success=bool(sol.found), solver=f"qpmpc/{self.solver}"),
        )
