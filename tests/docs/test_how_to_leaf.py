"""The leaf and the test shown in docs/how-to/write-a-leaf.md work as shown."""

from __future__ import annotations

import re
import subprocess
import sys
import textwrap
from pathlib import Path

GUIDE = Path(__file__).resolve().parents[2] / "docs" / "how-to" / "write-a-leaf.md"
BLOCK = re.compile(r"^( *)```python\n(.*?)^\1```", re.MULTILINE | re.DOTALL)


def test_the_guides_leaf_passes_the_guides_test(tmp_path: Path) -> None:
    blocks = [textwrap.dedent(body) for _, body in BLOCK.findall(GUIDE.read_text())]
    assert len(blocks) == 2, "the guide shows the leaf, then its test"
    (tmp_path / "battery_ok.py").write_text(blocks[0])
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_battery_ok.py").write_text(blocks[1])
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "tests"],
        cwd=tmp_path, capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "1 passed" in done.stdout
