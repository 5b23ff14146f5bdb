"""Your own robot from a preset file: here the shipped small humanoid copied under another
name into a folder of yours, loaded from the preset's path and walked.

    python examples/your_own_robot.py [FOLDER]
"""

import shutil
import sys
import tempfile
from pathlib import Path

import mpcwalk
from mpcwalk.robot import loading

folder = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
folder.mkdir(parents=True, exist_ok=True)
shutil.copy(loading.ROBOTS_DIR / "bioloid_like.xml", folder / "my_biped.xml")
preset = (loading.PRESETS_DIR / "bioloid_like.toml").read_text()
preset = preset.replace('name = "bioloid-like"', 'name = "my-biped"')
preset = preset.replace('description = "bioloid_like.xml"', 'description = "my_biped.xml"')
(folder / "my_biped.toml").write_text(preset)

robot = mpcwalk.load_robot(folder / "my_biped.toml")
print(f"{robot.name}: {robot.total_mass:.2f} kg, {len(robot.joint_names)} joints")
result = mpcwalk.run_walk(robot, controller="mpc", command=(0.1, 0.0, 0.0), nb_steps=2)
print("fell:", result.metrics.fell)
