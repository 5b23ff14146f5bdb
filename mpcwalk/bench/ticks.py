"""Per-tick time of every pattern generator on the same 20-step LIPM walk.

Each case runs :func:`mpcwalk.generators.rollout` over the same schedule and
records the wall time of every ``step()`` call (update + solve for the QP
generators). Ratios are taken against the closed-form generator measured in
the same run. Each case walks ``repeats`` times (a fresh generator each time), in rounds
that walk every case once, and reports the median over its walks of each walk's median and
99th percentile: a tail percentile of one walk moved by a fifth from run to run on this
virtual machine, and a slow moment of the machine once made every tick of the closed form's
first walk 1.7x slower (the reference of every ratio).
"""

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mpcwalk.exceptions import ConfigurationError, MpcwalkError
from mpcwalk.footsteps.footstep import FootGeometry, StepTiming
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.footsteps.velocity_planner import VelocityCommand, VelocityPlanner
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.generators import make_generator, rollout
from mpcwalk.generators.pattern_generator import PatternGenerator
from mpcwalk.models.lipm import LIPM

#: MPC back-ends timed by default (when installed), besides osqp-direct and casadi.
DEFAULT_QPSOLVERS = ("daqp", "proxqp", "quadprog", "osqp", "clarabel", "piqp", "highs", "qpalm")


@dataclass(frozen=True)
class TickCase:
    """Result of one generator configuration.

    Attributes:
        label: Row name.
        generator: Generator name.
        solver: QP back-end, or "" for closed forms.
        nb_ticks: Number of timed ticks.
        median_us: Median tick, in [us].
        p99_us: 99th percentile tick, in [us].
        ratio_to_analytic: median / median of the closed form, same run.
        zmp_margin_min_m: Smallest planned ZMP margin, in [m].
        failures: Ticks whose QP failed (in its first walk).
        timing: ``"paper M"`` (T = 0.5 s, r_ds = 0.2) or ``"slow"`` (static gaits:
            T = 2 s, r_ds = 0.5, same step lengths).
        error: The error that stopped this case, or "" (the run goes on).
        repeats: Walks timed; ``median_us`` and ``p99_us`` are the medians over them of
            each walk's median and 99th percentile.
    """

    label: str
    generator: str
    solver: str
    nb_ticks: int
    median_us: float
    p99_us: float
    ratio_to_analytic: float
    zmp_margin_min_m: float
    failures: int
    timing: str = "paper M"
    error: str = ""
    repeats: int = 1


def _cases(solvers: Sequence[str] | None, include_peer: bool):
    from qpsolvers import available_solvers

    cases: list[tuple[str, str, str, dict[str, Any]]] = [
        ("analytic", "analytic", "", {}),
        ("static (slow timing)", "static", "", {}),
        ("preview", "preview", "", {}),
        ("mpc daqp-direct (default)", "mpc", "daqp-direct", {"solver": "daqp-direct"}),
        ("mpc osqp-direct", "mpc", "osqp-direct", {"solver": "osqp-direct"}),
        ("mpc casadi", "mpc", "casadi", {"solver": "casadi"}),
    ]
    wanted = DEFAULT_QPSOLVERS if solvers is None else solvers
    for name in wanted:
        if name in available_solvers:
            cases.append((f"mpc {name}", "mpc", name, {"solver": name}))
    # footstep-adaptive MPC: dense QP rebuilt every tick; quadprog (its default), on the rows
    # near binding, and DAQP through qpsolvers
    if "quadprog" in available_solvers:
        cases.append(
            ("mpc-steps quadprog (default)", "mpc-steps", "quadprog", {"solver": "quadprog"})
        )
        screened = {"solver": "quadprog-screened"}
        cases.append(("mpc-steps quadprog-screened", "mpc-steps", "quadprog-screened", screened))
    if "daqp" in available_solvers:
        cases.append(("mpc-steps daqp", "mpc-steps", "daqp", {"solver": "daqp"}))
    if "quadprog" in available_solvers:  # the same with step timing and capturability
        timing = {"solver": "quadprog", "timing_adaptation": True, "capturability": True}
        cases.append(("mpc-timing quadprog", "mpc-steps", "quadprog", timing))
        late = {"solver": "quadprog", "late_adjustment": True}
        cases.append(("mpc-late quadprog", "mpc-steps", "quadprog", late))
        nlp = {"solver": "quadprog", "capturability": True}  # + the CasADi program (IPOPT)
        cases.append(("mpc-timing-nlp quadprog+ipopt", "mpc-nlp", "quadprog", nlp))
        cases.append(("mpc-hip quadprog", "mpc-hip", "quadprog", timing))  # with the flywheel
        hip = {**timing, "solver": "quadprog-screened"}
        cases.append(("mpc-hip quadprog-screened", "mpc-hip", "quadprog-screened", hip))
    cases.append(
        (
            "static-qp daqp-direct (default, slow timing)",
            "static-qp",
            "daqp-direct",
            {"solver": "daqp-direct"},
        )
    )
    cases.append(
        (
            "static-qp osqp-direct (slow timing)",
            "static-qp",
            "osqp-direct",
            {"solver": "osqp-direct"},
        )
    )
    if "daqp" in available_solvers:
        cases.append(("static-qp daqp (slow timing)", "static-qp", "daqp", {"solver": "daqp"}))
    if include_peer:
        cases.append(("qpmpc osqp (peer)", "qpmpc", "osqp", {"solver": "osqp"}))
        if "daqp" in available_solvers:
            cases.append(("qpmpc daqp (peer)", "qpmpc", "daqp", {"solver": "daqp"}))
    return cases


def _make(generator: str, lipm: LIPM, control_period: float, options: dict) -> PatternGenerator:
    if generator == "qpmpc":
        from mpcwalk.bench.qpmpc_peer import QpmpcPeer

        return QpmpcPeer(lipm=lipm, control_period=control_period, **options)
    return make_generator(generator, lipm=lipm, control_period=control_period, **options)


def run_tick_benchmark(
    *,
    nb_steps: int = 20,
    command: VelocityCommand = VelocityCommand(0.1, 0.0, 0.35),
    control_period: float = 0.01,
    solvers: Sequence[str] | None = None,
    include_peer: bool = True,
    progress: bool = True,
    repeats: int = 3,
) -> list[TickCase]:
    """Time every generator on the same walk.

    Args:
        nb_steps: Steps of the walk.
        command: Velocity command of the footstep planner.
        control_period: Generator tick, in [s].
        solvers: qpsolvers back-ends for the MPC (default: :data:`DEFAULT_QPSOLVERS`).
        include_peer: Also time the qpmpc peer on the same problem.
        progress: Show a progress bar.
        repeats: Walks per case (see the module's documentation).

    Returns:
        One :class:`TickCase` per configuration, the closed form first.
    """
    from tqdm import tqdm

    if isinstance(repeats, bool) or int(repeats) != repeats or repeats < 1:
        raise ConfigurationError(
            f"repeats must be a positive integer (walks per case), got {repeats!r}."
        )
    lipm = LIPM()
    fast, slow = StepTiming(), StepTiming(step_duration=2.0, double_support_ratio=0.5)
    scale = fast.step_duration / slow.step_duration
    slow_command = VelocityCommand(command.vx * scale, command.vy * scale, command.vyaw * scale)
    schedules = {
        "paper M": ContactSchedule(
            VelocityPlanner(LegLimits(), fast).plan(command, nb_steps), FootGeometry()
        ),
        "slow": ContactSchedule(
            VelocityPlanner(LegLimits(), slow).plan(slow_command, nb_steps), FootGeometry()
        ),
    }
    cases = _cases(solvers, include_peer)
    walks: list[list] = [[] for _ in cases]
    errors = [""] * len(cases)
    # round after round, every case once per round: a slow moment of the machine falls on
    # one walk of a few cases, which the medians over the rounds leave out
    rounds = [(r, i) for r in range(int(repeats)) for i in range(len(cases))]
    for _, i in tqdm(rounds, desc="walks", disable=not progress):
        label, generator, solver, options = cases[i]
        if errors[i]:
            continue
        schedule = schedules["slow" if generator in ("static", "static-qp") else "paper M"]
        try:
            walks[i].append(rollout(_make(generator, lipm, control_period, options), schedule))
        except MpcwalkError as failure:  # a failing case never stops the benchmark
            errors[i] = str(failure)
    results: list[TickCase] = []
    reference = None
    for (label, generator, solver, _), case_walks, message in zip(cases, walks, errors):
        timing = "slow" if generator in ("static", "static-qp") else "paper M"
        if message:
            nan = float("nan")
            results.append(
                TickCase(label, generator, solver, 0, nan, nan, nan, nan, 0, timing, message)
            )
            continue
        traj = case_walks[0]
        ticks = [walk.tick_times[1:] * 1e6 for walk in case_walks]  # the first: lazy set-up
        median = float(np.median([np.median(t) for t in ticks]))
        if reference is None:
            reference = median
        margins = support_margins(schedules[timing], traj.times, traj.zmp)
        results.append(
            TickCase(
                label=label,
                generator=generator,
                solver=solver,
                nb_ticks=len(ticks[0]),
                median_us=median,
                p99_us=float(np.median([np.percentile(t, 99) for t in ticks])),
                ratio_to_analytic=median / reference,
                zmp_margin_min_m=float(margins.min()),
                failures=int(traj.nb_failures),
                timing=timing,
                repeats=len(case_walks),
            )
        )
    return results


def format_table(results: list[TickCase]) -> str:
    """Markdown table of the results."""
    lines = [
        "| generator | median [us] | p99 [us] | median / analytic | min ZMP margin [cm] | QP failures |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for r in results:
        if r.error:
            lines.append(f"| {r.label} | failed: {r.error[:80]} | | | | |")
            continue
        lines.append(
            f"| {r.label} | {r.median_us:.1f} | {r.p99_us:.1f} | {r.ratio_to_analytic:.1f} | "
            f"{100 * r.zmp_margin_min_m:.2f} | {r.failures} |"
        )
    return "\n".join(lines)


def tick_report(
    results: list[TickCase],
    *,
    nb_steps: int,
    command: VelocityCommand,
    control_period: float,
    command_line: str,
) -> str:
    """``ticks.md``: what was timed, on which machine, the command line that reproduces it,
    and the table of the results (:func:`format_table`)."""
    from mpcwalk.bench.output import machine_description
    from mpcwalk.generators.mpc import MpcGenerator

    params = MpcGenerator.default_parameters
    header = (
        f"Per-tick time of each pattern generator, {nb_steps}-step walk at "
        f"v=({command.vx}, {command.vy}, {command.vyaw}), control period {control_period} s, "
        f"MPC (and qpmpc peer) horizon {params.horizon} samples at {params.sampling_period} s; "
        f"static gaits on slow timing (T = 2 s, r_ds = 0.5, same step lengths); "
        f"{results[0].repeats if results else 1} walks per case, the medians over them of "
        "each walk's median and 99th percentile. "
        f"Machine: {machine_description()}.\n"
        f"Command: `{command_line}`\n"
    )
    return header + "\n" + format_table(results) + "\n"
