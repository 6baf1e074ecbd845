"""Where the core still names one mission: "zone" or "survivor" outside the apps.

Scans ``sar_framework/``, ``launch/`` and ``interfaces/sar_interfaces/msg/`` (case-insensitive,
skipping ``__pycache__``, "timezone" and the search-and-rescue app's own files there) and
prints the hits per folder, then in total.

Usage: ``python tools/neutral_scan.py [--list] [--skip PATH ...]`` (``--skip``: a file or
folder left out of the count, for work in progress elsewhere).
"""

from __future__ import annotations

import argparse
import re
import sys
from collections import Counter
from pathlib import Path

ROOTS = ("sar_framework", "launch", "interfaces/sar_interfaces/msg")
WORD = re.compile(r"zone|survivor", re.IGNORECASE)
APP_FILES = (Path("launch/search_and_rescue.launch.py"),)
"""The search-and-rescue app's files outside ``plugins/sar/``: its launch file."""


def hits(text: str) -> int:
    """The mission words in ``text``, "timezone" not counted."""
    return sum(1 for m in WORD.finditer(text)
               if text[max(0, m.start() - 4):m.start()].lower() != "time")


def folder_of(path: Path) -> str:
    """The folder a hit is counted under (``sar_framework/mission``, ``launch``...)."""
    parts = path.parts
    if parts[0] == "sar_framework" and len(parts) > 2:
        return "/".join(parts[:2])
    return str(path.parent) if parts[0] != "sar_framework" else str(path)


def main(argv: list[str] | None = None) -> int:
    """Print the counts; exit 1 when there is any hit."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--list", action="store_true", help="print every file with hits")
    parser.add_argument("--skip", nargs="*", default=[], help="files or folders left out")
    args = parser.parse_args(argv)
    root = Path(__file__).resolve().parents[1]
    skips = [*APP_FILES, *(Path(s) for s in args.skip)]
    per_folder: Counter[str] = Counter()
    per_file: Counter[str] = Counter()
    for top in ROOTS:
        for path in sorted((root / top).rglob("*")):
            relative = path.relative_to(root)
            if not path.is_file() or "__pycache__" in relative.parts:
                continue
            if any(relative == s or s in relative.parents for s in skips):
                continue
            count = hits(path.read_text(errors="replace"))
            if count:
                per_folder[folder_of(relative)] += count
                per_file[str(relative)] += count
    for folder, count in per_folder.most_common():
        print(f"{count:6d}  {folder}")
    if args.list:
        for name, count in sorted(per_file.items()):
            print(f"{count:6d}  {name}")
    print(f"{sum(per_folder.values()):6d}  total")
    return 1 if per_folder else 0


if __name__ == "__main__":
    sys.exit(main())
