"""Tutorial 2's two routes to a leaf work as shown: named by path, with the testing kit."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
TUTORIAL = REPO / "docs" / "tutorials" / "02_writing_a_plugin.md"
BLOCK = re.compile(r"^```python\n# (battery_leaves/\S+)\n(.*?)^```", re.MULTILINE | re.DOTALL)


def test_the_tutorial_shows_both_routes() -> None:
    text = TUTORIAL.read_text()
    for words in ("pip install -e .", "sar_framework.plugins", "plugins:", "--plugin-path",
                  "plugin_paths=[PLUGIN]"):
        assert words in text, words


def test_the_by_path_test_passes_without_installing(tmp_path: Path) -> None:
    """Regression: only docstrings said the kit needs plugin_paths= for a leaf not installed."""
    files = dict(BLOCK.findall(TUTORIAL.read_text()))
    for name in ("battery_leaves/battery_leaves.py",
                 "battery_leaves/tests/test_battery_ok_by_path.py"):
        target = tmp_path / name
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(files[name])
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
         str(tmp_path / "battery_leaves" / "tests" / "test_battery_ok_by_path.py")],
        cwd=elsewhere, capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "1 passed" in done.stdout
