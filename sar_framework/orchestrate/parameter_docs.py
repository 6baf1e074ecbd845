"""docs/reference/parameters.md, generated from every node's parameter table.

``python -m sar_framework.orchestrate.parameter_docs > docs/reference/parameters.md`` writes it;
a test fails when the committed file and the tables disagree.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from sar_framework.app import discover_apps
from sar_framework.engine.param import REQUIRED, Param, type_name
from sar_framework.mission.processes import MissionSettings, mission_processes
from sar_framework.orchestrate.inputs import node_parameters

_ROOT = str(Path(__file__).resolve().parents[2]) + "/"

INTRO = """\
# Node parameters

Generated from each node's parameter table by
`python -m sar_framework.orchestrate.parameter_docs > docs/reference/parameters.md`
(a test fails when this file and the tables disagree). Each table is declared once, in a
module without ROS, as `sar_framework.engine.param.Param` entries (the type leaf params are
declared with too), and read by the node's ROS declarations (descriptors with ranges:
`ros2 param describe`), by `sar-tree run`'s checks of the parameter file and of `--sim-param`,
`--detect-param`, `--report-param`, `--runner-param`, by the launch file's defaults, by
`sar-tree faults` and `sar-sim --help`. `*` in a name stands for one segment (an id).
A number accepts an integer (`speed:=20`).
"""

_TITLES = {
    "runner": ("the tree runner", "sar_framework/mission/runner_params.py",
               "its own settings, with the installed apps' parameters (read for a tree that "
               "uses the app)"),
    "sim": ("the embedded simulator", "sar_framework/sim/params.py",
            "`sar-tree run --speed` and the launch's `speed` set `speed`"),
    "recorder": ("the recorder", "sar_framework/recording/params.py",
                 "`sar-tree run --record FILE` and the launch's `record` set `output`"),
}


def default_text(param: Param) -> str:
    """A default as the docs show it: ``true``, ``2.0``, ``'map'``, (required), (unset)."""
    value: Any = param.default
    if value is REQUIRED:
        return "(required)"
    if value is None:
        return "(unset)"
    if isinstance(value, bool):
        return "`true`" if value else "`false`"
    if isinstance(value, str):
        return f"`'{value.removeprefix(_ROOT)}'`"
    return f"`{value!r}`"


def markdown_table(table: tuple[Param, ...]) -> str:
    """One node's parameters as a Markdown table."""
    rows = ["| parameter | type | default | unit | range | meaning |",
            "| --- | --- | --- | --- | --- | --- |"]
    for p in table:
        choices = f"one of {', '.join(p.enum)}" if p.enum else ""
        rows.append(f"| `{p.name}` | {type_name(p.type).replace('|', 'or')} | "
                    f"{default_text(p)} | {p.unit} | {p.bounds() or choices} | "
                    f"{p.description.replace('|', '/')} |")
    return "\n".join(rows) + "\n"


def document() -> str:
    """The whole of docs/reference/parameters.md."""
    apps = discover_apps()
    executables = {p.label: p.executable for p in mission_processes(
        MissionSettings(tree="t", params_file="p", record="r"), apps)}
    for kind in (kind for app in apps for kind in app.process_kinds if kind.executable):
        executables.setdefault(kind.label, kind.executable)  # started by some runs only
    parts = [INTRO]
    titles = {**_TITLES, **{kind.label: (kind.title, kind.declared_in, "")
                            for app in apps for kind in app.process_kinds}}
    for label, own in node_parameters(apps).items():
        # the runner's with the installed apps' (a tree that uses one reads them)
        table = (*(p for app in apps for p in app.parameters), *own) if label == "runner" \
            else own
        title, module, note = titles[label]
        lead = f"`{executables[label]}`, {title}; declared in `{module}`."
        parts.append(f"\n## {label}\n\n{lead}" + (f" {note[0].upper()}{note[1:]}." if note
                                                  else "") + "\n\n" + markdown_table(table))
    return "".join(parts)


if __name__ == "__main__":
    sys.stdout.write(document())
