"""`mpcwalk bench loop`: whole-loop timing per robot, reduced."""

from mpcwalk.bench.loop import format_loop_table, run_loop_benchmark


def test_loop_benchmark_reduced_run():
    cases = run_loop_benchmark(
        walks=(("bioloid-like", "mpc", (0.1, 0.0, 0.0), 2, None),), progress=False
    )
    (case,) = cases
    assert not case.fell and case.steps_completed == 3  # 2 steps and the closing one
    assert case.time_simulated_s > 3.0 and case.real_time_factor > 0.0
    for tick in (case.generator_tick_us, case.ik_tick_us, case.mujoco_step_us):
        assert 0.0 < tick < case.controller_tick_us + case.mujoco_step_us
    assert case.controller_tick_us > case.generator_tick_us
    assert case.distance_m > 0.05 and case.foot_position_error_cm_max < 2.0
    assert format_loop_table(cases).count("\n") == 6
