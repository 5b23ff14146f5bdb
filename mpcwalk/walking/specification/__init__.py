"""One walk, one specification: :class:`WalkSpec` and its parts, and its TOML file.

- :class:`ControllerSpec`: generator and its options, feedback, stabilizers, arm swing,
  swing profile, controller options; the named controllers (:data:`CONTROLLERS`);
- :class:`PlanSpec`: command or path, steps or duration, timing, control period;
- :class:`WorldSpec`: sensors, latency, state source, the simulated robot's departure from
  the model, the ground;
- :class:`DisturbanceSpec`: pushes, sensor faults;
- :class:`RunSpec`: seed, progress bar, video.
"""

from mpcwalk.walking.specification.controller import (
    CONTROLLERS,
    CUSTOM,
    SWING_PROFILES,
    ControllerSpec,
    controller_names,
)
from mpcwalk.walking.specification.disturbances import DisturbanceSpec, Push
from mpcwalk.walking.specification.plan import PlanSpec
from mpcwalk.walking.specification.spec_file import SPEC_FILE, read_spec, spec_to_toml, write_spec
from mpcwalk.walking.specification.walk_spec import (
    DEFAULT_CONTROLLER,
    FIELDS,
    PARTS,
    RunSpec,
    WalkSpec,
)
from mpcwalk.walking.specification.world import WorldSpec

__all__ = [
    "CONTROLLERS",
    "CUSTOM",
    "DEFAULT_CONTROLLER",
    "FIELDS",
    "PARTS",
    "SPEC_FILE",
    "SWING_PROFILES",
    "ControllerSpec",
    "DisturbanceSpec",
    "PlanSpec",
    "Push",
    "RunSpec",
    "WalkSpec",
    "WorldSpec",
    "controller_names",
    "read_spec",
    "spec_to_toml",
    "write_spec",
]
