"""Hot reload from the studio in a real browser (headless chromium), on a real mission.

One full-stack run: ``sar-tree studio live --run TREE`` starts the mission in the embedded
simulator; the page's editor, opened on the mission's tree file, shows the diagnostic of a
misspelt leaf typed into it; applied anyway, the runner refuses it and the page says why;
fixed and applied, the runner swaps it in, the page shows the swap event and draws the new
tree from the file (with its params), and the mission completes.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from e2e.helpers import DEFAULT_TREE

from sar_framework.testing.browser import browser_missing, headless_chromium, start_studio

from .page import assert_drawn, until, wait_for

pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.browser,
              pytest.mark.skipif(browser_missing() is not None, reason=str(browser_missing()))]

SPEED = "20"
NAMES = ["NavigateToZone", "MissionOrReturnToBase"]
ANCHOR = "- AdvanceZone: {}"
TYPED = "\n            - Dwel: {name: Linger, duration: 0.5}"


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


def test_edit_the_running_tree_see_a_refusal_then_apply_and_see_the_swap(tmp_path: Path
                                                                         ) -> None:
    from selenium.webdriver.common.by import By

    tree = tmp_path / "mission.yaml"
    tree.write_text(DEFAULT_TREE.read_text(encoding="utf-8"), encoding="utf-8")
    studio, url = start_studio(["live", "--run", str(tree), "--speed", SPEED], tmp_path)
    try:
        with headless_chromium() as driver:
            driver.get(url)  # typed while the mission starts, applied once it drives
            until(driver, "return studio.hello !== null", 60)
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
            wait_for(driver, NAMES, lambda s: s["statuses"]["NavigateToZone"] == "RUNNING",
                     120, "the first zone goal running")
            # applied as it is: saved, and the runner refuses it; the mission goes on
            refused = applied(driver, "refused by the mission")
            assert "the tree goes on" in refused and "Dwel" in refused
            until(driver, "return [...document.querySelectorAll('#reasons li')]"
                          ".some((li) => li.className === 'reload_refused')")
            # fixed by hand: the caret after "Dwel", an "l"
            driver.execute_script("const s = arguments[0], at = s.value.indexOf('Dwel:') + 4;"
                                  "s.focus(); s.setSelectionRange(at, at)", source)
            source.send_keys("l")
            until(driver, "return editor.checked && editor.checked.ok")
            swapped = applied(driver, "applied")
            assert "1 added (Linger)" in swapped, swapped
            assert "- Dwell: {name: Linger, duration: 0.5}" in tree.read_text()
            until(driver, "return [...document.querySelectorAll('#reasons li')]"
                          ".some((li) => li.className === 'tree_swapped')")
            assert any("1 added (Linger)" in line for line in feed(driver))
            # the running tree's diagram, drawn again from the file (the status's own form
            # may show first, while the file is drawn): params included
            linger = until(driver, "const tree = studio.hello.tree;"
                                   "const f = Object.values(tree.nodes)"
                                   ".find((n) => n.name === 'Linger');"
                                   "return tree.source === 'file' && f && studio.nodes.has(f.uid)"
                                   " && f", 30)
            assert linger["params"]["duration"] == 0.5 and linger["kind"] == "Dwell"
            end = wait_for(driver, NAMES, lambda s: s["complete"], 180, "the mission's end")
            png = driver.get_screenshot_as_png()
            (tmp_path / "swapped.png").write_bytes(png)
            assert end["header"].startswith("SUCCESS"), end
            assert_drawn(png, end["rects"]["MissionOrReturnToBase"], "SUCCESS",
                         "MissionOrReturnToBase")
        studio.wait_for_output(r"Mission SUCCESS", timeout=30)
        studio.wait_for_output(r"tree reloads: 1 swapped, 1 refused", timeout=30)
    finally:
        assert studio.stop() == 0
