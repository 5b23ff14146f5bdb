"""The terrain cadence: how much slower a walk steps when its terrain lengthens its steps.

On stairs and stepping stones the footsteps no longer follow the command: each landing goes
to the next tread or stone (:mod:`~mpcwalk.footsteps.terrain_steps`), so a step may advance a
whole run, or a stone and its gap, where the flat walk advances ``vx T``. At the preset's
step duration that is a walk several times faster than commanded: the G1 commanded at
0.1 m/s (0.06 m a step at T = 0.6 s) climbs 0.30 m treads one foot per tread, 0.50 m/s, past
its flat legs' top speed (0.20 m a step, 0.33 m/s).

:func:`cadence_stretch` is the factor ``k >= 1`` by which every step of such a plan is
lengthened so that no step advances faster than :data:`TERRAIN_CADENCE_SHARE` of the flat
legs' top speed (``max_step_forward / T``); a walk with the terrain cadence steps at
``k T`` with its command divided by ``k``, which plans the same footsteps (the strides are
``v T``), each step ``k`` times longer.
"""

from mpcwalk._checks import checked_number
from mpcwalk.footsteps.footstep import FootstepPlan

#: Share of the flat legs' longest step that a step of the terrain cadence advances at most
#: per (unstretched) step duration. Measured on the robustness matrix's stairs (3 treads of
#: 1.5 sole lengths up and down, `mpc` on the sensors): the G1 steps 0.30 m per step, 1.5
#: times its longest flat step; stretched to that step alone (k = 1.5, T = 0.9 s) its three
#: stair walks stop after 15 to 17 of 47 steps; at k = 2 (T = 1.2 s) all three walk 47/47.
TERRAIN_CADENCE_SHARE = 0.75


def largest_advance(plan: FootstepPlan) -> float:
    """The largest advance [m] of a landing ahead of its support foot, along the support
    foot's heading, over the plan's steps (0 without steps)."""
    advances = [
        float(stance[step.side.other].to_local(step.xy)[0])
        for step, stance in zip(plan.steps, plan.stances())
    ]
    return max([0.0, *advances])


def cadence_stretch(
    plan: FootstepPlan, max_step_forward: float, share: float = TERRAIN_CADENCE_SHARE
) -> float:
    """The factor ``k >= 1`` on the step duration that keeps every step of ``plan`` within
    ``share`` of the flat legs' top speed: ``max(1, largest advance / (share *
    max_step_forward))``.

    Args:
        plan: The footsteps (on a terrain).
        max_step_forward: The flat legs' longest step ahead [m]
            (:attr:`~mpcwalk.footsteps.leg_limits.LegLimits.max_step_forward`).
        share: Share of the flat legs' top speed a step may use, in (0, 1].
    """
    reach = checked_number("max_step_forward", max_step_forward, low=0.0, low_inclusive=False)
    share = checked_number("share", share, low=0.0, high=1.0, low_inclusive=False)
    return max(1.0, largest_advance(plan) / (share * reach))


__all__ = ["TERRAIN_CADENCE_SHARE", "cadence_stretch", "largest_advance"]
