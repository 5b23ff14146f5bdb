"""Compare two QP back-ends in the loop: the same walk in MuJoCo with the linear MPC solved
by DAQP through its own workspace (the default) and by quadprog through qpsolvers.

    python examples/compare_qp_backends.py
"""

import mpcwalk

walk = mpcwalk.WalkSpec.build("bioloid-like", controller="mpc", command=(0.1, 0.0, 0.0), nb_steps=4)
for solver in ("daqp-direct", "quadprog"):
    # the same walk, one field changed: the generator's options (the controller: "custom")
    result = mpcwalk.run_walk(walk.replace(generator_options={"solver": solver}))
    m = result.metrics
    print(
        f"{solver:12s} fell {m.fell}, generator tick {m.generator_tick_us_median:.0f} us "
        f"(median), landings {m.foot_position_error_cm_max:.2f} cm max"
    )
