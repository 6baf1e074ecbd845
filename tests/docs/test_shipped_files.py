"""Shipped files name no path of the machine they were written on."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SHIPPED = ("trees", "config", "docs", "launch", "maps")
# A home or build directory, as an absolute path: /home/ann, /root/..., /Users/..., /work/...
MACHINE_PATH = re.compile(r"(?<![\w./~-])(?:/home/|/root/|/Users/|/work/|[A-Za-z]:\\Users\\)")


def shipped_text_files() -> list[Path]:
    """Every text file under the shipped folders."""
    files = []
    for folder in SHIPPED:
        for path in sorted((REPO / folder).rglob("*")):
            if path.is_file() and b"\0" not in path.read_bytes()[:1024]:
                files.append(path)
    return files


def test_the_pattern_finds_machine_paths() -> None:
    found = [MACHINE_PATH.search(t) is not None for t in (
        "# docs: /work/shared/spec.md", "see /home/ann/x", "C:\\Users\\ann", "/opt/ros/jazzy",
        "`/detect_survivor`", "sar_interfaces/srv/X", "--report-dir /tmp/run", "~/work/x")]
    assert found == [True, True, True, False, False, False, False, False]


def test_no_machine_paths_in_shipped_files() -> None:
    files = shipped_text_files()
    assert len(files) > 20
    hits = []
    for path in files:
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            if MACHINE_PATH.search(line):
                hits.append(f"{path.relative_to(REPO)}:{number}: {line.strip()}")
    assert hits == []
