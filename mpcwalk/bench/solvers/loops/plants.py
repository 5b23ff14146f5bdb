"""Each QP back-end as the MPC's solver, in a control loop.

Two plants:

- ``"lipm"``: the MPC runs closed loop on the LIPM (the measured state is the
  plant's state) over a 20-step walk, with velocity pushes at a few ticks.
  Every tick is timed; failed solves (the MPC then follows its previous
  plan), the longest run of failures, whether the walk got to its end (the
  MPC gives up after ``max_fallback_ticks`` failures in a row) and the ZMP
  margin of the executed ZMP are recorded.
- ``"mujoco"``: the MPC drives the small humanoid (``bioloid-like``) walking
  in MuJoCo through the project's walk runner, ``mpcwalk.walking.runner.run_walk``
  (:func:`run_mujoco_loop`): the generator tick of every control tick, the
  failed solves, the fall and the walk's metrics (steps completed, foot
  placement error, measured ZMP margin, real-time factor) come from there.
"""

import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from mpcwalk.bench.solvers.backends.settings import backend_settings
from mpcwalk.bench.solvers.problems.families import get_family, walk_schedule
from mpcwalk.bench.solvers.tolerances import ToleranceLevel
from mpcwalk.exceptions import MpcwalkError
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.models.com_state import ComState


@dataclass(frozen=True)
class LoopRun:
    """One walk with one back-end.

    Attributes:
        plant: ``"lipm"`` or ``"mujoco"``.
        backend: QP back-end.
        formulation: ``"dense"`` or ``"sparse"``.
        family: Problem family (controller) name.
        walk: Walk name.
        solve_times: QP solve time of every tick, shape (n,), in [s].
        tick_times: Whole generator tick (update + solve), shape (n,), in [s].
        failures: Ticks whose solve failed.
        max_consecutive_failures: Longest run of failed solves.
        completed: Whether the walk reached its end (no fall, no give-up).
        zmp_margin_min_m: Smallest margin of the executed ZMP (LIPM plant) or of the
            measured CoP (MuJoCo), in [m].
        metrics: Other walk metrics (MuJoCo runs), JSON-ready.
        error: What stopped the walk, or "".
    """

    plant: str
    backend: str
    formulation: str
    family: str
    walk: str
    solve_times: np.ndarray
    tick_times: np.ndarray
    failures: int
    max_consecutive_failures: int
    completed: bool
    zmp_margin_min_m: float
    metrics: dict = field(default_factory=dict)
    error: str = ""

    def summary(self) -> dict:
        """JSON-ready summary (times in [us])."""
        solve = self.solve_times * 1e6
        tick = self.tick_times * 1e6
        pick = lambda a, q: float(np.percentile(a, q)) if len(a) else float("nan")
        return {
            "plant": self.plant,
            "backend": self.backend,
            "formulation": self.formulation,
            "family": self.family,
            "walk": self.walk,
            "nb_ticks": len(tick),
            "solve_median_us": pick(solve, 50),
            "solve_p99_us": pick(solve, 99),
            "tick_median_us": pick(tick, 50),
            "tick_p99_us": pick(tick, 99),
            "failures": self.failures,
            "max_consecutive_failures": self.max_consecutive_failures,
            "completed": self.completed,
            "zmp_margin_min_m": self.zmp_margin_min_m,
            "metrics": self.metrics,
            "error": self.error,
        }


def push_schedule(
    duration: float, control_period: float, nb_pushes: int, speed: float, seed: int = 0
) -> dict[int, np.ndarray]:
    """Ticks of ``nb_pushes`` velocity pushes spread over the walk: tick -> dv [m/s]."""
    rng = np.random.default_rng(seed)
    pushes = {}
    for j in range(nb_pushes):
        tick = int(round((j + 1) / (nb_pushes + 1) * duration / control_period))
        angle = rng.uniform(0.0, 2.0 * np.pi)
        pushes[tick] = speed * np.array([np.cos(angle), np.sin(angle)])
    return pushes


def make_loop_generator(
    backend: str,
    formulation: str,
    level: ToleranceLevel,
    family: str = "mpc",
    control_period: float = 0.01,
):
    """The family's generator with ``backend`` at ``level`` as its QP solver."""
    from mpcwalk.generators import make_generator

    fam = get_family(family)
    return make_generator(
        fam.generator,
        control_period=control_period,
        solver=backend,
        formulation=formulation,
        solver_settings=backend_settings(backend, level),
        **fam.generator_options(),
    )


def run_lipm_loop(
    backend: str,
    formulation: str,
    level: ToleranceLevel,
    *,
    family: str = "mpc",
    walk: str = "turning",
    nb_steps: int = 20,
    control_period: float = 0.01,
    nb_pushes: int = 3,
    push_speed: float = 0.1,
    seed: int = 0,
) -> LoopRun:
    """Closed loop on the LIPM with pushes; never raises on a solver failure."""
    fam = get_family(family)
    schedule = walk_schedule(fam.timing, walk, nb_steps)
    pushes = push_schedule(schedule.duration, control_period, nb_pushes, push_speed, seed)
    solve, ticks, zmp, times = [], [], [], []
    failures = run = worst = 0
    error = ""
    try:
        generator = make_loop_generator(backend, formulation, level, family, control_period)
        out = generator.reset(schedule)
        tick = 0
        while not generator.done:
            velocity = out.com_velocity + pushes.get(tick, 0.0)
            measured = ComState(out.com, velocity, out.com_acceleration)
            start = time.perf_counter()
            out = generator.step(measured)
            ticks.append(time.perf_counter() - start)
            solve.append(out.solve.solve_time if out.solve is not None else 0.0)
            ok = out.solve is None or out.solve.success
            failures += not ok
            run = 0 if ok else run + 1
            worst = max(worst, run)
            zmp.append(out.zmp)
            times.append(out.time)
            tick += 1
    except MpcwalkError as exc:
        error = " ".join(str(exc).split())[:160]
    except Exception as exc:
        error = f"{type(exc).__name__}: {' '.join(str(exc).split())[:140]}"
    margin = (
        float(np.min(support_margins(schedule, np.array(times), np.array(zmp))))
        if times
        else float("nan")
    )
    return LoopRun(
        "lipm",
        backend,
        formulation,
        family,
        walk,
        np.array(solve),
        np.array(ticks),
        failures,
        worst,
        not error,
        margin,
        error=error,
    )


def mujoco_walk_runner():
    """The project's MuJoCo walk runner (``mpcwalk.walking.runner.run_walk``), or None
    where it is missing (the benchmark then skips the MuJoCo walks)."""
    try:
        from mpcwalk.walking.runner import run_walk
    except ImportError:
        return None
    return run_walk


def run_mujoco_loop(
    backend: str,
    formulation: str,
    level: ToleranceLevel,
    *,
    robot: str = "bioloid-like",
    walk: str = "turning",
    nb_steps: int = 20,
    control_period: float = 0.01,
) -> LoopRun | None:
    """MuJoCo walk of ``robot`` with ``backend`` as the MPC's solver (``mpcwalk walk``'s
    settings: the robot preset's gait and MPC parameters); None without a walk runner.

    The per-tick times are the generator's (QP update and solve) as the walk log records
    them; a crash of the back-end or a give-up of the MPC ends the walk as a failure.
    """
    from mpcwalk.footsteps.velocity_planner import VelocityCommand

    run_walk = mujoco_walk_runner()
    if run_walk is None:
        return None
    from mpcwalk.bench.solvers.problems.families import WALKS
    from mpcwalk.walking.specification import WalkSpec

    command: VelocityCommand = WALKS[walk]
    empty = np.zeros(0)
    try:
        spec = WalkSpec.build(
            robot,
            generator="mpc",
            command=(command.vx, command.vy, command.vyaw),
            nb_steps=nb_steps,
            control_period=control_period,
            generator_options={
                "solver": backend,
                "formulation": formulation,
                "solver_settings": backend_settings(backend, level),
            },
        )
        result = run_walk(spec)
    except Exception as exc:
        text = f"{type(exc).__name__}: {' '.join(str(exc).split())[:140]}"
        return LoopRun(
            "mujoco",
            backend,
            formulation,
            "mpc",
            walk,
            empty,
            empty,
            0,
            0,
            False,
            float("nan"),
            error=text,
        )
    log, m = result.log, result.metrics
    failed = np.asarray(log.generator_failed, dtype=bool)
    worst = run = 0
    for f in failed:
        run = run + 1 if f else 0
        worst = max(worst, run)
    keep = (
        "fell",
        "fall_reason",
        "steps_planned",
        "steps_completed",
        "foot_position_error_cm_max",
        "cop_margin_min_m",
        "cop_margin_p05_m",
        "com_error_rms_m",
        "real_time_factor",
        "controller_tick_us_median",
    )
    metrics = {k: m[k] for k in keep}
    return LoopRun(
        "mujoco",
        backend,
        formulation,
        "mpc",
        walk,
        np.asarray(log.generator_tick, dtype=float),
        np.asarray(log.generator_tick, dtype=float),
        int(failed.sum()),
        worst,
        not result.fall.fell,
        float("nan") if m.cop_margin_min_m is None else m.cop_margin_min_m,
        metrics=metrics,
        error=result.fall.reason if result.fall.fell else "",
    )


def loop_table(runs: Sequence[dict]) -> str:
    """Markdown table of loop summaries."""
    lines = [
        "| plant | back-end | formulation | ticks | solve median [us] | solve p99 [us] | "
        "tick median [us] | tick p99 [us] | failed solves | longest failure run | "
        "walk completed | min ZMP margin [mm] |",
        "|---" * 12 + "|",
    ]
    for r in runs:
        lines.append(
            f"| {r['plant']} | {r['backend']} | {r['formulation']} | {r['nb_ticks']} | "
            f"{r['solve_median_us']:.0f} | {r['solve_p99_us']:.0f} | {r['tick_median_us']:.0f} | "
            f"{r['tick_p99_us']:.0f} | {r['failures']} | {r['max_consecutive_failures']} | "
            f"{'yes' if r['completed'] else 'no: ' + r['error'][:60]} | "
            f"{1e3 * r['zmp_margin_min_m']:.1f} |"
        )
    return "\n".join(lines)


def mujoco_table(runs: Sequence[dict]) -> str:
    """Markdown table of MuJoCo walk summaries."""
    lines = [
        "| back-end | formulation | ticks | generator tick median [us] | p99 [us] | "
        "failed solves | longest failure run | fell | steps | foot error max [cm] | "
        "CoP margin p05 [mm] | real-time factor |",
        "|---" * 12 + "|",
    ]
    for r in runs:
        m = r.get("metrics") or {}
        fell = "yes: " + (m.get("fall_reason") or r["error"])[:50] if not r["completed"] else "no"
        num = lambda v, f="{:.1f}", s=1.0: "-" if v is None else f.format(s * v)
        lines.append(
            f"| {r['backend']} | {r['formulation']} | {r['nb_ticks']} | "
            f"{r['tick_median_us']:.0f} | {r['tick_p99_us']:.0f} | {r['failures']} | "
            f"{r['max_consecutive_failures']} | {fell} | "
            f"{m.get('steps_completed', '-')}/{m.get('steps_planned', '-')} | "
            f"{num(m.get('foot_position_error_cm_max'))} | "
            f"{num(_cop_margin_p05(m), s=1e3)} | {num(m.get('real_time_factor'))} |"
        )
    return "\n".join(lines)


def _cop_margin_p05(metrics: dict) -> float | None:
    """The CoP margin's 5th percentile [m] of a walk's metrics (``zmp_margin_p05_m`` in the
    results written before the key said CoP)."""
    value = metrics.get("cop_margin_p05_m")
    return metrics.get("zmp_margin_p05_m") if value is None else value
