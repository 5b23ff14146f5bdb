"""Experiment configs and paths of mpcwalk (data), and the thin scripts that run them.

pip installs the configs (``paper_m/*.toml``) and paths (``paper_a/*.mdat``) of this folder as
the package ``mpcwalk.experiments.data`` (``package-dir`` and ``package-data`` in
``pyproject.toml``); the scripts are not installed. This file makes the folder a regular
package, which editable installs need to map it.
"""
