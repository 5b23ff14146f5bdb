"""Walk a robot in MuJoCo from Python and read its metrics.

python examples/walk_a_robot.py
"""

import mpcwalk

result = mpcwalk.run_walk("bioloid-like", controller="mpc", command=(0.1, 0.0, 0.0), nb_steps=4)
m = result.metrics
print(f"fell: {m.fell}, steps {m.steps_completed}/{m.steps_planned}")
print(f"distance {m.distance_m:.3f} m of {m.distance_planned_m:.3f} m planned")
print(
    f"landings {m.foot_position_error_cm_mean:.2f} cm mean, {m.foot_position_error_cm_max:.2f} max"
)
print(f"CoP margin (5th percentile) {1000 * m.cop_margin_p05_m:.1f} mm")
print(f"real-time factor {m.real_time_factor:.1f}")
