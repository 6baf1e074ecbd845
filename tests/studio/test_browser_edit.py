"""The tree editor in a real browser (headless chromium): an error typed shows its
``sar-tree validate`` diagnostic, completion fixes it, the diagram is redrawn, Save writes."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from sar_framework.cli import main
from sar_framework.testing.browser import (
    browser_missing,
    colour_share,
    headless_chromium,
    start_studio,
)

from .page import until

pytestmark = [pytest.mark.slow, pytest.mark.browser,
              pytest.mark.skipif(browser_missing() is not None, reason=str(browser_missing()))]

REPO = Path(__file__).resolve().parents[2]
TREE = REPO / "trees" / "tutorials" / "01_first_tree.yaml"
BAD_LINE = (255, 215, 210)  # #ffd7d2, a line with an error


def diagnostics(driver: Any) -> list[str]:
    return driver.execute_script(
        "return [...document.querySelectorAll('#diagnostics li')].map((li) => li.textContent)")


@dataclass
class Editing:
    """One ``studio edit`` of a copy of the tutorial tree, and a browser (shared: each start
    of a studio and of chromium costs seconds)."""

    url: str
    tree: Path
    driver: Any


@pytest.fixture(scope="module")
def editing(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Editing]:
    folder = tmp_path_factory.mktemp("edit")
    tree = folder / "tree.yaml"
    shutil.copy(TREE, tree)
    studio, url = start_studio(["edit", str(tree), "--root", str(folder)], folder)
    try:
        with headless_chromium() as driver:
            yield Editing(url, tree, driver)
    finally:
        studio.stop()


def test_save_without_the_token_writes_nothing(editing: Editing) -> None:
    driver, tree = editing.driver, editing.tree
    before = tree.read_text()
    driver.get(editing.url.split("?")[0])  # the address without its token
    until(driver, "return editor.checked && editor.checked.ok")
    driver.execute_script("document.getElementById('source').value += '# x\\n'")
    driver.find_element("id", "save").click()
    state = until(driver, "const t = document.getElementById('save-state').textContent;"
                          "return t.startsWith('not saved') && t")
    assert "a valid session token is required" in state
    assert tree.read_text() == before


def test_type_an_error_see_it_fix_it_and_save(editing: Editing, tmp_path: Path,
                                              capsys) -> None:
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    driver, tree, url = editing.driver, editing.tree, editing.url
    driver.get(url)
    until(driver, "return studio.hello && studio.hello.mode === 'edit'")
    until(driver, "return editor.checked && editor.checked.ok")
    assert diagnostics(driver) == ["✓ valid"]
    source = driver.find_element(By.ID, "source")
    # the caret at the end of the text, then a child typed by hand, misspelt
    driver.execute_script("arguments[0].focus();"
                          "arguments[0].setSelectionRange(1e9, 1e9)", source)
    source.send_keys("      - AdvanceZon: {name: Again}")
    until(driver, "return editor.checked && !editor.checked.ok")
    shown = [d for d in diagnostics(driver) if ": error: " in d]
    # the same line as sar-tree validate prints for that text
    tree_text = driver.execute_script("return arguments[0].value", source)
    check = tmp_path / "check" / "tree.yaml"
    check.parent.mkdir()
    check.write_text(tree_text)
    main(["validate", str(check)])
    printed = [line.replace(str(check), str(tree))
               for line in capsys.readouterr().err.splitlines() if ": error: " in line]
    assert shown == printed, (shown, printed)
    assert "unknown plugin 'AdvanceZon' (did you mean 'AdvanceZone'?)" in shown[0]
    png = driver.get_screenshot_as_png()
    (tmp_path / "error.png").write_bytes(png)
    box = driver.execute_script(
        "const r = document.getElementById('editor-wrap').getBoundingClientRect();"
        "return [r.left, r.top, r.width, r.height]")
    assert colour_share(png, tuple(box), BAD_LINE) > 0.002  # the line is marked
    # completion: put the caret after "AdvanceZon", take the schema's "AdvanceZone"
    driver.execute_script(
        "const s = arguments[0], at = s.value.indexOf('AdvanceZon:') + 10;"
        "s.setSelectionRange(at, at); s.dispatchEvent(new Event('input'));", source)
    options = until(driver, "return editor.options.length && editor.options")
    assert options[0][0] == "AdvanceZone"
    source.send_keys(Keys.TAB)
    until(driver, "return editor.checked && editor.checked.ok")
    assert diagnostics(driver) == ["✓ valid"]
    names = until(driver, "return studio.hello && [...studio.nodes.keys()].length === 4 "
                          "&& [...document.querySelectorAll('#tree g.node title')]"
                          ".map((t) => t.textContent)")
    assert len(names) == 4  # the diagram redrawn with the new leaf
    assert "Again" in driver.find_element(By.ID, "tree").text
    driver.find_element(By.ID, "save").click()
    until(driver, "return document.getElementById('save-state').textContent"
                  ".startsWith('saved')")
    saved = tree.read_text()
    assert saved == driver.execute_script("return arguments[0].value", source)
    assert "- AdvanceZone: {name: Again}" in saved
    assert main(["validate", str(tree)]) == 0
    # no mission here: "Apply to mission" is the live studio's (test_browser_mission)
    assert not driver.find_element(By.ID, "apply").is_displayed()
