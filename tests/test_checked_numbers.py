"""Gains and figures of the lower rooms go through one check (``_checks.checked_number``):
a negative, non-finite, boolean or string value is a named error that says what was
expected and what came."""

import pytest

from mpcwalk.control.stabilizers.ankle_imu import AnkleImuStabilizer
from mpcwalk.control.stabilizers.dcm_integrator import DcmIntegrator
from mpcwalk.control.stabilizers.gyro import GyroStabilizer
from mpcwalk.estimation.attitude_filter import AttitudeFilter
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.gait_defaults import GaitDefaults
from mpcwalk.robot.ground import Ground


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (
            lambda: GyroStabilizer(hip_roll=-0.1),
            r"GyroStabilizer hip_roll must be a number >= 0 s \(rad per rad/s\), got -0.1; "
            r"paper M uses",
        ),
        (
            lambda: DcmIntegrator(gain=float("nan"), limit=0.1),
            r"DcmIntegrator gain must be a number >= 0, got nan\.",
        ),
        (lambda: AnkleImuStabilizer(kd=True), r"AnkleImuStabilizer kd must be a number >= 0"),
        (lambda: AttitudeFilter(gain=-1.0), r"gain must be a number >= 0 rad/s, got -1.0\."),
        (
            lambda: GaitDefaults(step_height="0.04"),
            r"\[gait\] step_height must be a number >= 0, got '0.04'\.",
        ),
        (lambda: Ground(tilt=25.0), r"Ground.tilt must be a number in \[-20, 20\] deg, got 25.0"),
    ],
)
def test_bad_gains_and_figures_are_named_errors(build, message):
    with pytest.raises(ConfigurationError, match=message):
        build()
