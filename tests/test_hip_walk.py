"""The hip strategy in the closed loop: ``mpc-hip`` walks through a forward push on the small
humanoid that the linear MPC (``mpc``) and the same footstep and timing adaptation without the
flywheel (``mpc-timing``) fall from.

Measured (0.1 s pushes at 1.6 s, forward, 6-step walk): ``mpc`` falls at 6 N; ``mpc-timing``
walks through 6 N and falls at 6.5 N; ``mpc-hip`` walks through 7 N and falls at 7.5 N."""

import pytest

import mpcwalk

#: 7 N for 0.1 s on the torso at 1.6 s (single support of the third step), forward.
PUSH = (1.6, 0.1, 7.0, 0.0, 0.0)


def _walk(controller: str) -> mpcwalk.WalkResult:
    spec = mpcwalk.WalkSpec.build(
        "bioloid-like", controller=controller, command=(0.1, 0.0, 0.0), nb_steps=6, pushes=[PUSH]
    )
    return mpcwalk.run_walk(spec)


@pytest.mark.slow
def test_mpc_hip_recovers_a_push_mpc_and_mpc_timing_fall_from():
    assert _walk("mpc").metrics.fell
    assert _walk("mpc-timing").metrics.fell
    hip = _walk("mpc-hip")
    assert not hip.metrics.fell
    assert hip.metrics.steps_completed == hip.metrics.steps_planned
