"""A recording of a tree whose app comes from its ``plugins:`` (the inspection patrol), in
the studio in a real browser (headless chromium): the app is loaded from the recorded plugin
files, so its events mark the timeline and its words fill the header, as in the run."""

from __future__ import annotations

import shutil
from typing import Any

import pytest
from e2e.patrol_example import example_folder, run

from sar_framework.testing.browser import browser_missing

from .page import replay_page, until, wait_for

pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.browser,
              pytest.mark.skipif(browser_missing() is not None, reason=str(browser_missing()))]

NAMES = ["GoToShelf", "Scan", "GoHome"]
SCANS = ["A", "B", "C"]


@pytest.fixture(scope="module")
def page(tmp_path_factory: pytest.TempPathFactory) -> Any:
    """The patrol run once round (a low battery), recorded, its folder then removed, and
    the recording opened in a replay studio."""
    folder = example_folder(tmp_path_factory.mktemp("patrol"))
    run(folder, "--set", "battery=30", "--record", "out/patrol.mcap")
    record = folder.parent / "patrol.mcap"
    (folder / "out" / "patrol.mcap").rename(record)
    shutil.rmtree(folder)  # the tree and the app's files are gone: the recording has them
    with replay_page(record, NAMES) as driver:
        yield driver


def test_the_apps_events_mark_the_timeline_and_its_words_fill_the_header(page: Any) -> None:
    from selenium.webdriver.common.by import By

    timeline = page.execute_script("return studio.hello.timeline")
    scans = [m for m in timeline["marks"] if m["label"].startswith("shelf_scanned")]
    assert [m["label"] for m in scans] == [f"shelf_scanned {s}" for s in SCANS], \
        timeline["marks"]
    assert {m["kind"] for m in scans} == {"found"}
    assert [e["fields"] for e in timeline["events"] if e["kind"] == "shelf_scanned"] == \
        [[s] for s in SCANS]
    drawn = page.find_elements(By.CSS_SELECTOR, "#marks .mark.found")
    assert len(drawn) == len(SCANS)
    drawn[0].click()
    first = float(drawn[0].get_attribute("data-t"))
    wait_for(page, NAMES, lambda s: s["t"] == first, 60, "the frame at the first scan")
    # just before the third scan: the status after the second one says two
    before_third = float(drawn[2].get_attribute("data-t")) - 0.01
    page.execute_script("pause(); seek(arguments[0])", before_third)
    wait_for(page, NAMES, lambda s: abs(s["t"] - before_third) < 1e-6, 60,
             "the frame before the third scan")
    until(page, "return document.getElementById('app-status').textContent"
                " === 'shelves scanned: 2'")
    page.execute_script("const s = document.getElementById('scrubber');"
                        "s.value = s.max; s.dispatchEvent(new Event('input'));")
    end = wait_for(page, NAMES, lambda s: s["t"] == timeline["end"], 60,
                   "the end of the recording")
    assert end["statuses"]["GoHome"] == "SUCCESS"
    assert page.find_element(By.ID, "app-status").text == "shelves scanned: 3"
