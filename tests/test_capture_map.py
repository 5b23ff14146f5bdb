"""The LIPM's push-recovery map along a robot's nominal walk."""

import pytest
from conftest import get_robot

from mpcwalk.experiments.capture_map import capture_map


@pytest.fixture(scope="module")
def cells():
    return capture_map(get_robot("bioloid-like"), nb_directions=8, nb_phases=6)


def test_more_steps_and_adapted_timing_never_recover_less(cells):
    assert len(cells) == 48
    for cell in cells:
        assert cell.fixed[0] <= cell.fixed[1] <= cell.fixed[2]
        for fixed, adaptive in zip(cell.fixed, cell.adaptive):
            assert adaptive >= fixed - 1e-12


def test_late_in_single_support_only_a_step_recovers_a_forward_push(cells):
    """Late in single support the DCM has left the stance sole towards the next footstep:
    standing cannot stop it, the step that is about to land can (measured 1.04 N s), and
    landing it earlier adds more (1.23 N s)."""
    late = next(c for c in cells if c.direction_deg == 0.0 and c.phase == 0.75)
    assert late.single_support
    assert late.fixed[0] == 0.0
    assert late.fixed[1] > 0.8
    assert late.adaptive[1] > late.fixed[1] + 0.1


def test_a_push_towards_the_stance_leg_is_held_by_the_ankle_alone(cells):
    """Early in single support, a push towards the stance leg: the swing leg may not cross,
    so the bound with steps is the ankle's (the same with 0, 1 and 2 steps at 0.5 s)."""
    cell = next(c for c in cells if c.phase == 0.25 and c.direction_deg == 90.0)
    assert cell.single_support
    assert cell.fixed[2] == pytest.approx(cell.fixed[0])
