"""Kajita's ZMP preview control on the cart-table model."""

import numpy as np
import pytest
from plans import arc_schedule

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.generators import make_generator, rollout
from mpcwalk.generators.preview import PreviewGenerator, compute_preview_gains
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM

COMMANDS = {  # torso displacement per step (dx [m], dy [m], dyaw [rad]) at T = 0.5 s
    "straight": (0.05, 0.0, 0.0),  # 0.1 m/s
    "turning": (0.05, 0.0, np.deg2rad(10.0)),  # 0.1 m/s, 20 deg/s
    "sideways": (0.0, 0.05, 0.0),  # 0.1 m/s to the left
}


@pytest.mark.parametrize("period, state_weight", [(0.01, 0.0), (0.01, 1e-3), (0.005, 0.0)])
def test_plain_gains_equal_brute_force_finite_horizon(period, state_weight):
    """Without integral action, u = -Gx x - Gd r is the first input of the
    finite-horizon least squares over N_L samples with terminal cost
    x^T (P - Qe C^T C - Qx) x."""
    model = CartTable(LIPM(0.23), period)
    N, Qe, R = int(round(1.6 / period)), 1.0, 1e-6
    gains = compute_preview_gains(
        model, N, zmp_weight=Qe, jerk_weight=R, state_weight=state_weight, integral_action=False
    )
    mats = model.prediction_matrices(N)
    Xs = np.stack([mats["Pps"], mats["Pvs"], mats["Pas"]], axis=1)  # (N, 3, 3)
    Xu = np.stack([mats["Ppu"], mats["Pvu"], mats["Pau"]], axis=1)  # (N, 3, N)
    rng = np.random.default_rng(0)
    for _ in range(3):
        x0 = rng.normal(size=3) * [0.05, 0.1, 0.5]
        r = rng.uniform(-0.1, 0.1, N)
        H = Qe * mats["Pzu"].T @ mats["Pzu"] + R * np.eye(N)
        f = Qe * mats["Pzu"].T @ (mats["Pzs"] @ x0 - r)
        H += state_weight * np.einsum("iku,ikv->uv", Xu, Xu)
        f += state_weight * np.einsum("iku,ik->u", Xu, Xs @ x0)
        W = gains.P - Qe * np.outer(model.C, model.C) - state_weight * np.eye(3)
        H += Xu[-1].T @ W @ Xu[-1]
        f += Xu[-1].T @ W @ Xs[-1] @ x0
        u_batch = np.linalg.solve(H, -f)[0]
        u_preview = -gains.Gx @ x0 - gains.Gd @ r
        # measured |difference| <= 1.5e-10 on inputs of 6 to 55 m/s^3
        assert u_preview == pytest.approx(u_batch, rel=1e-8)
    assert gains.spectral_radius < 1.0  # measured 0.943 (0.01 s), 0.971 (0.005 s)


@pytest.mark.parametrize("period, state_weight", [(0.01, 0.0), (0.01, 1e-3), (0.005, 0.0)])
def test_integral_gains_equal_brute_force_on_augmented_system(period, state_weight):
    """Kajita's gains: Delta u = -[Gi, Gx] [e; Delta x] - sum Gd[i] Delta r[i] is
    the first input of the finite-horizon problem on the augmented system with
    terminal cost P."""
    model = CartTable(LIPM(0.23), period)
    N, Qe, R = int(round(1.6 / period)), 1.0, 1e-6
    gains = compute_preview_gains(model, N, zmp_weight=Qe, jerk_weight=R, state_weight=state_weight)
    A, B, C = model.A, model.B, model.C
    At = np.zeros((4, 4))
    At[0, 0], At[0, 1:], At[1:, 1:] = 1.0, C @ A, A
    Bt, Et = np.r_[C @ B, B], np.r_[-1.0, 0.0, 0.0, 0.0]
    Qt = np.diag([Qe] + [state_weight] * 3)
    rng = np.random.default_rng(1)
    X0 = rng.normal(size=4) * [0.01, 0.001, 0.01, 0.1]
    dr = rng.normal(size=N) * 0.01
    H, f = R * np.eye(N), np.zeros(N)
    S, Su, d = np.eye(4), np.zeros((4, N)), np.zeros(4)
    for j in range(N):
        S, Su, d = At @ S, At @ Su, At @ d + Et * dr[j]
        Su[:, j] += Bt
        W = gains.P if j == N - 1 else Qt
        H += Su.T @ W @ Su
        f += Su.T @ W @ (S @ X0 + d)
    du_batch = np.linalg.solve(H, -f)[0]
    du_preview = -np.r_[gains.Gi, gains.Gx] @ X0 - gains.Gd @ dr
    assert du_preview == pytest.approx(du_batch, rel=1e-6)  # measured 1e-9 to 2e-8
    assert gains.Gd[0] == -gains.Gi
    assert gains.spectral_radius < 1.0  # measured 0.937 (0.01 s), 0.968 (0.005 s)


def test_tracks_reference_on_straight_ten_steps():
    schedule = arc_schedule(COMMANDS["straight"], 10)
    gen = PreviewGenerator(control_period=0.01)
    out = rollout(gen, schedule)
    err = np.abs(out.zmp - schedule.zmp_reference(out.times)).max()
    assert err < 0.01  # measured 0.0068 m
    assert support_margins(schedule, out.times, out.zmp).min() > 0.02  # measured 0.0233 m
    np.testing.assert_allclose(
        out.com[-1], schedule.torso_waypoints[-1], atol=1e-4
    )  # measured 2.3e-5
    # Finer control and sampling period: measured 0.0045 m.
    fine = rollout(PreviewGenerator(control_period=0.005), schedule)
    assert np.abs(fine.zmp - schedule.zmp_reference(fine.times)).max() < 0.006
    # Jerk held over 2 control periods (sampling_period = 0.01 s, outputs every 0.005 s).
    held = rollout(PreviewGenerator(control_period=0.005, sampling_period=0.01), schedule)
    assert np.abs(held.com[::2] - out.com).max() < 1e-12


@pytest.mark.parametrize("command", list(COMMANDS))
@pytest.mark.parametrize("integral_action", [True, False])
def test_zmp_inside_polygon_on_twenty_steps(command, integral_action):
    schedule = arc_schedule(COMMANDS[command], 20)
    out = rollout(PreviewGenerator(control_period=0.01, integral_action=integral_action), schedule)
    margin = support_margins(schedule, out.times, out.zmp).min()
    error = np.abs(out.zmp - schedule.zmp_reference(out.times)).max()
    # Measured min margin / max tracking error [m]:
    #   integral action: straight 0.0233 / 0.0068, turning 0.0233 / 0.0069,
    #                    sideways 0.0173 / 0.0127
    #   plain LQR:       straight 0.0162 / 0.0138, turning 0.0147 / 0.0169,
    #                    sideways -0.0012 / 0.0312 (leaves the polygon)
    if integral_action:
        assert margin > 0.015 and error < 0.015
    elif command == "sideways":
        assert -0.005 < margin < 0.0
    else:
        assert margin > 0.01 and error < 0.02


def test_feedback_with_own_output_equals_open_loop():
    schedule = arc_schedule(COMMANDS["turning"], 6)
    for kwargs in (
        {},
        {"integral_action": False},
        {"control_period": 0.005, "sampling_period": 0.01},
    ):
        open_loop = rollout(PreviewGenerator(**kwargs), schedule)
        closed = rollout(PreviewGenerator(**kwargs), schedule, feedback=True)
        assert np.abs(closed.com - open_loop.com).max() < 1e-9
        assert np.abs(closed.zmp - open_loop.zmp).max() < 1e-9


def test_measured_state_is_used_and_recovered_from():
    schedule = arc_schedule(COMMANDS["straight"], 6)
    reference = rollout(PreviewGenerator(), schedule)
    gen = PreviewGenerator()
    gen.reset(schedule)
    outs = []
    while not gen.done:
        measured = None
        if len(outs) == 150:  # push: +2 cm, +0.1 m/s sideways, acceleration unknown
            prev = outs[-1]
            measured = ComState(prev.com + [0.0, 0.02], prev.com_velocity + [0.0, 0.1])
        outs.append(gen.step(measured))
    com = np.array([o.com for o in outs])
    deviation = np.abs(com - reference.com[1:])[:, 1]
    assert deviation[150] > 0.015  # the push is taken into account
    # ... and rejected: by the end the CoM is back on the unpushed trajectory
    # (measured 1.4e-10 m). The unconstrained controller throws the ZMP 0.18 m
    # outside the polygon to do so.
    assert deviation[-1] < 1e-6


def test_integral_version_does_not_depend_on_world_origin():
    here = rollout(PreviewGenerator(), arc_schedule(COMMANDS["turning"], 6))
    offset = np.array([10.0, 5.0])
    there = rollout(PreviewGenerator(), arc_schedule(COMMANDS["turning"], 6, offset=offset))
    assert np.abs(there.com - here.com - offset).max() < 1e-9  # measured 1e-14


def test_horizon_predicts_the_closed_loop():
    schedule = arc_schedule(COMMANDS["straight"], 4)
    gen = PreviewGenerator(control_period=0.01)
    out = rollout(gen, schedule)
    gen.reset(schedule)
    # Once the preview window reaches past the end of the schedule the
    # reference is constant beyond it and the prediction is exact.
    k = int(round((schedule.duration - 1.6) / 0.01))
    for _ in range(k + 1):
        o = gen.step()
    h = o.horizon
    assert len(h.times) == 160
    np.testing.assert_allclose(h.times, out.times[k + 1 : k + 161])
    assert np.abs(h.com - out.com[k + 1 : k + 161]).max() < 1e-9
    np.testing.assert_allclose(h.zmp, schedule.zmp_reference(h.times))
    assert PreviewGenerator(predict_horizon=False).reset(schedule).horizon is None


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"sampling_period": 0.015}, "integer multiple"),
        ({"preview_time": 0.0}, "preview_time"),
        ({"jerk_weight": 0.0}, "positive"),
        ({"state_weight": -1.0}, "state_weight"),
    ],
)
def test_bad_parameters(kwargs, match):
    with pytest.raises(ConfigurationError, match=match):
        make_generator("preview", **kwargs)
