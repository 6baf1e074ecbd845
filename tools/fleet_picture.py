"""Draw the fleet's picture for the docs (docs/img/fleet.png) from a real run.

    .venv/bin/python tools/fleet_picture.py [--robots 3] [--out docs/img/fleet.png]

Runs ``sar-tree run trees/fleet_search.yaml --robots N`` (the embedded simulator, the zone
coordinator, a runner per robot) into a temporary folder and copies the ``fleet.png`` it
wrote: every robot's path in its colour, who searched which zone, every auction round's
bids. Nothing in the picture is drawn by hand. Exits with the run's exit code.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "docs" / "img" / "fleet.png"


def main() -> int:
    """Run the fleet mission and copy its picture; return the run's exit code."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=int, default=3)
    parser.add_argument("--speed", type=float, default=20.0)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="sar_fleet_picture_") as folder:
        run = subprocess.run(
            [sys.executable, "-m", "sar_framework", "run", "trees/fleet_search.yaml",
             "--robots", str(args.robots), "--speed", str(args.speed),
             "--report-dir", folder], cwd=REPO, check=False)
        picture = Path(folder) / "fleet.png"
        if not picture.is_file():
            sys.stderr.write("fleet_picture: the run wrote no fleet.png\n")
            return run.returncode or 1
        args.out.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(picture, args.out)
        print(f"fleet_picture: {args.out} (the run's exit code: {run.returncode})")
    return run.returncode


if __name__ == "__main__":
    sys.exit(main())
