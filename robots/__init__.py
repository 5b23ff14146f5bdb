"""Robot descriptions (MJCF) and presets of mpcwalk: data, no code.

pip installs this folder as the package ``mpcwalk.robot.data`` (``package-dir`` in
``pyproject.toml``), and the library finds it there with :mod:`importlib.resources`
(``mpcwalk.robot.package_data``). This file makes the folder a regular package, which
editable installs need to map it.
"""
