"""The registry of the experiments: :data:`EXPERIMENTS` (``mpcwalk experiment list``).

Each entry loads its :class:`~mpcwalk.experiments.protocol.Experiment` on demand (naming one
imports nothing of the others). A new experiment is one :class:`~mpcwalk.registry.Entry` here
(see ``docs/howto/add-experiment.md``).
"""

from mpcwalk.experiments.protocol import Experiment
from mpcwalk.registry import Entry, Registry


def _paper_m() -> Experiment:
    from mpcwalk.experiments.paper_m.experiment import PaperM

    return PaperM()


def _paper_a() -> Experiment:
    from mpcwalk.experiments.paper_a.experiment import PaperA

    return PaperA()


def _robustness() -> Experiment:
    from mpcwalk.experiments.robustness.experiment import Robustness

    return Robustness()


def _robustness_cadence() -> Experiment:
    from mpcwalk.experiments.robustness.experiment import RobustnessCadence

    return RobustnessCadence()


def _robustness_terrain() -> Experiment:
    from mpcwalk.experiments.robustness.experiment import RobustnessTerrain

    return RobustnessTerrain()


def _robustness_torque() -> Experiment:
    from mpcwalk.experiments.robustness.experiment import RobustnessTorque

    return RobustnessTorque()


def _push_map() -> Experiment:
    from mpcwalk.experiments.push_map.experiment import PushMap

    return PushMap()


def _push_map_torque() -> Experiment:
    from mpcwalk.experiments.push_map.experiment import PushMapTorque

    return PushMapTorque()


def _capture_map() -> Experiment:
    from mpcwalk.experiments.capture_map.experiment import CaptureMap

    return CaptureMap()


def _terrain() -> Experiment:
    from mpcwalk.experiments.terrain.experiment import TerrainExperiment

    return TerrainExperiment()


def _faults() -> Experiment:
    from mpcwalk.experiments.faults.experiment import Faults

    return Faults()


def _performance() -> Experiment:
    from mpcwalk.experiments.performance.experiment import Performance

    return Performance()


#: The experiments, by the name ``mpcwalk experiment run NAME`` takes (and ``results/NAME``).
EXPERIMENTS: Registry[Experiment] = Registry(
    "experiment",
    [
        Entry(
            "paper_m",
            "paper M's turning walk, disturbances, push sweep and speed, every controller",
            _paper_m,
        ),
        Entry(
            "paper_a",
            "paper A's foot placement table on the straight, turning and 3D ramp paths",
            _paper_a,
        ),
        Entry(
            "robustness",
            "the robustness matrix: every controller on every robot in perturbed worlds",
            _robustness,
        ),
        Entry(
            "robustness_terrain",
            "the robustness matrix's terrain factors alone (stairs, slope, stepping stones)",
            _robustness_terrain,
        ),
        Entry(
            "robustness_cadence",
            "the robustness matrix's terrain factors on every robot at the terrain cadence",
            _robustness_cadence,
        ),
        Entry(
            "robustness_torque",
            "the robustness matrix with the robots torque-controlled (inverse dynamics)",
            _robustness_torque,
        ),
        Entry(
            "push_map",
            "the largest push each controller survives per direction, phase and speed",
            _push_map,
        ),
        Entry(
            "push_map_torque",
            "the push maps in torque and in position mode, cell by cell",
            _push_map_torque,
        ),
        Entry(
            "capture_map",
            "the LIPM's push-recovery map of each robot with 0, 1 and 2 steps",
            _capture_map,
        ),
        Entry(
            "terrain",
            "the largest stair rise each controller climbs, slopes, stepping stones, rough ground",
            _terrain,
        ),
        Entry(
            "faults",
            "bad inputs refused, faults survived or stopped cleanly, interrupts, outputs",
            _faults,
        ),
        Entry(
            "performance",
            "where a control tick's time goes: a profile of whole walks",
            _performance,
        ),
    ],
    list_command="mpcwalk experiment list",
)


__all__ = ["EXPERIMENTS"]
