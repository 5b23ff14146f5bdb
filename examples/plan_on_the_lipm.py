"""Plan a walk on the LIPM alone (no robot): footsteps from a velocity command, the contact
schedule, then the closed form and the linear MPC on the same plan, and their ZMP margins.

    python examples/plan_on_the_lipm.py
"""

from mpcwalk import (
    LIPM,
    ContactSchedule,
    VelocityCommand,
    VelocityPlanner,
    make_generator,
    rollout,
    support_margins,
)

plan = VelocityPlanner().plan(VelocityCommand(vx=0.1, vy=0.0, vyaw=0.2), nb_steps=10)
schedule = ContactSchedule(plan)
for name in ("analytic", "mpc"):
    walk = rollout(make_generator(name, lipm=LIPM(com_height=0.23)), schedule)
    margins = support_margins(schedule, walk.times, walk.zmp)
    print(f"{name:9s} {len(walk.times)} ticks, smallest ZMP margin {1000 * margins.min():.1f} mm")
