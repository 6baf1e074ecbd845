"""A recording in the studio, in a real browser (headless chromium): the timeline's failure
mark scrubs to the failure, with the statuses, reasons and colours of that instant."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import pytest
from e2e.helpers import DEFAULT_TREE, FAST, run_to_end

from sar_framework.testing.browser import browser_missing, headless_chromium, start_studio

from .page import assert_drawn, state, wait_for

pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.browser,
              pytest.mark.skipif(browser_missing() is not None, reason=str(browser_missing()))]

NAMES = ["NavigateToZone", "Patrol", "NavigateToBase", "MissionOrReturnToBase"]


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A mission whose second goal aborts (a failure on the way to zone_b), recorded."""
    folder = tmp_path_factory.mktemp("faulty")
    record = folder / "faulty.mcap"
    code, output = run_to_end([str(DEFAULT_TREE), "--speed", FAST, "--record", str(record),
                               "--sim-param", "abort_goal_numbers:=[2]"], folder / "report")
    assert code == 0, output
    return record


@pytest.fixture(scope="module")
def page(recording: Path) -> Any:
    """One replay studio and browser for the file's tests (each start costs seconds); the
    first test reads the page as it opens, at the recording's start."""
    studio, url = start_studio(["replay", str(recording)], recording.parent)
    try:
        with headless_chromium() as driver:
            driver.get(url)
            wait_for(driver, NAMES, lambda s: True, 30, "the page's first frame")
            yield driver
    finally:
        studio.stop()


def test_the_failure_mark_scrubs_to_the_failure(page: Any, tmp_path: Path) -> None:
    from selenium.webdriver.common.by import By

    start = state(page, NAMES)
    assert start["statuses"]["NavigateToBase"] == "INVALID"
    mark = page.find_element(By.CSS_SELECTOR, "#marks .mark.failure")
    t = float(mark.get_attribute("data-t"))
    mark.click()
    there = wait_for(page, NAMES, lambda s: s["t"] == t, 10, "the frame at the failure mark")
    assert there["statuses"]["NavigateToZone"] == "FAILURE"
    assert there["statuses"]["Patrol"] == "FAILURE"
    assert there["statuses"]["MissionOrReturnToBase"] == "RUNNING"
    assert any("goal 2 aborted" in r for r in there["reasons"]), there["reasons"]
    png = page.get_screenshot_as_png()
    (tmp_path / "failure.png").write_bytes(png)
    assert_drawn(png, there["rects"]["NavigateToZone"], "FAILURE", "NavigateToZone")
    assert_drawn(png, there["rects"]["Patrol"], "FAILURE", "Patrol")
    assert_drawn(png, there["rects"]["MissionOrReturnToBase"], "RUNNING",
                 "MissionOrReturnToBase")
    # the node panel: its last reason at this instant
    page.execute_script("selectNode(arguments[0])",
                        page.execute_script("return Object.values(studio.hello.tree.nodes)"
                                            ".find((f) => f.name === 'NavigateToZone').uid"))
    panel = page.find_element(By.ID, "node-panel")
    deadline = time.monotonic() + 10
    while "goal 2 aborted" not in panel.text and time.monotonic() < deadline:
        time.sleep(0.1)
    assert "last reason failure: goal to zone_b aborted" in panel.text
    assert "param action_name" in panel.text
    assert f"at {DEFAULT_TREE}:" in panel.text  # the recorded tree's own path


def test_the_scrubber_and_play_move_through_the_mission(page: Any) -> None:
    from selenium.webdriver.common.by import By

    hello = page.execute_script("return studio.hello.timeline")
    page.execute_script("const s = document.getElementById('scrubber');"
                        "s.value = s.max; s.dispatchEvent(new Event('input'));")
    end = wait_for(page, NAMES, lambda s: s["t"] == hello["end"], 10, "the end of the recording")
    assert end["complete"] and end["header"] == "SUCCESS (over)"
    assert end["statuses"]["NavigateToBase"] == "SUCCESS"
    png = page.get_screenshot_as_png()
    assert_drawn(png, end["rects"]["NavigateToBase"], "SUCCESS", "NavigateToBase")
    # a reason links to its instant
    page.find_element(By.CSS_SELECTOR, "#reasons li.failure").click()
    failure = wait_for(page, NAMES, lambda s: s["statuses"]["NavigateToZone"] == "FAILURE",
                       10, "the reason's instant")
    assert failure["t"] < end["t"]
    page.find_element(By.ID, "speed").send_keys("10")
    page.find_element(By.ID, "play").click()
    later = wait_for(page, NAMES, lambda s: s["t"] > failure["t"] + 2, 10, "playing on")
    assert later["robot"] != failure["robot"]
