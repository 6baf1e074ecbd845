"""A tree's ``plugins:`` in BehaviorTree.CPP 4 XML, both ways.

The export writes the plugins a tree names as an element under ``<root>`` that BT.CPP
4.7.3's parser passes over (it reads only ``<include>``, ``<BehaviorTree>`` and
``<TreeNodesModel>`` there)::

    <Plugins>
      <Plugin path="local_plugins"/>          <!-- a file or folder, relative to the XML -->
      <Plugin module="my_package.leaves"/>    <!-- an importable module -->
    </Plugins>

The import reads it back, so a tree exported and imported again finds its leaves with no
``--plugin-path``.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

from sar_framework.interop.xml_source import Element, Problem

#: The element under ``<root>`` that lists the plugins.
PLUGINS_TAG = "Plugins"
_ENTRY = "Plugin"


def plugins_element(entries: Sequence[str], folder: Path | None) -> ET.Element | None:
    """The ``<Plugins>`` element of a tree's plugin entries (None when there is none).

    Args:
        entries: :attr:`.spec.TreeSpec.plugin_paths`: absolute paths, or module names.
        folder: The folder the XML is written to (paths are made relative to it); None
            keeps them absolute.

    Returns:
        The element, or None.
    """
    if not entries:
        return None
    root = ET.Element(PLUGINS_TAG)
    for entry in dict.fromkeys(os.path.normpath(e) if Path(e).is_absolute() else e
                               for e in entries):
        if Path(entry).is_absolute():
            text = os.path.relpath(entry, folder) if folder is not None else entry
            ET.SubElement(root, _ENTRY, {"path": text})
        else:
            ET.SubElement(root, _ENTRY, {"module": entry})
    return root


def read_plugins(root: Element, file: str) -> tuple[list[str], list[Problem]]:
    """The plugin entries of a file's ``<Plugins>`` elements.

    Args:
        root: The parsed ``<root>``.
        file: The XML file (paths are relative to its folder).

    Returns:
        The entries (paths made absolute, modules as written) and the problems.
    """
    entries: list[str] = []
    problems: list[Problem] = []
    folder = Path(file).resolve().parent
    for element in (e for e in root.children if e.tag == PLUGINS_TAG):
        for item in element.children:
            path, module = item.attrs.get("path"), item.attrs.get("module")
            if item.tag != _ENTRY or (path is None) == (module is None):
                problems.append(Problem(file, item.line, item.column, f"<{item.tag}> in "
                                        f"<{PLUGINS_TAG}>: expected <{_ENTRY} path=\"...\"/> "
                                        f"or <{_ENTRY} module=\"...\"/>"))
            elif path is not None:
                entries.append(os.path.normpath(folder / path))
            else:
                entries.append(str(module))
    return entries, problems
