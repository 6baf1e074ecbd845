"""One frame of ``sar-tree watch``: a tree status document drawn with rich (no ROS).

The frame shows a header line (tree, tick, ticks per second, simulated time, an app's
field, root status), the tree with each node's status symbol and name in the status's
colour (the py_trees symbols, so it reads like ``py-trees-tree-watcher``), the running
branch in bold, feedback messages dimmed beside their node, the blackboard keys the
leaves write and, for a tree with blackboard entries, an entries panel (value, type and
writer of each; those that changed this tick in bold). A mission that is over gets a
closing line with its verdict.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from rich.console import Group, RenderableType
from rich.table import Table
from rich.text import Text
from rich.tree import Tree

from sar_framework.app.discovery import apps_status_text, view_apps

if TYPE_CHECKING:
    from sar_framework.app import App

STATUS_STYLES = {"SUCCESS": "green", "FAILURE": "red", "RUNNING": "yellow",
                 "INVALID": "bright_black"}
STATUS_SYMBOLS = {"SUCCESS": "✓", "FAILURE": "✕", "RUNNING": "*", "INVALID": "-"}
"""The py_trees unicode symbols (``py_trees.display.unicode_symbols``)."""
_MESSAGE_MAX = 70


def node_label(node: dict[str, Any]) -> Text:
    """``<symbol> <name> [kind] <message>`` in the node's status colour."""
    status = node["status"]
    style = STATUS_STYLES.get(status, "")
    if status == "RUNNING":
        style += " bold"
    label = Text(f"{STATUS_SYMBOLS.get(status, '?')} {node['name']}", style=style)
    if node["kind"] != node["name"]:
        label.append(f" [{node['kind']}]", style="cyan")
    if node["message"] and status != "INVALID":
        message = node["message"]
        message = message if len(message) <= _MESSAGE_MAX else message[:_MESSAGE_MAX - 1] + "…"
        label.append(f"  {message}", style="dim")
    return label


def tree_view(nodes: Sequence[dict[str, Any]], title: Text) -> Tree:
    """The nodes (depth first, with ``depth``) as a rich tree under ``title``."""
    view = Tree(title, guide_style="bright_black")
    branches: list[Tree] = [view]
    for node in nodes:
        del branches[node["depth"] + 1:]
        branches.append(branches[-1].add(node_label(node)))
    return view


@functools.lru_cache(maxsize=8)
def _tree_apps(tree: str) -> list[App]:
    """The apps of the tree file the runner says it ticks (its ``plugins:`` too), once."""
    return view_apps(tree)


def header(document: dict[str, Any], ticks_per_s: float | None) -> Text:
    """The line above the tree: name, tick, rate, simulated time, root status.

    The apps' words about the document follow the clock
    (:attr:`~sar_framework.app.App.status_text`).
    """
    apps = _tree_apps(str(document.get("tree") or ""))
    app_text = "".join(f"{words}  " for words in apps_status_text(document, apps) if words)
    rate = f"{ticks_per_s:.1f}" if ticks_per_s is not None else "-"
    status = str(document.get("status", "INVALID"))
    text = Text(f"{document.get('tree', '?')}", style="bold")
    text.append(f"  tick {document.get('tick', 0)}  {rate} ticks/s  "
                f"sim {float(document.get('sim_s') or 0.0):.1f} s  {app_text}root ")
    text.append(status, style=STATUS_STYLES.get(status, ""))
    return text


def blackboard_view(blackboard: dict[str, str]) -> RenderableType:
    """The blackboard keys the leaves write, or a line saying there are none."""
    if not blackboard:
        return Text("blackboard: no keys written by the leaves", style="dim")
    table = Table("blackboard key", "value", box=None, header_style="bold", pad_edge=False)
    for key, value in blackboard.items():
        table.add_row(key, value)
    return table


def entries_view(entries: dict[str, dict[str, str]], changed: set[str] | None = None
                 ) -> RenderableType:
    """The tree's blackboard entries (name, value, type, writer); ``changed`` ones in bold.

    Args:
        entries: ``name -> {"key", "value", "type", "writer"}`` as the watcher keeps them.
        changed: The names whose value changed in the latest status.
    """
    changed = changed or set()
    table = Table("entry", "value", "type", "writer", title="entries", title_justify="left",
                  box=None, header_style="bold", pad_edge=False)
    for name, entry in entries.items():
        style = "bold" if name in changed else ""
        table.add_row(name, Text(entry.get("value", ""), style=style or "default"),
                      Text(entry.get("type", ""), style="cyan"),
                      Text(entry.get("writer", ""), style="dim"), style=style)
    return table


def frame(document: dict[str, Any], ticks_per_s: float | None = None,
          source: str = "") -> RenderableType:
    """One whole frame for a status document (see :mod:`sar_framework.runner.tree_status`).

    Args:
        document: The decoded status document.
        ticks_per_s: The measured tick rate, if known.
        source: Where the frame came from (shown dimmed under the tree).

    Returns:
        Something ``rich`` renders.
    """
    running = [n["name"] for n in document["nodes"] if n["status"] == "RUNNING"]
    parts: list[RenderableType] = [
        tree_view(document["nodes"], header(document, ticks_per_s)),
        Text("running branch: " + (" → ".join(running) if running else "none"), style="bold"),
        blackboard_view(document.get("blackboard") or {}),
    ]
    if document.get("entries"):
        parts.append(entries_view(document["entries"], document.get("entries_changed")))
    if source:
        parts.append(Text(source, style="dim"))
    if document.get("complete"):
        status = str(document.get("status"))
        parts.append(Text(f"mission over: {status}", style=f"bold {STATUS_STYLES.get(status, '')}"))
    return Group(*parts)
