"""`mpcwalk bench loop`: whole-loop timing per robot, reduced."""

import math

from mpcwalk.bench.loop import format_loop_table, run_loop_benchmark


def test_loop_benchmark_reduced_run():
    cases = run_loop_benchmark(
        walks=(("bioloid-like", "mpc", (0.1, 0.0, 0.0), 2, None),), progress=False
    )
    (case,) = cases
    assert not case.fell and case.steps_completed == 3  # 2 steps and the closing one
    assert case.time_simulated_s > 3.0 and case.real_time_factor > 0.0
    assert case.step_duration_s == 0.5  # the preset's (None in the walk tuple)
    for tick in (
        case.generator_tick_us,
        case.ik_tick_us,
        case.controller_tick_us,
        case.estimator_tick_us,
        case.mujoco_step_us,
    ):
        assert math.isfinite(tick) and tick > 0.0  # every stage was timed
    assert case.distance_m > 0.05 and case.foot_position_error_cm_max < 2.0
    assert case.cop_margin_p05_m > 0.0  # the measured CoP stays inside the soles
    table = format_loop_table(cases)
    assert table.count("\n") == 6
    # the table shows this run's numbers
    row = f"| {case.distance_m:.3f} ({case.distance_planned_m:.3f}) |"
    assert row in table and f"| {100 * case.cop_margin_p05_m:.2f} |" in table
    # the floor: the same robot standing, MuJoCo alone, then with the sensors; both above the
    # whole loop's real-time factor (they are part of it)
    assert case.physics_floor_rtf > case.simulation_floor_rtf > case.real_time_factor
    timing = (
        f"| {case.real_time_factor:.1f} | {case.physics_floor_rtf:.0f} / "
        f"{case.simulation_floor_rtf:.0f} | {case.estimator_tick_us:.0f} | "
        f"{case.generator_tick_us:.0f} |"
    )
    assert timing in table
    overhead = case.controller_tick_us - case.generator_tick_us - case.ik_tick_us
    assert case.controller_overhead_us == overhead
    assert f"| {case.controller_tick_us:.0f} | {overhead:.0f} |" in table
