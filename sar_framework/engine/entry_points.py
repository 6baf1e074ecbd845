"""Whether any installed distribution may declare an entry-point group, read cheaply.

Importing ``importlib.metadata`` (with ``email``, ``csv``, ``zipfile`` ...) and scanning
costs about 10 ms, a tenth of ``sar-tree validate``, to learn in most installs that no
distribution declares a plugin. :func:`declared_anywhere` looks where
``importlib.metadata`` looks (each ``sys.path`` directory's ``*.dist-info`` and
``*.egg-info`` folders) for an ``entry_points.txt`` that mentions the group. It answers
False only when it read every such place and none does; anything it cannot read the same
way (a zip or ``.egg`` on the path, a meta-path finder with distributions of its own, an
unreadable file) answers True, and the caller asks ``importlib.metadata``.
"""

from __future__ import annotations

import importlib.machinery
import os
import sys
from collections.abc import Sequence


def declared_anywhere(group: str, path: Sequence[str] | None = None) -> bool:
    """Whether some distribution on ``path`` may declare entry points in ``group``.

    Args:
        group: The entry-point group, e.g. ``sar_framework.plugins``.
        path: The import path to look in; default ``sys.path``.

    Returns:
        False only when no distribution ``importlib.metadata`` would find names the group.
    """
    for finder in sys.meta_path:
        if finder is not importlib.machinery.PathFinder and \
                hasattr(finder, "find_distributions"):
            return True  # distributions from elsewhere than the path
    wanted = group.encode()
    for entry in sys.path if path is None else path:
        if not isinstance(entry, str) or entry.lower().endswith(".egg"):
            return True
        folder = entry or "."
        try:
            with os.scandir(folder) as children:
                names = [c.name for c in children]
        except NotADirectoryError:
            return True  # a zip file on the path
        except OSError:
            continue  # missing: importlib.metadata finds nothing there either
        for name in names:
            if not name.lower().endswith((".dist-info", ".egg-info")):
                continue
            try:
                with open(os.path.join(folder, name, "entry_points.txt"), "rb") as file:
                    if wanted in file.read():
                        return True
            except (FileNotFoundError, NotADirectoryError):
                continue  # no entry points, or a PKG-INFO file named *.egg-info
            except OSError:
                return True  # unreadable here: let importlib.metadata say
    return False
