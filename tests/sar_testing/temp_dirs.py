"""A temporary folder of the test's own for what launch writes (``launch_params_*``).

launch_ros writes every parameter dictionary of a Node into
``tempfile.NamedTemporaryFile(prefix="launch_params_", delete=False)`` and never removes
it: in the temp dir of the process that evaluates the launch description (``ros2 launch``,
or the test itself when it visits one). Pointing ``TMPDIR`` (a child's) and
``tempfile.tempdir`` (this process's) at a folder under the test's ``tmp_path`` keeps them
there, and pytest removes them with it.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Mapping
from pathlib import Path

import pytest


def own_tmpdir(tmp_path: Path) -> Path:
    """The test's own temp folder, ``tmp_path/tmp`` (made)."""
    folder = tmp_path / "tmp"
    folder.mkdir(exist_ok=True)
    return folder


def launch_env(tmp_path: Path, base: Mapping[str, str] | None = None,
               **extra: str) -> dict[str, str]:
    """An environment for ``ros2 launch``: ``base`` (``os.environ``), ``extra``, and ``TMPDIR``
    the test's own temp folder."""
    return {**(os.environ if base is None else base), **extra,
            "TMPDIR": str(own_tmpdir(tmp_path))}


@pytest.fixture
def launch_tmpdir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The test's own temp folder, for this process (a launch visited in-process) and children."""
    folder = own_tmpdir(tmp_path)
    monkeypatch.setenv("TMPDIR", str(folder))
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    return folder
