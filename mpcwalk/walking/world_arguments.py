"""The ``mpcwalk walk`` options of the sensors, the state source and the perturbed world.

They map one to one onto the keywords of :func:`~mpcwalk.walking.runner.run_walk`, which
validates them (:class:`~mpcwalk.walking.world_options.WorldOptions`); the experiments' scripts
reuse them.
"""

import argparse

from mpcwalk.exceptions import ConfigurationError


def add_world_arguments(p: argparse.ArgumentParser) -> None:
    """The options of the sensors, the state source and the perturbed world
    (:class:`~mpcwalk.walking.world_options.WorldOptions`)."""
    world = p.add_argument_group(
        "sensors and world",
        "The controller walks on the state estimated from the robot's sensors (IMU, "
        "encoders, foot force/torque sensors, with the noise of the robot's sensor model and "
        "one control period of latency); the simulated robot may differ from the "
        "controller's model.",
    )
    world.add_argument(
        "--noise-scale",
        type=float,
        default=1.0,
        metavar="X",
        help="factor on the noise and bias of the sensor model (0: exact sensors)",
    )
    world.add_argument(
        "--latency",
        type=float,
        default=None,
        metavar="S",
        help="sensing-to-actuation latency [s], a multiple of --control-period "
        "(default: one control period)",
    )
    world.add_argument(
        "--ideal",
        action="store_true",
        help="exact sensors, no latency, the controller on the simulator's ground truth "
        "(the simulator before sensing; with --state estimator: the estimator on exact "
        "sensors)",
    )
    world.add_argument(
        "--state",
        choices=("estimator", "oracle"),
        default=None,
        help="what the controller reads: the state estimated from the sensors, or the "
        "simulator's ground truth, for comparison (default: estimator; oracle with --ideal)",
    )
    world.add_argument(
        "--mass-scale",
        type=float,
        default=1.0,
        metavar="X",
        help="factor on the torso mass of the simulated robot (not of the controller's model)",
    )
    world.add_argument(
        "--com-offset",
        default="0,0",
        metavar="DX,DY",
        help="shift of the torso's CoM of the simulated robot [m], forward and left",
    )
    world.add_argument(
        "--friction",
        type=float,
        default=None,
        metavar="MU",
        help="friction coefficient of the feet on the floor (default: the robot model's)",
    )
    world.add_argument(
        "--servo-strength",
        type=float,
        default=1.0,
        metavar="X",
        help="factor on the servos' gains and torque limits of the simulated robot",
    )
    world.add_argument(
        "--seed", type=int, default=0, metavar="N", help="seed of the sensor noise and the bumps"
    )
    add_ground_arguments(world)


def add_ground_arguments(group) -> None:
    """The options of the simulated ground (:class:`~mpcwalk.robot.ground.Ground`), in the
    sensors and world group."""
    group.add_argument(
        "--ground-tilt",
        type=float,
        default=0.0,
        metavar="DEG",
        help="slope of the simulated ground [deg], up towards --ground-tilt-direction",
    )
    group.add_argument(
        "--ground-tilt-direction",
        type=float,
        default=0.0,
        metavar="DEG",
        help="azimuth of the uphill direction [deg] (0: the robot's forward, 90: its left)",
    )
    group.add_argument(
        "--ground-roughness",
        type=float,
        default=0.0,
        metavar="M",
        help="largest height of the ground's random bumps [m] (a height field; 0: flat)",
    )


def ground_options(args) -> dict:
    """The keyword arguments of :func:`~mpcwalk.walking.runner.run_walk` of the ground
    options."""
    return {
        "ground_tilt": args.ground_tilt,
        "ground_tilt_direction": args.ground_tilt_direction,
        "ground_roughness": args.ground_roughness,
    }


def world_options(args) -> dict:
    """The keyword arguments of :func:`~mpcwalk.walking.runner.run_walk` of the sensor and
    world options.

    Raises:
        ConfigurationError: A ``--com-offset`` that is not two numbers.
    """
    text = str(args.com_offset)
    try:
        dx, dy = (float(part) for part in text.split(","))
    except ValueError:
        raise ConfigurationError(
            f"--com-offset takes two numbers DX,DY in metres, got {text!r}; "
            "e.g. --com-offset 0.01,0 shifts the torso's CoM 1 cm forward."
        ) from None
    return {
        "noise_scale": args.noise_scale,
        "latency": args.latency,
        "ideal": args.ideal,
        "state": args.state,
        "mass_scale": args.mass_scale,
        "com_offset": (dx, dy),
        "friction": args.friction,
        "servo_strength": args.servo_strength,
        "seed": args.seed,
    }
