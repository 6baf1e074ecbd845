"""Draw the studio's picture for the docs (docs/img/studio.png) from a real run.

    .venv/bin/python tools/studio_picture.py [--recording FILE.mcap] [--out docs/img/studio.png]

Records the reference mission with its second navigation goal aborted (unless a recording
is given), opens it with ``sar-tree studio replay`` in a headless chromium, clicks the
timeline's failure mark, opens the failed node's panel and saves the screenshot. Nothing
in the picture is drawn by hand. Needs chromium and chromedriver.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
OUT = REPO / "docs" / "img" / "studio.png"

from sar_framework.testing.browser import (  # noqa: E402 - after the path is set
    browser_missing,
    headless_chromium,
    record_mission,
    start_studio,
)

SELECT = """
const uid = Object.values(studio.hello.tree.nodes).find((f) => f.name === arguments[0]).uid;
selectNode(uid);
"""


def picture(recording: Path, out: Path, folder: Path) -> Path:
    """Screenshot the studio at the recording's first failure mark, the failed node open."""
    from selenium.webdriver.common.by import By

    studio, url = start_studio(["replay", str(recording)], folder)
    try:
        with headless_chromium(1400, 820) as driver:
            driver.get(url)
            deadline = time.monotonic() + 30
            while not driver.execute_script("return studio.frame !== null") \
                    and time.monotonic() < deadline:
                time.sleep(0.2)
            driver.find_element(By.CSS_SELECTOR, "#marks .mark.failure").click()
            time.sleep(1.0)
            driver.execute_script(SELECT, "NavigateToZone")
            time.sleep(1.0)
            out.parent.mkdir(parents=True, exist_ok=True)
            driver.save_screenshot(str(out))
    finally:
        studio.stop()
    return out


def main(argv: list[str] | None = None) -> int:
    """Make the picture; print where it went."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--recording", type=Path)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    missing = browser_missing()
    if missing:
        print(f"studio_picture: {missing}")
        return 1
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    with tempfile.TemporaryDirectory(prefix="studio_picture_") as tmp:
        folder = Path(tmp)
        recording = args.recording or record_mission(folder / "mission.mcap",
                                                     "abort_goal_numbers:=[2]")
        print(f"studio_picture: {picture(recording, args.out, folder)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
