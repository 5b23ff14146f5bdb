"""The terrains of the experiment, sized for each robot, and one walk over them.

- :func:`stair_run`, :func:`stairs_terrain`, :func:`slope_terrain`,
  :func:`stones_terrain`, :func:`rough_terrain`: the terrains (features start
  ``config.approach`` ahead, the initial stance on level ground);
- :func:`walk_spec`: the walk over a terrain: a forward command whose nominal stride is a
  share of the stair run (one of ``config.stride_shares``, within the legs' flat reach; the planner
  moves the landings onto the treads), as many steps as the footsteps need to leave the
  terrain behind;
- :func:`terrain_walk`: walk it, its :data:`WALK_KEYS`; a terrain or walk the library
  refuses before anything runs is ``{"refused": "<message>"}`` (never an exception).
"""

import math
from typing import Any

from mpcwalk.exceptions import ConfigurationError, InfeasibleCommand, InfeasibleStep
from mpcwalk.experiments.terrain.config import TerrainConfig
from mpcwalk.terrain import RoughPatch, Slope, Stairs, SteppingStones, Terrain, TerrainReach

#: What a walk over a terrain measured (keys of its metrics).
WALK_KEYS = (
    "outcome",
    "fall_reason",
    "stop_reason",
    "steps_completed",
    "steps_planned",
    "landing_error_3d_cm_mean",
    "landing_error_3d_cm_max",
    "landing_height_error_cm_max",
    "tread_margin_cm_min",
    "swing_clearance_cm_min",
    "toe_stubs",
    "com_height_error_cm_rms",
)
#: Refusals: the library's named errors raised before a walk runs.
REFUSALS = (ConfigurationError, InfeasibleStep, InfeasibleCommand)
#: Most steps of one walk.
MAX_STEPS = 200
#: Share of the legs' flat forward reach the nominal stride keeps (clear of the bound).
REACH_SHARE = 0.99


def reach_of(robot: Any) -> TerrainReach:
    """What ``robot``'s legs and soles cross."""
    length, width = robot.sole_size
    return TerrainReach.for_leg(length, width, robot.leg_length)


def stair_run(robot: Any, config: TerrainConfig) -> float:
    """The run [m]: ``config.run_soles`` sole lengths, never under the sole with margins."""
    return max(config.run_soles * robot.sole_size[0], reach_of(robot).min_tread)


def stairs_terrain(robot: Any, config: TerrainConfig, rise: float) -> Terrain:
    """``nb_stairs`` steps of ``rise`` [m] up, a landing, as many down."""
    run = stair_run(robot, config)
    up = Stairs(config.approach, rise, run, config.nb_stairs)
    landing = config.landing_soles * robot.sole_size[0]
    return Terrain([up, Stairs(up.end + landing, -rise, run, config.nb_stairs)])


def slope_terrain(robot: Any, config: TerrainConfig) -> Terrain:
    """A slope of ``slope_deg`` up, a landing, the same slope down."""
    length = config.slope_length_legs * robot.leg_length
    up = Slope(config.approach, length, config.slope_deg)
    landing = config.landing_soles * robot.sole_size[0]
    return Terrain([up, Slope(up.end + landing, length, -config.slope_deg)])


def stones_terrain(robot: Any, config: TerrainConfig) -> Terrain:
    """Stones of ``stones_length_soles`` sole lengths, ``stones_gap_share`` of the leg
    apart, wide enough for both soles of the stance, over a pit."""
    length, width = robot.sole_size
    half_stance = max(abs(float(foot.xy[1])) for foot in robot.initial_feet())
    return Terrain(
        [
            SteppingStones(
                config.approach,
                count=config.stones_count,
                length=config.stones_length_soles * length,
                gap=config.stones_gap_share * robot.leg_length,
                width=2.0 * (half_stance + width),
                depth=config.stones_depth_share * robot.leg_length,
            )
        ]
    )


def rough_terrain(robot: Any, config: TerrainConfig) -> Terrain:
    """A patch of blocks of ``rough_block_soles`` sole lengths up to ``rough_height_share``
    of the leg high."""
    block = config.rough_block_soles * robot.sole_size[0]
    return Terrain(
        [
            RoughPatch(
                config.approach,
                length=config.rough_length_blocks * block,
                width=config.rough_width_blocks * block,
                block=block,
                height=config.rough_height_share * robot.leg_length,
                seed=config.seed,
            )
        ]
    )


def terrain_of(kind: str, robot: Any, config: TerrainConfig, rise: float | None = None) -> Terrain:
    """The terrain ``kind`` (``stairs`` with ``rise`` [m]) for ``robot``."""
    if kind == "stairs":
        return stairs_terrain(robot, config, float(rise or 0.0))
    builders = {"slope": slope_terrain, "stones": stones_terrain, "rough": rough_terrain}
    return builders[kind](robot, config)


def own_step_duration(robot: Any, controller: str) -> float:
    """The step duration [s] ``controller`` walks at by itself on ``robot`` (its
    generator's own, else the robot's gait)."""
    from mpcwalk.walking.controller_builder import walk_timing
    from mpcwalk.walking.specification import ControllerSpec, PlanSpec

    generator = ControllerSpec.named(controller).generator
    return float(walk_timing(generator, robot.gait, PlanSpec()).step_duration)


def walk_spec(
    robot: Any,
    controller: str,
    terrain: Terrain,
    config: TerrainConfig,
    step_duration: float,
    stride_share: float = 1.0,
) -> Any:
    """The walk of ``controller`` over ``terrain`` at ``step_duration`` [s] (a controller
    of ``config.own_timing``: at its own, :func:`own_step_duration`), its nominal stride
    ``stride_share`` of the stair run within the legs' flat reach (see the module's
    documentation).

    Raises:
        MpcwalkError: The terrain or the walk refused (:data:`REFUSALS`).
    """
    from mpcwalk.walking.specification import WalkSpec
    from mpcwalk.walking.walk_setup import check_walk_terrain, set_up_walk

    check_walk_terrain(robot, terrain)
    run = stride_share * stair_run(robot, config)
    stride = min(run, REACH_SHARE * robot.gait.max_step_forward)
    timing = {} if controller in config.own_timing else {"step_duration": step_duration}
    if not timing:  # the generator's own timing (paper A's 12 s), the command's too
        step_duration = own_step_duration(robot, controller)
    spec = WalkSpec.build(
        robot.name,
        controller=controller,
        terrain=terrain,
        command=(stride / step_duration, 0.0, 0.0),
        nb_steps=1,
        control_period=config.control_period,
        seed=config.seed,
        **timing,
    )
    end = max(feature.end for feature in terrain.features) + robot.sole_size[0]
    nb_steps = max(2, math.ceil(end / stride))
    while True:
        spec = spec.replace(nb_steps=nb_steps)
        plan = set_up_walk(spec, robot=robot).plan
        far = min(float(step.position[0]) for step in plan.steps[-2:])
        if far >= end or nb_steps >= MAX_STEPS:
            return spec
        nb_steps = min(MAX_STEPS, nb_steps + max(2, math.ceil((end - far) / stride)))


def terrain_walk(
    robot: Any,
    controller: str,
    terrain: Terrain,
    config: TerrainConfig,
    step_duration: float,
    stride_share: float = 1.0,
    *,
    side_view: Any = None,
) -> dict[str, Any]:
    """Walk ``controller`` over ``terrain`` (:func:`walk_spec`): its :data:`WALK_KEYS` and
    ``nb_steps``, or
    ``{"refused": message}`` when the library refuses the terrain or the walk before it
    runs. ``side_view``: a path where to draw the walk's side view. Any other exception
    (a crash while walking) propagates."""
    from mpcwalk.walking.runner import run_walk

    try:
        spec = walk_spec(robot, controller, terrain, config, step_duration, stride_share)
        result = run_walk(spec, robot=robot)
    except REFUSALS as error:
        return {"refused": " ".join(f"{type(error).__name__}: {error}".split())[:400]}
    metrics = result.metrics.to_dict()
    out = {key: metrics[key] for key in WALK_KEYS}
    out["nb_steps"] = spec.plan.nb_steps
    out["step_duration_s"] = result.config.step_duration_s
    if side_view is not None:
        draw_side_view(result, side_view)
    return out


def draw_side_view(result: Any, path: Any) -> None:
    """The side view of a walk on a terrain, small, at ``path``."""
    import matplotlib.pyplot as plt

    from mpcwalk.walking.side_view import plot_walk_side_view

    spec = result.spec
    title = (
        f"{result.robot}, {spec.controller.name}: T = {result.config.step_duration_s:g} s, "
        f"{result.metrics.outcome}"
    )
    figure = plot_walk_side_view(result.schedule, result.log, spec.world.terrain, title=title)
    figure.savefig(path, dpi=70)
    plt.close(figure)


def climbed(walk: dict[str, Any], config: TerrainConfig) -> bool:
    """A walk climbs: it walked to the end of its schedule (no fall, no stop), completed all
    its steps, and its largest 3D landing error is below ``config.climb_error_cm``."""
    if walk.get("refused") or walk.get("outcome") != "walked":
        return False
    error = walk.get("landing_error_3d_cm_max")
    return (
        walk["steps_completed"] >= walk["steps_planned"]
        and error is not None
        and error < config.climb_error_cm
    )


__all__ = [
    "REFUSALS",
    "WALK_KEYS",
    "climbed",
    "draw_side_view",
    "own_step_duration",
    "reach_of",
    "rough_terrain",
    "slope_terrain",
    "stair_run",
    "stairs_terrain",
    "stones_terrain",
    "terrain_of",
    "terrain_walk",
    "walk_spec",
]
