"""sar_framework: schema-checked YAML behaviour trees (py_trees) on ROS 2.

The public Python API::

    from sar_framework import load_tree
    tree = load_tree("my_tree.yaml", context=objects)  # the context objects its leaves need
    tree.root   # the py_trees root behaviour
    tree.spec   # the validated TreeSpec (for rendering)

Importing this package never imports ROS.
"""

from __future__ import annotations

from typing import Any

__all__ = ["load_spec", "load_tree"]
__version__ = "0.1.0"


def __getattr__(name: str) -> Any:
    # Lazy re-export keeps `import sar_framework` cheap for tools and plugins.
    if name in __all__:
        from sar_framework.engine import api

        return getattr(api, name)
    raise AttributeError(f"module 'sar_framework' has no attribute {name!r}")
