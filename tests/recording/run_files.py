"""A tree made of several files: an ``include:``, a ``plugins:`` entry in the included
file and a leaf from a ``--plugin-path`` folder (the recording tests' run files)."""

from __future__ import annotations

import shutil
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
TUTORIALS = REPO / "trees" / "tutorials"
PAUSE_PLUGIN = '''"""A leaf that succeeds at once (a --plugin-path plugin of these tests)."""

import py_trees

from sar_framework.engine.plugin import leaf


@leaf()
class Pause(py_trees.behaviour.Behaviour):
    """SUCCESS at once."""

    def update(self) -> py_trees.common.Status:
        """Succeed."""
        self.feedback_message = "paused"
        return py_trees.common.Status.SUCCESS
'''
TREE = """format: 1
name: recorded_with_includes
include: [common/06_report_library.yaml]
root:
  sequence:
    name: IncludedAndPlugins
    memory: true
    children:
      - Pause: {name: FirstPause}
      - subtree: report_survivor
"""


def make_tree(folder: Path) -> tuple[Path, Path]:
    """Write the tree's files under ``folder``; return the tree file and the plugin folder."""
    (folder / "mission" / "common").mkdir(parents=True)
    (folder / "mission" / "plugins").mkdir()
    shutil.copy(TUTORIALS / "common" / "06_report_library.yaml", folder / "mission" / "common")
    shutil.copy(TUTORIALS / "plugins" / "tutorial_leaves.py", folder / "mission" / "plugins")
    (folder / "extra").mkdir()
    (folder / "extra" / "pause.py").write_text(PAUSE_PLUGIN)
    tree = folder / "mission" / "tree.yaml"
    tree.write_text(TREE)
    return tree, folder / "extra"
