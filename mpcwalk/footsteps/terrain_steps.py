"""Footsteps placed on a terrain: the nominal landings moved along their headings onto tops
that hold the sole, within the legs' reach.

Each landing of a plan (the velocity planner's, on the flat floor) is carried along with the
offset the terrain gave its support foot (the robot keeps the commanded stride, not the
commanded schedule: a walk slowed by a flight of stairs does not rush afterwards), then
moved along its heading, every :data:`~mpcwalk.footsteps.terrain_tops.SEARCH_STEP`, to the
place nearest to it (forward first when two are as near) that

- holds the sole (:class:`~mpcwalk.footsteps.terrain_tops.TerrainTops`: the whole sole on
  one top with the tread margin, or resting on the highest block of a rough patch, wholly
  on one block preferred by half a sole length);
- is within ``reach.max_rise`` of the support foot's height, within
  ``reach.max_swing_rise`` of the swing foot's lift-off height (unless the support foot's
  own rise is larger), and at most
  ``reach.max_stride`` ahead of it (beyond the flat legs' ``max_step_forward``: stairs
  whose run exceeds the flat stride are still climbed) or ``limits.max_step_backward``
  behind;
- lies on the support foot's top or the next one ahead (no tread or stone is skipped).

On treads and stones, one or two feet per top as the geometry allows: from a tread, the
landing goes onto the next one when it is within reach (step-over, one foot per tread:
the swing foot then climbs two rises, so high stairs are climbed two feet per tread), else
the second foot joins the first on its tread; at the end of a top the landing moves
onto the next one. The closing step joins the support foot on its top. A landing that
crosses onto another top, level or up, with a stride beyond the flat legs'
``limits.max_step_forward`` crosses as short as it can
(:meth:`TerrainStepPlacer._shortest_crossing`): the foot first lands at the front of its own
top when it still advances there by half a sole within the flat reach (two feet on that
top), and the crossing lands at the nearest place of the next top that keeps the margin it
prefers. The count of steps is the caller's: the robot walks as far as those steps go. The
footstep's height is the sole centre's on its top, its roll and pitch the top's tilt under
its heading (:meth:`~mpcwalk.terrain.Terrain.sole_support`).
"""

from dataclasses import replace

import numpy as np

from mpcwalk.exceptions import ConfigurationError, InfeasibleStep
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.footsteps.terrain_tops import SEARCH_STEP, Place, TerrainTops
from mpcwalk.terrain import Terrain, TerrainReach

#: Preference [share of the sole length] of a place wholly on one block of a rough patch.
ROUGH_PREFERENCE = 0.5
_EPS = 1e-9
#: Drop [m] below the swing foot's lift-off height from which a landing is a step down.
DESCENT_MIN = 0.005


#: Advance [share of the sole length] a foot must still make on its own top, within the flat
#: reach, to land there before a crossing beyond the flat reach (a step that shortens the
#: crossing by less is not worth its time).
CROSSING_ADVANCE = 0.5
#: Margin to a top's edges [share of the sole length] a landing prefers: on a tread or a stone
#: the landing moves towards the middle until it has it (a landing error of a few centimetres
#: must not put a heel on a nose).
PREFERRED_MARGIN = 0.25
#: Metres of distance from the nominal landing one metre of missing margin is worth.
MARGIN_WEIGHT = 2.0
#: Room [share of the sole length] a step down adds behind the heel to the margin it
#: prefers: the landing moves towards the front of the lower tread, so that a swing foot
#: falling a few centimetres short of its target (compliant servos, the stance leg bent
#: by the lowered CoM) does not put its heel on the nose it steps down from.
DESCENT_HEEL_ROOM = 0.2


def _heading(yaw: float) -> np.ndarray:
    return np.array([np.cos(yaw), np.sin(yaw)])


class TerrainStepPlacer:
    """Places footsteps on a terrain (see the module's documentation).

    Args:
        terrain: The ground.
        reach: What the legs and soles cross (sole size, tread margin, stride, rise).
        limits: The flat legs' reach; its ``max_step_backward`` bounds a landing behind the
            support foot.
    """

    def __init__(
        self, terrain: Terrain, reach: TerrainReach, limits: LegLimits = LegLimits()
    ) -> None:
        if not isinstance(terrain, Terrain) or not isinstance(reach, TerrainReach):
            raise ConfigurationError(
                f"Footsteps on a terrain need a Terrain and a TerrainReach, got "
                f"{type(terrain).__name__} and {type(reach).__name__}; e.g. "
                "TerrainReach.for_leg(sole_length, sole_width, leg_length)."
            )
        self.terrain, self.reach, self.limits = terrain, reach, limits
        self.tops = TerrainTops(terrain, reach)

    def place(self, plan: FootstepPlan, *, closing: bool = False) -> FootstepPlan:
        """``plan`` with every landing moved onto the terrain (``closing``: its last step
        puts the feet side by side). A flat terrain leaves the plan as it is.

        Raises:
            InfeasibleStep: A landing with no place within reach; the message names the
                step, the distance and the feature.
        """
        if self.terrain.is_flat:
            return plan
        feet = {Side.LEFT: plan.initial_left, Side.RIGHT: plan.initial_right}
        nominal = dict(feet)
        steps: list[Footstep] = []
        for k, step in enumerate(plan.steps):
            support = feet[step.side.other]
            heading = _heading(step.yaw)
            shift = float((support.xy - nominal[step.side.other].xy) @ heading)
            target = step.xy + shift * heading
            is_closing = closing and k == len(plan.steps) - 1
            place = self._choose(k, step, target, support, feet[step.side], is_closing)
            rest = self.tops.support(place.center, step.yaw)
            position = np.array([place.center[0], place.center[1], rest.height])
            landing = Footstep(step.side, position, step.yaw, rest.roll, rest.pitch)
            feet[step.side], nominal[step.side] = landing, step
            steps.append(landing)
        return replace(plan, steps=tuple(steps))

    def _places(
        self, step: Footstep, target: np.ndarray, support: Footstep, ahead: float
    ) -> list[Place]:
        """The places along the landing's heading from ``limits.max_step_backward`` behind
        the support foot to ``ahead`` [m] ahead of it (every :data:`SEARCH_STEP`)."""
        heading, support_heading = _heading(step.yaw), _heading(support.yaw)
        along = float(heading @ support_heading)
        if along <= 1e-3:  # a landing turned across the support foot: only its own place
            offsets = np.zeros(1)
        else:
            start = float((target - support.xy) @ support_heading)
            low = (-self.limits.max_step_backward - start) / along
            high = (ahead - start) / along
            offsets = SEARCH_STEP * np.arange(
                np.ceil(low / SEARCH_STEP - 1e-9), np.floor(high / SEARCH_STEP + 1e-9) + 1
            )
        centers = target + offsets[:, None] * heading
        strides = (centers - support.xy) @ support_heading
        return self.tops.places(centers, step.yaw, offsets, strides)

    def _within_reach(self, place: Place, support: Footstep, swing: Footstep) -> bool:
        rise = abs(place.height - float(support.position[2]))
        climb = abs(place.height - float(swing.position[2]))
        return (
            place.holds
            and rise <= self.reach.max_rise + _EPS
            and climb <= max(self.reach.max_swing_rise, rise) + _EPS
            and -self.limits.max_step_backward - _EPS <= place.stride
            and place.stride <= self.reach.max_stride + _EPS
        )

    def _preference(
        self, place: Place, yaw: float = 0.0, lift_height: float = -np.inf
    ) -> tuple[float, int]:
        penalty = 0.0
        if place.top[0] == "rough" and not place.wholly:
            penalty = ROUGH_PREFERENCE * self.reach.sole_length
        if place.top[0] == "top":  # treads, stones, landings: keep the sole off their edges
            wanted = PREFERRED_MARGIN * self.reach.sole_length
            if place.height < lift_height - DESCENT_MIN:
                margin = self._heel_room_margin(place, yaw)  # a step down
            else:
                margin = self.tops.support(place.center, yaw).margin
            penalty += MARGIN_WEIGHT * max(0.0, wanted - margin)
        return abs(place.offset) + penalty, 0 if place.offset >= 0.0 else 1

    def _heel_room_margin(self, place: Place, yaw: float) -> float:
        """Margin [m] to the top's edges of the sole lengthened behind its heel by
        :data:`DESCENT_HEEL_ROOM` (how a step down measures its place)."""
        room = DESCENT_HEEL_ROOM * self.reach.sole_length
        center = np.asarray(place.center, dtype=float) - 0.5 * room * _heading(yaw)
        return self.terrain.sole_support(
            center,
            yaw,
            self.reach.sole_length + room,
            self.reach.sole_width,
            self.tops.samples,
            self.reach.max_kink,
        ).margin

    def _choose(
        self,
        k: int,
        step: Footstep,
        target: np.ndarray,
        support: Footstep,
        swing: Footstep,
        closing: bool,
    ) -> Place:
        valid = [
            p
            for p in self._places(step, target, support, self.reach.max_stride)
            if self._within_reach(p, support, swing)
        ]
        own = self.tops.rests_on(support.xy, support.yaw)  # the support foot's top
        left = self.tops.rests_on(swing.xy, swing.yaw)  # the top the swing foot leaves
        first: dict = {}  # top -> nearest stride of its places
        for p in valid:
            first[p.top] = min(first.get(p.top, np.inf), p.stride)
        ahead = [top for top, stride in first.items() if top != own and stride > _EPS]
        following = min(ahead, key=lambda top: first[top]) if ahead else None
        allowed = {own, following, left}
        pool = [p for p in valid if p.top in allowed]
        if not pool:
            raise self._infeasible(k, step, target, support, own)
        lift = float(swing.position[2])

        def preference(p: Place) -> tuple[float, int]:
            return self._preference(p, step.yaw, lift)

        best = min(pool, key=preference)
        on_own = [p for p in pool if p.top == own]
        on_next = [p for p in pool if p.top == following]
        progress = float((target - support.xy) @ _heading(support.yaw))
        if closing and on_own:
            return min(on_own, key=preference)
        if progress > _EPS and best.top == own:
            stalled = best.stride <= _EPS
            if on_next and (self.tops.is_narrow(own) or stalled):
                best = min(on_next, key=preference)
            elif stalled and not on_next and left == own:
                raise self._infeasible(k, step, target, support, own)
        if closing or best.top == own or best.stride <= self.limits.max_step_forward + _EPS:
            return best
        return self._shortest_crossing(best, on_own, pool, step.yaw, lift)

    def _shortest_crossing(
        self, best: Place, on_own: list[Place], pool: list[Place], yaw: float, lift: float
    ) -> Place:
        """A crossing onto another top beyond the flat reach, level or up, made as short
        as the tops allow: a landing ahead of the support foot on its own top, by at least
        :data:`CROSSING_ADVANCE` of a sole and within the flat reach, with the tread margin
        (the crossing is then made from the front of that top); else the nearest place of
        ``best``'s top that keeps the margin :data:`PREFERRED_MARGIN` asks, or ``best``'s
        when it has less, when it is nearer than ``best``. A step down keeps ``best``: it
        lands towards the front of the lower top (:data:`DESCENT_HEEL_ROOM`)."""
        if best.height < lift - DESCENT_MIN:  # a step down keeps the heel room it prefers
            return best
        flat, sole = self.limits.max_step_forward, self.reach.sole_length

        def margin(p: Place) -> float:
            return self.tops.support(p.center, yaw).margin

        ahead = [
            p
            for p in on_own
            if CROSSING_ADVANCE * sole - _EPS <= p.stride <= flat + _EPS
            and margin(p) >= self.tops.margin - _EPS
        ]
        if ahead:
            return max(ahead, key=lambda p: p.stride)
        # never less margin than the preferred landing's (a top of one and a half soles
        # keeps its landing centred)
        wanted = min(PREFERRED_MARGIN * sole, margin(best)) - _EPS
        kept = [p for p in pool if p.top == best.top and margin(p) >= wanted]
        nearest = min(kept, key=lambda p: p.stride, default=best)
        return nearest if nearest.stride < best.stride else best

    def _infeasible(
        self, k: int, step: Footstep, target: np.ndarray, support: Footstep, own
    ) -> InfeasibleStep:
        """The error of a landing with no place within reach: the nearest place ahead that
        holds the sole, how far and how high it is, and its feature."""
        reach = self.reach
        places = self._places(step, target, support, reach.max_stride + max(1.0, reach.max_stride))
        beyond = [p for p in places if p.holds and p.top != own and p.stride > _EPS]
        where = f"from the support foot at x = {support.xy[0]:.3f} m"
        if not beyond:
            found = "finds no top ahead that holds its sole (the terrain ends)"
        else:
            p = min(beyond, key=lambda place: place.stride)
            rise = p.height - float(support.position[2])
            found = (
                f"finds the nearest top that holds its sole {p.stride:.3f} m ahead and "
                f"{rise:+.3f} m up, on {self.tops.describe(p.top)}"
            )
        return InfeasibleStep(
            f"Step {k} ({step.side.value} foot) has no place on the terrain within reach: "
            f"{where}, it {found}; its legs reach {reach.max_stride:.3f} m ahead and "
            f"{reach.max_rise:.3f} m up or down, with the sole {reach.tread_margin:.3f} m "
            "from a top's edges. Shorten the gap or the rise, or walk a robot with longer "
            "legs (TerrainReach.for_leg)."
        )


def place_on_terrain(
    plan: FootstepPlan,
    terrain: Terrain,
    reach: TerrainReach,
    *,
    limits: LegLimits = LegLimits(),
    closing: bool = False,
) -> FootstepPlan:
    """One-call form of :meth:`TerrainStepPlacer.place`."""
    return TerrainStepPlacer(terrain, reach, limits).place(plan, closing=closing)


__all__ = [
    "CROSSING_ADVANCE",
    "DESCENT_HEEL_ROOM",
    "DESCENT_MIN",
    "ROUGH_PREFERENCE",
    "TerrainStepPlacer",
    "place_on_terrain",
]
