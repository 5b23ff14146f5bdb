"""What the ``mpcwalk bench`` commands leave behind: ``NAME.md`` and ``NAME.json``."""

import importlib
import json
import os
import platform
from pathlib import Path
from typing import Any


def machine_description() -> str:
    """One line describing the machine the benchmark ran on: its processor (its brand when
    the optional ``cpuinfo`` package is there), cores and Python."""
    cpu = platform.processor() or platform.machine()
    try:
        cpuinfo = importlib.import_module("cpuinfo")  # optional, untyped
        cpu = cpuinfo.get_cpu_info().get("brand_raw", cpu) or cpu
    except Exception:
        pass
    return f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}"


def write_bench_output(out: str | Path, name: str, text: str, payload: Any) -> tuple[Path, Path]:
    """Write ``text`` to ``out/NAME.md`` and ``payload`` to ``out/NAME.json``; their paths.

    Args:
        out: Output folder (created).
        name: File stem, the benchmark's name (``ticks``, ``ik``, ``loop``).
        text: The markdown report.
        payload: The results, as JSON.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    markdown, data = out / f"{name}.md", out / f"{name}.json"
    markdown.write_text(text.rstrip("\n") + "\n")
    data.write_text(json.dumps(payload, indent=2) + "\n")
    return markdown, data
