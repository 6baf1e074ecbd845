"""A recording in the studio, in a real browser (headless chromium): the timeline's failure
mark scrubs to the failure, with the statuses, reasons and colours of that instant; a row of
the event list moves the timeline to its event's instant, with the recorded statuses there."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

import pytest
from e2e.helpers import DEFAULT_TREE, FAST, run_to_end

from sar_framework.recording.readback import read_recording
from sar_framework.testing.browser import (
    browser_missing,
    colour_share,
    hex_rgb,
)

from .page import assert_drawn, replay_page, state, until, wait_for

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
    with replay_page(recording, NAMES, 30) as driver:
        yield driver


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
    deadline = time.monotonic() + 60  # outer safety bound (drawn within a second)
    while "goal 2 aborted" not in panel.text and time.monotonic() < deadline:  # outer safety bound
        time.sleep(0.1)
    assert "goal 2 aborted" in panel.text, panel.text
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
    # The robot stands at the failure for as long as the tree took to send its next goal: on
    # a loaded machine that is seconds of simulated time. So wait for the move itself.
    later = wait_for(page, NAMES, lambda s: s["robot"] != failure["robot"], 60,
                     "the robot moving on as the recording plays")
    assert later["t"] > failure["t"]


#: The marked row's background in the event list (studio.css, ``#events li.now a``).
ROW_NOW = "#ffe08a"
ROW = """
const li = document.querySelector(`#events li[data-i="${arguments[0]}"]`);
const r = li.getBoundingClientRect();
return {now: li.classList.contains("now"), marked: eventList.now,
        rect: [r.left, r.top, r.width, r.height],
        scrubber: +document.getElementById("scrubber").value,
        clock: document.getElementById("clock").textContent,
        tree: Object.fromEntries([...studio.nodes].map(([uid, g]) => [uid, g.dataset.status]))};
"""


def recorded_statuses(recording: Path, t: float) -> dict[str, str]:
    """The node statuses of the recording's last tick at or before ``t``."""
    documents = [d for d in read_recording(recording).statuses if d["sim_s"] <= t]
    return {n["uid"]: n["status"] for n in documents[-1]["nodes"]}


def test_an_event_row_moves_the_timeline_to_its_instant(page: Any, recording: Path,
                                                       tmp_path: Path) -> None:
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.select import Select

    timeline = page.execute_script("return studio.hello.timeline")
    events = timeline["events"]
    kinds = {e["kind"] for e in events}
    assert {"started", "status", "navigation", "zone_reached", "detection", "note", "failure",
            "survivor_broadcast", "completion"} <= kinds, kinds
    assert len(page.find_elements(By.CSS_SELECTOR, "#events li")) == len(events)
    assert [e["t"] for e in events] == sorted(e["t"] for e in events)
    names = [*NAMES, "DetectSurvivor"]
    detection = next(e for e in events if e["kind"] == "detection" and e["status"] == "FOUND")
    navigation = next(e for e in events if e["kind"] == "navigation"
                      and e["node"] == "NavigateToBase")  # the return after the failure
    for event in (detection, navigation):
        link = page.find_element(By.CSS_SELECTOR, f'#events li[data-i="{event["i"]}"] a')
        page.execute_script("arguments[0].scrollIntoView({block: 'center'})", link)
        link.click()
        there = wait_for(page, names, lambda s, t=event["t"]: s["t"] == t, 10,
                         f"the instant of {event['kind']} {event['message']}")
        row = page.execute_script(ROW, event["i"])
        assert row["now"] and row["marked"] == event["i"]
        assert abs(row["scrubber"] - event["t"]) < 0.011
        assert row["clock"] == f"{event['t'] - timeline['start']:.1f} s"
        recorded = recorded_statuses(recording, event["t"])
        assert {uid: row["tree"][uid] for uid in recorded} == recorded
        assert page.execute_script("return location.hash") == f"#t={event['t']}"
    # at the return to base: the zone's navigation failed and the base's runs
    assert there["statuses"]["NavigateToZone"] == "FAILURE"
    assert there["statuses"]["NavigateToBase"] == "RUNNING"
    png = page.get_screenshot_as_png()
    (tmp_path / "event.png").write_bytes(png)
    assert_drawn(png, there["rects"]["NavigateToZone"], "FAILURE", "NavigateToZone")
    assert_drawn(png, there["rects"]["NavigateToBase"], "RUNNING", "NavigateToBase")
    assert colour_share(png, tuple(row["rect"]), hex_rgb(ROW_NOW)) > 0.3
    # one kind only
    Select(page.find_element(By.ID, "event-kind")).select_by_value("detection")
    shown = [li for li in page.find_elements(By.CSS_SELECTOR, "#events li") if li.is_displayed()]
    assert len(shown) == sum(e["kind"] == "detection" for e in events)
    Select(page.find_element(By.ID, "event-kind")).select_by_value("")
    # playing on marks later rows
    page.find_element(By.ID, "play").click()
    until(page, f"return eventList.now > {navigation['i']}")
    page.find_element(By.ID, "play").click()


SCALE = """
const [n, shows] = arguments;
const start = studio.hello.timeline.start;
const rows = Array.from({length: n}, (_, i) => ({
  i, t: start + i * 0.01, sim_s: start + i * 0.01, seq: i + 1, kind: i % 7 ? "status" : "note",
  node: "N", uid: "0", status: "", fields: [], mark: "", message: `event ${i}`}));
fillEvents(rows, start);
let reads = 0;
const times = eventList.times;
eventList.times = new Proxy(times, {get(target, key) {
  if (typeof key === "string" && /^[0-9]+$/.test(key)) reads += 1;
  const value = target[key];
  return typeof value === "function" ? value.bind(target) : value;
}});
const observer = new MutationObserver(() => {});
observer.observe(document.getElementById("events"),
                 {subtree: true, attributes: true, attributeFilter: ["class"]});
const frame = window.requestAnimationFrame;
let frames = 0;
window.requestAnimationFrame = (callback) => { frames += 1; return frame(callback); };
const wrong = [];
let mostReads = 0;
for (let k = 0; k < shows; k++) {
  const want = (k * 7919) % n;
  reads = 0;
  showEventAt(start + want * 0.01);
  mostReads = Math.max(mostReads, reads);
  if (eventList.now !== want) wrong.push([want, eventList.now]);
}
const classChanges = observer.takeRecords().length;
observer.disconnect();
window.requestAnimationFrame = frame;
eventList.times = times;
const marked = document.querySelectorAll("#events li.now").length;
fillEvents(studio.hello.timeline.events, start);
return {wrong, mostReads, classChanges, frames, marked};
"""


def test_the_event_list_keeps_up_with_thousands_of_events(page: Any) -> None:
    # What keeps it fast, counted rather than timed (bench_studio.py prints the times):
    # each instant is found by bisection (no scan), changes at most two rows' class, and
    # the list scrolls once per drawn frame, however many instants are shown in between.
    n, shows = 10000, 2000
    seen = page.execute_script(SCALE, n, shows)
    assert seen["wrong"] == [], seen["wrong"][:5]
    assert seen["mostReads"] <= math.ceil(math.log2(n)) + 2, seen
    assert seen["classChanges"] <= 2 * shows, seen
    assert seen["frames"] <= 1, seen  # 0 when a scroll was already pending
    assert seen["marked"] == 1, seen


def test_an_address_with_an_instant_opens_there(page: Any) -> None:
    events = page.execute_script("return studio.hello.timeline.events")
    detection, zone = (next(e for e in events if e["kind"] == kind)
                       for kind in ("detection", "zone_reached"))
    base = page.current_url.split("#")[0]
    page.get(f"{base}#t={detection['t']}")  # the same page: the address changes
    wait_for(page, NAMES, lambda s: s["t"] == detection["t"], 10, "the linked instant")
    page.get(f"{base}#t={zone['t']}")
    page.refresh()  # a page opened on the address
    wait_for(page, NAMES, lambda s: s["t"] == zone["t"], 30, "the linked instant on opening")
    assert page.execute_script("return eventList.now") == max(
        e["i"] for e in events if e["t"] == zone["t"])
