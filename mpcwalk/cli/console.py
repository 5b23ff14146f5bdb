"""The parsers' helpers (the help formatter, ``--out``'s type, negative numbers as values)
and what the commands print (lengths in millimetres, a walk's summary)."""

import argparse
import re
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from mpcwalk.walking.result import WalkResult

#: Options whose value may be a negative number ("--vx -1e-2" is read as "--vx=-1e-2").
_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


class HelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Shows an option's default in its help, unless it has none (None, a flag's False) or
    the help already says it."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        if action.default is None or action.default is False or action.default == []:
            return action.help
        if "default:" in (action.help or "") or action.default is argparse.SUPPRESS:
            return action.help
        return super()._get_help_string(action)


def use_formatter(parser: argparse.ArgumentParser) -> None:
    """Give ``parser`` and all its sub-command parsers the :class:`HelpFormatter`."""
    parser.formatter_class = HelpFormatter
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for child in action.choices.values():
                use_formatter(child)


def out_path(text: str) -> Path:
    """``--out``'s argument type: a non-empty path (``''`` would be the working folder)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("an output folder is needed, got an empty string")
    return Path(text)


def joined_negative_numbers(argv: list[str]) -> list[str]:
    """``--vx -0.05`` as ``--vx=-0.05``: argparse reads a negative number as an option."""
    out: list[str] = []
    for token in argv:
        if out and out[-1].startswith("--") and "=" not in out[-1] and _NUMBER.match(token):
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def format_length(value: float | None) -> str:
    """A length [m] in millimetres with three significant digits (4e-6 m: "0.004 mm")."""
    if value is None:
        return "n/a"
    digits = np.format_float_positional(
        1e3 * value, precision=3, unique=False, fractional=False, trim="-"
    )
    return f"{digits} mm"


def _format(value: float | None, unit: str = "") -> str:
    return "n/a" if value is None else f"{value:.2f}{unit}"


def summary(result: "WalkResult") -> str:
    """Two lines telling what was planned and simulated, and how the walk went."""
    m, config = result.metrics, result.config
    state = f"FELL at {m.fall_time_s:.2f} s ({m.fall_reason})" if m.fell else "no fall"
    if m.outcome in ("stopped", "interrupted"):
        state = f"{m.outcome.upper()} at {m.time_simulated_s:.2f} s"
    steps = f"{m.steps_planned} steps"
    if m.closing_steps:
        steps = f"{m.steps_planned - m.closing_steps} steps + {m.closing_steps} closing step"
    standing = m.time_planned_s - m.walking_time_planned_s
    asked = "" if config.duration_s is None else f" for --duration {config.duration_s:g} s"
    return (
        f"{result.robot} {result.generator}: planned {steps}{asked}, "
        f"{m.time_planned_s:.2f} s ({m.walking_time_planned_s:.2f} s walking, "
        f"{standing:.2f} s standing before and after); simulated {m.time_simulated_s:.2f} s\n"
        f"{state}; {m.steps_completed}/{m.steps_planned} steps completed, "
        f"{m.distance_m:.3f} m (planned {m.distance_planned_m:.3f} m), yaw "
        f"{m.yaw_change_deg:.1f} deg, foot error {_format(m.foot_position_error_cm_mean, ' cm')} "
        f"mean, CoP margin min {format_length(m.cop_margin_min_m)} (loaded soles), real time "
        f"x{_format(m.real_time_factor)}\n{_sensing(result)}{_terrain(result)}"
    )


def _terrain(result: "WalkResult") -> str:
    """One more line on a terrain: landings in 3D, tread margins, swings, CoM height."""
    m = result.metrics
    if m.landing_error_3d_cm_mean is None and m.com_height_error_cm_rms is None:
        return ""
    return (
        f"\nterrain: landing error 3D {_format(m.landing_error_3d_cm_mean, ' cm')} mean, "
        f"{_format(m.landing_error_3d_cm_max, ' cm')} max; tread margin min "
        f"{_format(m.tread_margin_cm_min, ' cm')}; swing clearance min "
        f"{_format(m.swing_clearance_cm_min, ' cm')}, toe stubs {m.toe_stubs}; CoM height "
        f"error RMS {_format(m.com_height_error_cm_rms, ' cm')}"
    )


def _sensing(result: "WalkResult") -> str:
    """One line on what the controller read and how well it knew the robot."""
    m, config = result.metrics, result.config
    sensors = "ideal sensors" if config.ideal_sensors else f"noise x{config.noise_scale:g}"
    text = f"state: {config.state_source} ({sensors}, latency {1e3 * config.latency_s:g} ms)"
    changed = {
        key: value
        for key, value in config.model_mismatch.items()
        if value not in (None, 1.0, [0.0, 0.0], (0.0, 0.0))
    }
    if changed:
        text += "; world: " + ", ".join(f"{key} {value}" for key, value in changed.items())
    if m.estimator_com_error_rms_m is not None:
        text += (
            f"; estimator CoM error RMS {format_length(m.estimator_com_error_rms_m)}, "
            f"max {format_length(m.estimator_com_error_max_m)} (relative to the support "
            f"{format_length(m.estimator_com_error_support_rms_m)}), yaw drift "
            f"{_format(m.estimator_yaw_drift_deg, ' deg')}"
        )
    return text
