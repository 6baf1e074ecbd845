"""The live studio on one real mission, in a real browser (headless chromium).

One full-stack run for all of the live view's tests (each mission costs tens of seconds on
a loaded 2-core machine): ``sar-tree studio live --run TREE`` starts the mission in the
embedded simulator, and the tests below run in file order against it:

1. the page follows the mission: node colours change with the ticks, the robot moves;
2. hot reload: the page's editor, opened on the mission's tree file, shows the diagnostic of
   a misspelt leaf typed into it; applied anyway, the runner refuses it and the page says
   why; fixed and applied, the runner swaps it in, the page shows the swap event and draws
   the new tree from the file (with its params). The tree under test holds the mission
   before its return to base (a ``Dwell`` of a day) until that swap takes the hold out, so
   the reload lands mid-mission however slow the machine;
3. the mission completes, its end stays on the page and in ``api/frame``, and the studio
   (with the mission it started) ends cleanly.
"""

from __future__ import annotations

import json
import math
import time
import urllib.request
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest
from e2e.helpers import DEFAULT_TREE

from sar_framework.testing.browser import browser_missing, headless_chromium, start_studio
from sar_framework.testing.processes import NodeProcess

from .page import assert_drawn, state, until, wait_for

pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.browser,
              pytest.mark.skipif(browser_missing() is not None, reason=str(browser_missing()))]

SPEED = "10"
NAMES = ["NavigateToZone", "NavigateToBase", "MissionOrReturnToBase"]
ANCHOR = "- AdvanceZone: {}"
TYPED = "\n            - Dwel: {name: Linger, duration: 0.5}"
TO_BASE = "            NavigateToBase: {}\n"
HELD = ("            sequence:\n"
        "              name: HoldThenBase\n"
        "              memory: true\n"
        "              children:\n"
        "                - Dwell: {name: Hold, duration: 86400.0}\n"
        "                - NavigateToBase: {}\n")


@dataclass
class Mission:
    """The shared mission: the studio that runs it, its page, and what the tests saw."""

    studio: NodeProcess
    url: str
    driver: Any
    tree: Path
    folder: Path
    seen: set[str] = field(default_factory=set)  # node statuses api/frame reported


@pytest.fixture(scope="module")
def mission(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Mission]:
    """``studio live --run`` of a copy of the default tree (edited by the reload test)."""
    folder = tmp_path_factory.mktemp("mission")
    tree = folder / "mission.yaml"
    default = DEFAULT_TREE.read_text(encoding="utf-8")
    assert default.count(TO_BASE) == 1
    tree.write_text(default.replace(TO_BASE, HELD), encoding="utf-8")
    studio, url = start_studio(["live", "--run", str(tree), "--speed", SPEED], folder)
    try:
        with headless_chromium() as driver:
            driver.get(url)
            until(driver, "return studio.hello !== null", 60)
            yield Mission(studio, url, driver, tree, folder)
    finally:
        studio.stop()


def api(url: str, what: str) -> dict:
    base = url.split("?", maxsplit=1)[0]
    with urllib.request.urlopen(f"{base}api/{what}", timeout=10) as answer:
        return json.load(answer)


def frame_statuses(url: str) -> set[str]:
    return {status for status, _message, _visited in api(url, "frame")["nodes"].values()}


def test_the_page_follows_the_running_mission(mission: Mission) -> None:
    driver = mission.driver
    running = wait_for(driver, NAMES, lambda s: s["statuses"]["NavigateToZone"] == "RUNNING"
                       and s["robot"] is not None, 90, "a zone goal running")
    mission.seen |= frame_statuses(mission.url)
    png = driver.get_screenshot_as_png()
    (mission.folder / "running.png").write_bytes(png)
    assert_drawn(png, running["rects"]["NavigateToZone"], "RUNNING", "NavigateToZone")
    seen = {running["statuses"]["NavigateToZone"]}
    start = running["robot"]

    def moved_and_recoloured(s: dict) -> bool:
        # a zone's SUCCESS lasts one tick (50 ms at 10x), too short to poll; its goal's
        # RUNNING colour ending is not (the mission holds at the last zone)
        seen.add(s["statuses"]["NavigateToZone"])
        return math.dist(s["robot"], start) > 1.0 and len(seen) > 1

    moved = wait_for(driver, NAMES, moved_and_recoloured, 90,
                     "the robot 1 m on and the zone goal's colour changed")
    assert moved["tick"] > running["tick"]


def applied(driver: Any, prefix: str) -> str:
    """Click "Apply to mission" and wait for the answer starting with ``prefix``."""
    from selenium.webdriver.common.by import By

    driver.execute_script("document.getElementById('save-state').textContent = ''")
    driver.find_element(By.ID, "apply").click()
    return until(driver, "const t = document.getElementById('save-state').textContent;"
                         f"return t.startsWith({prefix!r}) && t", 60)


def feed(driver: Any) -> list[str]:
    return driver.execute_script(
        "return [...document.querySelectorAll('#reasons li')].map((li) => li.textContent)")


def test_edit_the_running_tree_see_a_refusal_then_apply_and_see_the_swap(mission: Mission
                                                                         ) -> None:
    from selenium.webdriver.common.by import By

    driver, tree = mission.driver, mission.tree
    assert not driver.find_element(By.ID, "editor-pane").is_displayed()
    driver.find_element(By.ID, "edit-open").click()
    until(driver, "return editor.checked && editor.checked.ok")
    source = driver.find_element(By.ID, "source")
    driver.execute_script("const s = arguments[0], at = s.value.indexOf(arguments[1])"
                          " + arguments[1].length; s.focus(); s.setSelectionRange(at, at)",
                          source, ANCHOR)
    source.send_keys(TYPED)
    error = until(driver, "return editor.checked && !editor.checked.ok && "
                          "editor.checked.diagnostics[0].text")
    assert error.startswith(f"{tree}:53:") and "unknown plugin 'Dwel'" in error, error
    wait_for(driver, ["Hold"], lambda s: s["statuses"]["Hold"] == "RUNNING", 120,
             "the mission held before its return to base")
    # applied as it is: saved, and the runner refuses it; the mission goes on (held)
    refused = applied(driver, "refused by the mission")
    assert "the tree goes on" in refused and "Dwel" in refused
    until(driver, "return [...document.querySelectorAll('#reasons li')]"
                  ".some((li) => li.className === 'reload_refused')")
    assert state(driver, ["Hold"])["statuses"]["Hold"] == "RUNNING"
    # fixed by hand: the hold taken out, then the caret after "Dwel", an "l"
    driver.execute_script("const s = arguments[0]; s.value = s.value.replace(arguments[1],"
                          " arguments[2]); const at = s.value.indexOf('Dwel:') + 4;"
                          "s.focus(); s.setSelectionRange(at, at)", source, HELD, TO_BASE)
    source.send_keys("l")
    until(driver, "return editor.checked && editor.checked.ok")
    swapped = applied(driver, "applied")
    assert "2 added (Linger, NavigateToBase)" in swapped and "halted Hold" in swapped, swapped
    assert "- Dwell: {name: Linger, duration: 0.5}" in tree.read_text()
    assert "Hold" not in tree.read_text()
    until(driver, "return [...document.querySelectorAll('#reasons li')]"
                  ".some((li) => li.className === 'tree_swapped')")
    assert any("added (Linger, NavigateToBase)" in line for line in feed(driver))
    # the running tree's diagram, drawn again from the file (the status's own form may show
    # first, while the file is drawn): params included
    linger = until(driver, "const tree = studio.hello.tree;"
                           "const f = Object.values(tree.nodes)"
                           ".find((n) => n.name === 'Linger');"
                           "return tree.source === 'file' && f && studio.nodes.has(f.uid)"
                           " && f", 30)
    assert linger["params"]["duration"] == 0.5 and linger["kind"] == "Dwell"


def test_the_mission_completes_and_its_end_stays(mission: Mission) -> None:
    driver, studio = mission.driver, mission.studio
    end = wait_for(driver, NAMES, lambda s: s["complete"], 180, "the mission's end")
    now = api(mission.url, "frame")
    assert now["complete"] and now["status"] == "SUCCESS", now
    mission.seen |= frame_statuses(mission.url)
    assert {"RUNNING", "SUCCESS"} <= mission.seen
    assert now["robot"] is not None and len(now["path"]) > 10
    assert api(mission.url, "hello")["tree"]["source"] == "file"  # the --run tree, its params
    studio.wait_for_output(r"Mission SUCCESS", timeout=30)  # the mission's own lines
    studio.wait_for_output(r"tree reloads: 1 swapped, 1 refused", timeout=30)
    # nothing arrives any more; the final state is still drawn
    time.sleep(1.0)
    final = wait_for(driver, NAMES, lambda s: s["tick"] == end["tick"], 5, "the end")
    png = driver.get_screenshot_as_png()
    (mission.folder / "final.png").write_bytes(png)
    assert final["header"] == "SUCCESS (over)"
    assert final["statuses"]["NavigateToBase"] == "SUCCESS"
    assert_drawn(png, final["rects"]["NavigateToBase"], "SUCCESS", "NavigateToBase")
    assert_drawn(png, final["rects"]["MissionOrReturnToBase"], "SUCCESS",
                 "MissionOrReturnToBase")
    assert math.dist(final["robot"], (0.0, 0.0)) < 0.5  # back at base
    assert api(mission.url, "frame")["tick"] == now["tick"]  # over: the end stays
    assert state(driver, NAMES)["tick"] == end["tick"]
    assert studio.stop() == 0
