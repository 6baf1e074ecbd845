"""The live studio in a real browser (headless chromium), attached to a real mission: node
colours change with the ticks, the robot moves, and the end stays on screen."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from e2e.helpers import DEFAULT_TREE, sar_tree_run

from sar_framework.testing.browser import browser_missing, headless_chromium, start_studio

from .page import assert_drawn, state, wait_for

pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.browser,
              pytest.mark.skipif(browser_missing() is not None, reason=str(browser_missing()))]

NAMES = ["NavigateToZone", "NavigateToBase", "MissionOrReturnToBase"]


def test_live_view_follows_a_mission_and_keeps_its_end(tmp_path: Path) -> None:
    studio, url = start_studio(["live", "--tree", str(DEFAULT_TREE)], tmp_path)
    shots = tmp_path / "shots"
    shots.mkdir()
    try:
        with headless_chromium() as driver:
            driver.get(url)
            wait_for(driver, NAMES, lambda s: True, 30, "the page's first frame")
            mission = sar_tree_run([str(DEFAULT_TREE), "--speed", "5"], tmp_path / "report")
            try:
                running = wait_for(driver, NAMES,
                                   lambda s: s["statuses"]["NavigateToZone"] == "RUNNING"
                                   and s["robot"] is not None, 90, "a zone goal running")
                png = driver.get_screenshot_as_png()
                (shots / "running.png").write_bytes(png)
                assert_drawn(png, running["rects"]["NavigateToZone"], "RUNNING",
                             "NavigateToZone")
                seen = {running["statuses"]["NavigateToZone"]}
                start = running["robot"]

                def moved_and_reached(s: dict) -> bool:
                    seen.add(s["statuses"]["NavigateToZone"])
                    return math.dist(s["robot"], start) > 1.0 and "SUCCESS" in seen

                moved = wait_for(driver, NAMES, moved_and_reached, 90,
                                 "the robot 1 m on and a zone reached")
                assert moved["tick"] > running["tick"]
                end = wait_for(driver, NAMES, lambda s: s["complete"], 120, "the mission's end")
                assert mission.wait(timeout=60) == 0
            finally:
                mission.stop()
            # nothing arrives any more; the final state is still drawn
            final = wait_for(driver, NAMES, lambda s: s["tick"] == end["tick"], 5, "the end")
            png = driver.get_screenshot_as_png()
            (shots / "final.png").write_bytes(png)
            assert final["header"] == "SUCCESS (over)"
            assert final["statuses"]["NavigateToBase"] == "SUCCESS"
            assert_drawn(png, final["rects"]["NavigateToBase"], "SUCCESS", "NavigateToBase")
            assert_drawn(png, final["rects"]["MissionOrReturnToBase"], "SUCCESS",
                         "MissionOrReturnToBase")
            assert math.dist(final["robot"], (0.0, 0.0)) < 0.5  # back at base
            assert state(driver, NAMES)["tick"] == end["tick"]
    finally:
        studio.stop()
