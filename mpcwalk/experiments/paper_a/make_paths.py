"""Write the footstep paths of paper A's two experiments (straight.mdat, turning.mdat) and
a 3D one (ramp.mdat, with the terrain it crosses, ramp.toml).

Paper A (Atlas in the DARPA VRC) walked hand-made paths: a straight walk with
constant orientation and a turning walk started with the body turned 90 deg
to the right; both begin with two steps in place. The paths here are made
with the velocity planner and Atlas-like leg limits, one waypoint per step,
so each line changes one foot. Paper A's files hold each foot's full pose (height and
quaternion), and the paper notes that the feet's orientation "can be adjusted easily, which
is advantage on uneven terrain walk": the ramp path is the straight one placed on a 5 deg
ramp up, a landing and a ramp down (:data:`RAMP`), each sole at its height and pitched as
the ground under it. With mpcwalk installed (or ``PYTHONPATH=.``), run
``python -m mpcwalk.experiments.paper_a.make_paths`` to regenerate the files in
``paths/`` beside this module.
"""

import math
from pathlib import Path

import numpy as np

from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, StepTiming
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.footsteps.mdat import PathWaypoint, write_mdat
from mpcwalk.footsteps.terrain_steps import place_on_terrain
from mpcwalk.footsteps.velocity_planner import VelocityCommand, VelocityPlanner
from mpcwalk.terrain import Slope, Terrain, TerrainReach, terrain_to_toml

HERE = Path(__file__).resolve().parent / "paths"
HALF_STANCE_WIDTH = 0.12  # [m] Atlas-like feet 0.24 m apart
STEP_LENGTH = 0.20  # [m] landing ahead of the support foot
NB_IN_PLACE = 2  # paper A: two steps in place to settle the initial stance
#: Atlas-like limits (the ATLAS_REACHABILITY rectangle in LegLimits terms).
ATLAS_LIMITS = LegLimits(
    max_step_forward=0.30,
    max_step_backward=0.15,
    max_step_lateral=0.16,
    max_step_yaw=0.4,
    max_step_yaw_inward=0.4,
    y_sep=0.09,
    half_stance_width=HALF_STANCE_WIDTH,
)
#: One step per second: velocities below are then per-step displacements.
UNIT_TIMING = StepTiming(step_duration=1.0)
#: The ground of the 3D path: 5 deg up over 0.8 m from 0.5 m ahead of the start (7 cm), a
#: 0.6 m landing, 5 deg down over 0.8 m, the floor again from 2.7 m.
RAMP = Terrain([Slope(0.5, 0.8, 5.0), Slope(1.9, 0.8, -5.0)], width=3.0)
#: The atlas-like robot's soles (length, width) [m] and leg (hip height above the soles in
#: its nominal posture) [m], which place the 3D path's soles on :data:`RAMP`.
ATLAS_SOLE = (0.26, 0.13)
ATLAS_LEG = 0.906


def _stance(yaw: float) -> list[Footstep]:
    """Feet side by side about the origin, body heading ``yaw`` [rad]."""
    dx, dy = -math.sin(yaw) * HALF_STANCE_WIDTH, math.cos(yaw) * HALF_STANCE_WIDTH
    left = Footstep(Side.LEFT, np.array([dx, dy, 0.0]), yaw)
    return [left, Footstep(Side.RIGHT, np.array([-dx, -dy, 0.0]), yaw)]


def _waypoints(command: VelocityCommand, nb_steps: int, yaw: float) -> list[PathWaypoint]:
    left, right = _stance(yaw)
    plan = VelocityPlanner(ATLAS_LIMITS, UNIT_TIMING).plan(
        command, nb_steps, initial_left=left, initial_right=right
    )
    return _with_steps_in_place(plan)


def _with_steps_in_place(plan: FootstepPlan) -> list[PathWaypoint]:
    """The stances of ``plan``, the first one repeated :data:`NB_IN_PLACE` times."""
    stances = plan.stances()
    stances[1:1] = [stances[0]] * NB_IN_PLACE
    return [PathWaypoint(_rounded(st[Side.LEFT]), _rounded(st[Side.RIGHT])) for st in stances]


def _rounded(foot: Footstep) -> Footstep:
    """Position rounded to the micrometre (readable file, no -0.0)."""
    return foot.moved(position=[round(float(v), 6) + 0.0 for v in foot.position])


def straight_path() -> list[PathWaypoint]:
    """Two steps in place, then 15 steps of 0.2 m forward (3.0 m) and a closing step."""
    return _waypoints(VelocityCommand(vx=STEP_LENGTH), 15, 0.0)


def turning_path() -> list[PathWaypoint]:
    """Start turned 90 deg right, two steps in place, then a quarter arc turning
    left (torso radius 1.2 m, 10 steps of 9 deg) back to heading +x, and a closing step."""
    nb_steps, radius = 10, 1.2
    dyaw = 0.5 * math.pi / nb_steps
    return _waypoints(VelocityCommand(vx=radius * dyaw, vyaw=dyaw), nb_steps, -0.5 * math.pi)


def ramp_path() -> list[PathWaypoint]:
    """The straight path's steps placed on :data:`RAMP`: each sole at the height of the
    ground under it, pitched as that ground (a sole over a ramp's foot rests on both tops,
    over its brow on the top under its centre), so the file's lines carry heights and
    tilted quaternions."""
    left, right = _stance(0.0)
    plan = VelocityPlanner(ATLAS_LIMITS, UNIT_TIMING).plan(
        VelocityCommand(vx=STEP_LENGTH), 15, initial_left=left, initial_right=right
    )
    reach = TerrainReach.for_leg(*ATLAS_SOLE, ATLAS_LEG)
    return _with_steps_in_place(place_on_terrain(plan, RAMP, reach, limits=ATLAS_LIMITS))


HEADER = {
    "straight": "Paper A straight walk (Atlas-like, feet 0.24 m apart): initial stance, two steps in\n"
    "place (repeated lines), 15 forward steps of 0.2 m (3.0 m), closing step; constant\n"
    "orientation. Generated by mpcwalk.experiments.paper_a.make_paths.",
    "ramp": "Paper A straight walk in 3D (Atlas-like, feet 0.24 m apart): the straight path's\n"
    "steps placed on ramp.toml (5 deg up over 0.8 m from x = 0.5 m, a 0.6 m landing, 5 deg\n"
    "down over 0.8 m), each sole at the ground's height and pitched as the ground under it.\n"
    "Generated by mpcwalk.experiments.paper_a.make_paths.",
    "turning": "Paper A turning walk (Atlas-like, feet 0.24 m apart): same start turned 90 deg to the\n"
    "right (yaw -pi/2), two steps in place (repeated lines), a quarter arc turning left\n"
    "(torso radius 1.2 m, 9 deg per step) to heading +x, closing step.\n"
    "Generated by mpcwalk.experiments.paper_a.make_paths.",
}


def main() -> None:
    for name, make in (("straight", straight_path), ("turning", turning_path), ("ramp", ramp_path)):
        write_mdat(HERE / f"{name}.mdat", make(), header=HEADER[name])
        print(f"wrote {name}.mdat")
    (HERE / "ramp.toml").write_text(
        "# The ground of ramp.mdat (mpcwalk.experiments.paper_a.make_paths.RAMP)\n"
        + terrain_to_toml(RAMP)
    )
    print("wrote ramp.toml")


if __name__ == "__main__":
    main()
