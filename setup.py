"""ament_python build of sar_framework (``colcon build``); pip reads pyproject.toml.

The metadata, packages and console scripts live in pyproject.toml. This adds what a ROS
package installs besides: package.xml, its ament index marker, and launch/, config/, maps/,
trees/ under ``share/sar_framework``. An editable install (``pip install -e .``, run by
``make setup``) gets no copies: tools/bootstrap.py links the repository's folders instead.
"""

import sys
from pathlib import Path

from setuptools import setup

PACKAGE = "sar_framework"
SHARED_FOLDERS = ("launch", "config", "maps", "trees")
HERE = Path(__file__).resolve().parent


def data_files() -> list[tuple[str, list[str]]]:
    """Every shared file, grouped by its install folder (paths relative to this file)."""
    files = [("share/ament_index/resource_index/packages", [f"resource/{PACKAGE}"]),
             (f"share/{PACKAGE}", ["package.xml"])]
    for top in SHARED_FOLDERS:
        folders = sorted({p.parent for p in (HERE / top).rglob("*")
                          if p.is_file() and "__pycache__" not in p.parts})
        for folder in folders:
            relative = folder.relative_to(HERE)
            files.append((f"share/{PACKAGE}/{relative}",
                          sorted(str(p.relative_to(HERE)) for p in folder.iterdir()
                                 if p.is_file())))
    return files


setup(data_files=[] if "editable_wheel" in sys.argv else data_files())
