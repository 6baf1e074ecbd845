"""Sphinx configuration: the docs site, built from the markdown pages (MyST) and the docstrings.

``python -m sphinx -W --keep-going -n -b html docs BUILD`` builds it; tests/docs/test_site.py
does so in every test run, with every warning an error. Nothing is fetched from the network.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

project = "sar_framework"
author = "the sar_framework developers"
copyright = "the sar_framework developers"

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "tutorials/broken"]

# Links to a heading (`page.md#a-heading`) resolve the way GitHub resolves them.
myst_heading_anchors = 4
myst_enable_extensions = ["colon_fence"]

# Every reference must resolve; names from outside the project (py_trees, the standard
# library, typing constructs) are not documented here and have no inventory without a fetch.
nitpicky = True
nitpick_ignore_regex = [
    (r"py:.*", r"(py_trees|pathlib|collections|typing|types|enum|dataclasses|re|yaml)\..*"),
    (r"py:.*", r"(Path|Any|Callable|Iterator|Mapping|Sequence|Status|Behaviour|Enum)"),
    (r"py:.*", r"(int|float|str|bool|bytes|dict|list|tuple|set|frozenset|object|type|None)"),
    (r"py:class", r".*\[.*"),  # a generic type in a docstring, split at its commas
    # Internal modules the documented docstrings mention by name; the reference documents
    # the public API only (reference/api.md), not every module behind it.
    (r"py:.*", r"(ports|trees|assertions|ros_env|spin|ros_harness|processes|mission_stack|"
               r"nav2_navigators)(\..*)?"),
    (r"py:.*", r"sar_framework\.(engine\.(ports|registry|diagnostics|spec|checking\.validate)|"
               r"testing\.mission_stack)\..*"),
    (r"py:.*", r"(sar_framework\.engine\.plugin\._T|LIST_TYPES|REQUIRED|TreeSpec|Registry)"),
    # rclpy's node (ROS is not imported to build the docs) and the runner's event emitter
    (r"py:class", r"(Node|sar_framework\.events\.emitter\.EventEmitter)"),
]

autodoc_member_order = "bysource"
autodoc_typehints = "signature"
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_use_ivar = True  # a dataclass's "Attributes:" as fields, not a second description

html_theme = "alabaster"
html_title = "sar_framework"
