"""Where the data shipped with mpcwalk lies: robot descriptions, presets, experiment configs.

The top-level folder ``robots/`` of the repository is installed as the package
``mpcwalk.robot.data`` (setuptools' ``package-dir`` and ``package-data`` in
``pyproject.toml``); each experiment's ``config.toml`` lies in its own package
(``mpcwalk.experiments.paper_m``...). :mod:`importlib.resources` finds them wherever
pip put them, for an editable install (the source folders), a normal install and a wheel
(folders inside the installed package) alike: nothing here depends on where the source tree
is.
"""

import importlib.resources
from pathlib import Path

from mpcwalk.exceptions import PackageDataNotFound

ROBOT_DATA = "mpcwalk.robot.data"
"""Package of the robot descriptions written by this project (MJCF) and of the presets."""


def package_data_dir(package: str) -> Path:
    """Folder of an installed data package, on the file system.

    MuJoCo and the readers of this project open files by path, so the folder must be a real
    directory (pip installs wheels unzipped).

    Args:
        package: Dotted name of the data package, e.g. :data:`ROBOT_DATA`.

    Returns:
        The folder of the package.

    Raises:
        PackageDataNotFound: mpcwalk is not installed with its data (e.g. the source tree was
            put on ``sys.path`` by hand), or is imported from a zip archive.
    """
    try:
        root = importlib.resources.files(package)
    except ModuleNotFoundError as error:
        raise PackageDataNotFound(package, f"importlib found no package {package!r}") from error
    if not isinstance(root, Path) or not root.is_dir():
        raise PackageDataNotFound(package, f"it is not a folder on the file system: {root}")
    return root


__all__ = ["ROBOT_DATA", "package_data_dir"]
