"""What the ``mpcwalk bench`` commands leave behind: ``NAME.md`` and ``NAME.json``."""

import json
import os
import platform
from pathlib import Path
from typing import Any


def machine_description() -> str:
    """One line describing the machine the benchmark ran on."""
    return (
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}"
    )


def write_bench_output(out: str | Path, name: str, text: str, payload: Any) -> None:
    """Print ``text`` and write it to ``out/NAME.md``, and ``payload`` to ``out/NAME.json``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    print(text)
    (out / f"{name}.md").write_text(text.rstrip("\n") + "\n")
    (out / f"{name}.json").write_text(json.dumps(payload, indent=2) + "\n")
    print(f"\nwrote {out / f'{name}.md'} and {out / f'{name}.json'}")
