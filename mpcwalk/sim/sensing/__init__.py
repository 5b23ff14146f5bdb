"""What the simulated robot senses: the truth through its sensors' imperfections.

- :mod:`~mpcwalk.sim.sensing.model`: :class:`SensorModel`, the figures of a robot's sensors
  (noise, bias, quantisation, latency);
- :mod:`~mpcwalk.sim.sensing.simulator`: :class:`SensorSimulator`, which applies them to the
  exact readings of each control period;
- :mod:`~mpcwalk.sim.sensing.faults`: :class:`SensorFaults`, NaN and dropped readings
  injected into a walk.
"""

from mpcwalk.sim.sensing.faults import SensorFaults, readings_are_finite
from mpcwalk.sim.sensing.model import SensorModel
from mpcwalk.sim.sensing.simulator import SensorSimulator

__all__ = ["SensorFaults", "SensorModel", "SensorSimulator", "readings_are_finite"]
