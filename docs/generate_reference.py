"""Write the generated reference pages of the documentation site.

- ``reference/metrics.md``: every key of ``metrics.json`` (the fields of ``WalkMetrics`` and
  of the ``config`` block, ``WalkConfig``) with its meaning, from their docstrings, and the
  definition of the CoP margin, from its module's docstring;
- ``reference/cli.md``: every command and sub-command with its options, from the parser.

Run it after changing either (``python docs/generate_reference.py``); the test suite fails
when the committed pages differ from what it writes.
"""

import argparse
import dataclasses
import importlib
import inspect
import io
import re
import sys
from contextlib import redirect_stdout
from pathlib import Path

DOCS = Path(__file__).resolve().parent


def docstring_attributes(cls) -> dict[str, str]:
    """``name -> description`` of the ``Attributes:`` section of a class docstring."""
    text = cls.__doc__ or ""
    section = text.split("Attributes:", 1)[1] if "Attributes:" in text else ""
    entries: dict[str, str] = {}
    name = None
    for line in section.splitlines():
        match = re.match(r"^ {8}(\w+): ?(.*)$", line)
        if match:
            name = match.group(1)
            entries[name] = match.group(2).strip()
        elif name and line.startswith(" " * 12):
            entries[name] += " " + line.strip()
        elif line.strip() and not line.startswith(" " * 8):
            break
    return entries


def describe_keys(cls) -> list[tuple[str, str]]:
    """Every field of the dataclass ``cls`` with its description (a ``_max`` or ``_min``
    field described with its ``_mean`` sibling points there)."""
    described = docstring_attributes(cls)
    rows = []
    for field in dataclasses.fields(cls):
        text = described.get(field.name)
        if text is None:
            stem = re.sub(r"_(max|min|p05)(?=(_|$))", "_mean", field.name)
            if stem in described:
                text = f"See `{stem}`."
        if text is None:
            raise SystemExit(f"{cls.__name__}.{field.name} has no description in its docstring")
        rows.append((field.name, text))
    return rows


def metrics_page() -> str:
    from mpcwalk.walking.metrics import WalkMetrics
    from mpcwalk.walking.result import WalkConfig

    lines = [
        "# `metrics.json`",
        "",
        "Every `mpcwalk walk` writes `metrics.json` in its `--out` folder, beside `spec.toml` "
        "(the walk's specification, to walk it again with `--spec`); `run_walk` "
        "returns the same as `result.metrics`, `result.config` (and `result.spec`). Its keys are the fields of "
        "`WalkMetrics`, then a `config` block with the fields of `WalkConfig`. A value is "
        "`null` where it cannot be measured (no landing checked, no CoP, a run shorter than "
        "the window). Units are in the names: `_m`, `_cm`, `_mm`, `_s`, `_deg`, `_us`.",
        "",
        "This page is generated from the docstrings (`python docs/generate_reference.py`).",
        "",
        "## The walk's metrics",
        "",
        "| key | meaning |",
        "|---|---|",
    ]
    lines += [f"| `{k}` | {v.replace('|', '/')} |" for k, v in describe_keys(WalkMetrics)]
    lines += ["", "## The `config` block", "", "| key | meaning |", "|---|---|"]
    lines += [f"| `{k}` | {v.replace('|', '/')} |" for k, v in describe_keys(WalkConfig)]
    return "\n".join(lines + ["", *cop_margin_section()]) + "\n"


def cop_margin_section() -> list[str]:
    """The definition of the CoP margin: its module's docstring, in Markdown."""
    module = importlib.import_module("mpcwalk.walking.metrics.cop_margins")
    body = inspect.cleandoc(module.__doc__ or "").split("\n", 1)[1].strip()
    body = re.sub(r":\w+:`~?([\w.]+)`", lambda m: f"`{m.group(1).split('.')[-1]}`", body)
    title = "## The CoP margin (`cop_margin_min_m`, `cop_margin_p05_m`, `cop_outside_share`)"
    return [title, "", body.replace("``", "`")]


def _subparsers(parser: argparse.ArgumentParser):
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            yield from action.choices.items()


def _help(parser: argparse.ArgumentParser) -> str:
    buffer = io.StringIO()
    with redirect_stdout(buffer):
        parser.print_help()
    return buffer.getvalue().rstrip()


def cli_page() -> str:
    import os

    from mpcwalk.cli import build_parser

    os.environ["COLUMNS"] = "100"
    parser = build_parser()
    lines = [
        "# Command line",
        "",
        "`mpcwalk COMMAND --help` prints the same. This page is generated from the parser "
        "(`python docs/generate_reference.py`).",
        "",
        "```text",
        _help(parser),
        "```",
    ]

    def walk(prefix: str, p: argparse.ArgumentParser, depth: int) -> None:
        for name, sub in _subparsers(p):
            lines.extend(["", f"{'#' * depth} `{prefix} {name}`", "", "```text", _help(sub), "```"])
            walk(f"{prefix} {name}", sub, depth + 1)

    walk("mpcwalk", parser, 2)
    return "\n".join(lines) + "\n"


PAGES = {"reference/metrics.md": metrics_page, "reference/cli.md": cli_page}


def main() -> int:
    for relative, build in PAGES.items():
        (DOCS / relative).write_text(build())
        print(f"wrote docs/{relative}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
