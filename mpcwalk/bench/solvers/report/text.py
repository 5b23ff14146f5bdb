"""Text of ``report.md``: the headline and the sections around the tables."""

import math

import numpy as np

from mpcwalk.bench.solvers.config import SolverBenchConfig
from mpcwalk.bench.solvers.loops.plants import loop_table, mujoco_table
from mpcwalk.bench.solvers.results import in_set, select, shgeom_runtimes, success_rates


def headline(
    rows: list[dict], config: SolverBenchConfig, extras: dict, sections: dict[str, str]
) -> list[str]:
    """Bullet points with the numbers a reader wants first."""
    main = in_set(rows, "main")
    out = [
        f"{len({r['problem'] for r in rows})} problems, {len(rows)} solves recorded "
        f"({len({r['solver'] for r in rows})} back-ends)."
    ]
    for level in [lv for lv in ("mid", "default") if lv in config.levels][:1]:
        for formulation in config.formulations:
            sel = select(main, formulation=formulation, start="cold")
            if not sel:
                continue
            means = shgeom_runtimes(sel, level, config.time_limit)
            rates = success_rates(sel, [level])
            reliable = [s for s in means if rates[s][level] >= 95.0]
            best = sorted(reliable, key=lambda s: means[s][0])[:4]
            out.append(
                f"{formulation}, {level} accuracy, cold start, fastest back-ends that "
                "succeed on at least 95% of the problems (qpbenchmark shifted geometric "
                "mean relative to the best, success rate): "
                + ", ".join(f"{s} {means[s][0]:.1f} ({rates[s][level]:.0f}%)" for s in best)
            )
    for name in ("osqp-direct", "daqp", "casadi-qpoases"):
        sel = select(main, solver=name, start="cold")
        if not sel:
            continue
        levels = [lv for lv in config.levels if select(sel, tolerance=lv)]
        solver_rates = success_rates(sel, levels)[name]
        out.append(
            f"{name} success per level (cold, both formulations): "
            + ", ".join(f"{lv} {solver_rates[lv]:.0f}%" for lv in levels)
        )
    warm = [
        r
        for r in select(main, solver="osqp-direct", family=config.sweep_family, tolerance="default")
        if r["success"]
    ]
    if any(r["start"] == "warm" for r in warm):
        parts = []
        for formulation in config.formulations:
            cold = [
                r["runtime"]
                for r in warm
                if r["formulation"] == formulation and r["start"] == "cold"
            ]
            hot = [
                r["runtime"]
                for r in warm
                if r["formulation"] == formulation and r["start"] == "warm"
            ]
            if cold and hot:
                parts.append(
                    f"{formulation} {np.median(hot) * 1e6:.0f} us warm against "
                    f"{np.median(cold) * 1e6:.0f} us cold"
                )
        out.append(
            f"OSQP through its own API (vector-only updates, shifted warm start), "
            f"family `{config.sweep_family}`, median: " + "; ".join(parts) + "."
        )
    out.append(sections["growth_headline"] + ".")
    if "ticks" in extras and sections["ticks"]:
        out.append(sections["ticks"].split("\n\n")[-1])
    loops = (extras.get("loops") or {}).get("lipm", [])
    if loops:
        done = [r for r in loops if r["completed"] and r["failures"] == 0]
        fastest = min(loops, key=lambda r: r["solve_median_us"])
        out.append(
            f"In the loop (LIPM, {config.loop_pushes} pushes of {config.loop_push_speed} "
            f"m/s): {len(done)} of {len(loops)} back-end/formulation pairs walked to the "
            f"end without a failed solve; fastest median solve "
            f"{fastest['solve_median_us']:.0f} us ({fastest['backend']}, "
            f"{fastest['formulation']})."
        )
    mujoco = (extras.get("loops") or {}).get("mujoco", [])
    if mujoco:
        up = [r for r in mujoco if r["completed"]]
        fell = [f"{r['backend']} ({r['formulation']})" for r in mujoco if not r["completed"]]
        fastest = min(up or mujoco, key=lambda r: r["tick_median_us"])
        out.append(
            f"MuJoCo ({(extras.get('loops') or {}).get('mujoco_robot')}, "
            f"{config.loop_nb_steps} steps): {len(up)} of {len(mujoco)} pairs kept the "
            f"robot up"
            + (f" (fell or stopped: {', '.join(fell)})" if fell else "")
            + f"; fastest median generator tick {fastest['tick_median_us']:.0f} us "
            f"({fastest['backend']}, {fastest['formulation']})."
        )
    return out


def compose_report(
    rows: list[dict],
    config: SolverBenchConfig,
    extras: dict,
    figures: dict[str, str],
    sections: dict[str, str],
) -> str:
    """The whole report."""
    d = extras.get("durations", {})
    stages = ", ".join(f"{k} {v / 60:.1f} min" for k, v in d.items())
    workers = config.timing_workers
    timing_mode = (
        "one Ray timing actor (one CPU slot of the Ray instance, nothing else of the "
        "benchmark beside it) timed every solve, so no two timed solves overlapped"
        if workers == 1
        else f"{workers} Ray timing actors timed solves in parallel (timings "
        "taken in parallel: each solve shared the machine with another one)"
    )
    parts = [
        "# Solver benchmark on the walking QPs",
        f"Command: `{extras.get('command') or 'mpcwalk bench solvers --out DIR'}` "
        f"({sections['date']}; stages: {stages}).",
        f"Machine: {extras.get('machine', '')}. Timing: {timing_mode}; the untimed work "
        f"(reference walks, feasibility checks, qpbenchmark export) ran before, as Ray tasks, "
        f"{config.prep_workers} at a time; the tick benchmark and qpbenchmark ran each on a "
        "fresh timing actor, the closed loops one Ray task at a time. Workers run single-threaded (OMP/BLAS/Rayon threads "
        "= 1). The machine was shared with another process running MuJoCo walks during the "
        "run: absolute times carry that load, ratios from the same run are the robust numbers.",
        "## Headline",
        "\n".join(f"- {line}" for line in headline(rows, config, extras, sections)),
        "## Problems",
        sections["problems"],
        "## Back-ends and settings",
        f"Every back-end installed: {', '.join(extras.get('backends', []))}. Left out as not "
        f"applicable (they need a positive definite cost, the sparse formulation's is "
        f"semidefinite): {sections['not_applicable'] or 'none'}. Warm-started (they take an "
        f"initial guess): {sections['warm']}. CasADi's Opti runs up to N = "
        f"{config.opti_max_horizon}. Time limit of one solve: {config.time_limit} s "
        "(qpbenchmark: 10 s); a back-end with no time limit of its own is killed after twice "
        "the limit per solve plus a set-up allowance, and a solve over the limit is a timeout, "
        "never a success. After two timeouts in a group (formulation, back-end, level, start, "
        "horizon), the rest of the group and longer horizons are recorded as skipped timeouts.",
        "<details><summary>Settings per tolerance level</summary>\n\n"
        + sections["settings"]
        + "\n\n</details>",
        "## Success rate per tolerance level",
        "Success (qpbenchmark): the back-end says it found a solution, and the primal residual, "
        "dual residual and duality gap, recomputed on the problem for every back-end the same "
        "way, are below the level's tolerance (default 1, low 1e-3, mid 1e-6, high 1e-9); "
        "runtime within the limit. Main set (each family at its own horizon)."
        + (f"\n\n![success rates]({figures['success']})" if "success" in figures else ""),
        sections["success"],
        "## Runtime: shifted geometric mean (qpbenchmark convention)",
        "Shift 10 s, a solve not found counts as the time limit, relative to the best back-end "
        "(absolute mean in brackets). With runtimes of micro- to milliseconds and a 10 s shift "
        "this mean is close to the arithmetic mean: the next sections give medians and p99. "
        'Known slow back-ends (marked "sampled" elsewhere: JAX-based, qpsolvers compiles a '
        "new solver at every call, over a second per solve) ran on one problem per family at "
        "default settings only and are left out of this mean.",
        sections["shgeom"],
        "## Runtime per family: medians and 99th percentiles",
        "### default settings",
        sections["family_default"],
    ]
    if sections.get("family_mid"):
        parts += ["### mid accuracy (1e-6)", sections["family_mid"]]
    parts += [
        "### Warm start against cold start",
        f"Family `{config.sweep_family}`, default settings "
        "(warm: after solving the preceding ticks of the walk).",
        sections["median_warm_cold"],
        "## Growth with the horizon",
        "Same 1.6 s horizon sampled from 0.1 s (N = 16) to 5 ms (N = 320): the dense "
        "formulation has 2N variables and a dense lower-triangular constraint matrix, the "
        "sparse one 8N variables and O(N) nonzeros. "
        + sections["growth_headline"]
        + "."
        + (f"\n\n![time vs horizon]({figures['horizon']})" if "horizon" in figures else ""),
        sections["growth"],
        "## Our fastest MPC tick against the closed form and qpmpc",
        "`mpcwalk.bench.ticks` in the same run (one process, after the solves): every "
        "generator on the same 20-step turning walk, update + solve per tick.",
        sections["ticks"],
        "## In the loop",
        in_loop_text(config, extras, figures),
        "## qpbenchmark test set",
        qpbenchmark_text(extras),
        "## Notes",
        "- Times are those of the back-end call (matrix and vector updates included, the QP's "
        "own update excluded: it is the same for every back-end). Cold: a fresh back-end object "
        "(OSQP set-up and factorisation included; the symbolic construction of a CasADi "
        "function is not timed, Opti's compilation at its first solve is). qpOASES through "
        "CasADi (conic and Opti) keeps its working set between calls: its warm solves are "
        "hot-started. Warm: the back-end first "
        "solves the preceding ticks of the walk, then the timed one from the shifted solution.",
        "- Residuals are recomputed on the OSQP form of each problem for every back-end; a "
        "back-end that gives no dual (or a dual we cannot map) fails every level.",
        "- Dense and sparse formulations are the same QP; the dense one is what DAQP, quadprog "
        "and qpOASES expect, the sparse one what sparse interior-point and ADMM solvers like.",
        "- Behaviours of back-ends met while building this benchmark: qpsolvers' `sip` "
        "interface edits its input matrices in place (`eliminate_zeros` on a matrix sharing the "
        "caller's arrays), so the benchmark hands every case fresh matrices; HiGHS counts its "
        "`time_limit` over the life of a solver object, so the CasADi HiGHS plugin (one object "
        "per QP) given a time limit fails every call after that much solving time, and none is "
        "set here; CasADi's ProxQP plugin has no duality-gap check, hence its low success at "
        "tight levels; qpOASES through CasADi keeps its working set between calls (automatic "
        "hot start) but is slow to start cold on the sparse formulation.",
    ]
    return "\n\n".join(p for p in parts if p) + "\n"


def in_loop_text(config: SolverBenchConfig, extras: dict, figures: dict[str, str]) -> str:
    loops = extras.get("loops") or {}
    runs = loops.get("lipm", [])
    text = (
        f"The MPC (family `mpc`, N = 32 at 50 ms) with each back-end fast enough offline "
        f"(median under {config.loop_backends_max_time * 1e3:.0f} ms on this QP) runs a "
        f"{config.loop_nb_steps}-step turning walk closed loop on the LIPM, with "
        f"{config.loop_pushes} velocity pushes of {config.loop_push_speed} m/s; default "
        "settings. A failed solve makes the MPC follow its previous plan; ten in a row stop "
        "the walk."
    )
    if runs:
        text += "\n\n" + loop_table(runs)
    if "ticks" in figures:
        text += f"\n\n![in-loop tick histograms]({figures['ticks']})"
    mujoco = loops.get("mujoco", [])
    if mujoco:
        text += (
            f"\n\n**MuJoCo**: the same back-ends as the MPC of `{loops.get('mujoco_robot')}`"
            f" walking {config.loop_nb_steps} steps (turning, 0.1 m/s and 20 deg/s) in "
            "MuJoCo through `mpcwalk.walking.runner.run_walk` (the `mpcwalk walk` job: whole-body IK, "
            "DCM feedback, position servos), default settings, no push. Tick: the "
            "generator's update and solve, from the walk log.\n\n" + mujoco_table(mujoco)
        )
        if "mujoco_ticks" in figures:
            text += f"\n\n![MuJoCo tick histograms]({figures['mujoco_ticks']})"
    elif not loops.get("mujoco_available"):
        text += (
            "\n\nMuJoCo walk per back-end: not run, `mpcwalk.walking.runner.run_walk` is missing "
            "here; `mpcwalk.bench.solvers.loops.plants.run_mujoco_loop` calls it."
        )
    return text


def qpbenchmark_text(extras: dict) -> str:
    text = (
        f"{extras.get('nb_exported', 0)} problems (both formulations) are exported in "
        "qpbenchmark's format to `qpbenchmark/data/*.npz`, with the test set class "
        "`MpcwalkQpbenchmark` in `qpbenchmark/mpcwalk_qpbenchmark.py`. Run qpbenchmark itself "
        "on them (needs `pip install mpcwalk[bench]`):\n\n"
        "```\ncd qpbenchmark\npython mpcwalk_qpbenchmark.py run            # every solver, "
        "all four settings\npython mpcwalk_qpbenchmark.py run --solver daqp --settings "
        "mid_accuracy\npython mpcwalk_qpbenchmark.py report --author <name>\n```"
    )
    q = extras.get("qpbenchmark")
    if not q:
        return text + "\n\nqpbenchmark was not run here."
    if "error" in q:
        return text + f"\n\nqpbenchmark run: {q['error']}."
    settings = ["default", "low_accuracy", "mid_accuracy", "high_accuracy"]
    body = []
    for solver in sorted(q["success"]):
        success, runtime = q["success"][solver], q["runtime"][solver]
        body.append(
            [solver]
            + [
                f"{success.get(s, math.nan):.0f}% / {runtime.get(s, math.nan):.1f}"
                for s in settings
            ]
        )
    table = ["| solver | " + " | ".join(settings) + " |", "|---" * (len(settings) + 1) + "|"]
    table += ["| " + " | ".join(row) + " |" for row in body]
    return (
        text + f"\n\nReduced run made here by qpbenchmark {q.get('version', '')} itself "
        f"(solvers: {', '.join(q.get('solvers', []))}; JAX-based ones left out for time): "
        "success rate / shifted geometric mean of runtime relative to the best, per "
        "settings. Its full report: `qpbenchmark/results/mpcwalk_qpbenchmark.md`.\n\n"
        + "\n".join(table)
    )
