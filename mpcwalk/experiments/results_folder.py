"""Where the committed results of the repository are, from any working directory."""

from pathlib import Path

import mpcwalk


def find_results(name: str, *, start: str | Path | None = None) -> Path | None:
    """The folder ``results/<name>`` of the repository: looked for in the working directory
    (or ``start``) and its parents, then beside the package (a checkout installed in
    editable mode); None when there is none (an installed wheel has no results)."""
    here = Path.cwd() if start is None else Path(start)
    candidates = [here.resolve(), *here.resolve().parents]
    candidates.append(Path(mpcwalk.__file__).resolve().parents[1])
    for folder in candidates:
        path = folder / "results" / name
        if path.is_dir():
            return path
    return None


__all__ = ["find_results"]
