"""What the browser tests read from the studio's page (``window.studio``) and its pixels."""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from sar_framework.engine.rendering.render import STATUS_COLOURS
from sar_framework.testing.browser import colour_share, headless_chromium, hex_rgb, start_studio

STATE = """
const uid = (name) => Object.values(studio.hello.tree.nodes).find((f) => f.name === name).uid;
const g = (name) => studio.nodes.get(uid(name));
const names = arguments[0];
const robot = document.getElementById("robot");
return {
  connected: studio.hello !== null && studio.frame !== null,
  t: studio.frame && studio.frame.t, tick: studio.frame && studio.frame.tick,
  complete: studio.frame && studio.frame.complete,
  header: document.getElementById("mission-status").textContent,
  statuses: Object.fromEntries(names.map((n) => [n, g(n).dataset.status])),
  rects: Object.fromEntries(names.map((n) => {
    const r = g(n).getBoundingClientRect(); return [n, [r.left, r.top, r.width, r.height]];
  })),
  robot: robot.dataset.x === undefined ? null : [+robot.dataset.x, +robot.dataset.y],
  reasons: [...document.querySelectorAll("#reasons li")].map((li) => li.textContent),
};
"""


def state(driver: Any, names: list[str]) -> dict[str, Any]:
    """The page's state for the nodes ``names``: statuses, on-screen boxes, robot, header."""
    return driver.execute_script(STATE, names)


def wait_for(driver: Any, names: list[str], found: Callable[[dict[str, Any]], bool],
             timeout: float, what: str) -> dict[str, Any]:
    """Poll the page until ``found`` says yes; its state then."""
    deadline = time.monotonic() + timeout
    last: dict[str, Any] = {}
    while time.monotonic() < deadline:  # outer safety bound
        try:
            last = state(driver, names)
        except Exception as err:  # the page may not have its tree yet
            last = {"error": str(err)}
        else:
            if last["connected"] and found(last):
                return last
        time.sleep(0.2)
    raise AssertionError(f"{what}: not seen within {timeout} s; last state: {last}")


def until(driver: Any, script: str, timeout: float = 60) -> Any:
    """Poll a script on the page until it returns something true; return that.

    The bound is an outer safety bound: a page's check answers in well under a second when
    idle, and 15 s was reached by a machine loaded with builds beside the suite.
    """
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:  # outer safety bound
        value = driver.execute_script(script)
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"not true within {timeout} s: {script}")


def drawn_status(png: bytes, rect: list[float]) -> dict[str, float]:
    """The share of each status colour inside a node's box on a screenshot."""
    return {status: colour_share(png, tuple(rect), hex_rgb(colour))
            for status, colour in STATUS_COLOURS.items()}


def assert_drawn(png: bytes, rect: list[float], status: str, name: str) -> None:
    """A node is filled with its status's colour on the screenshot, and with no other."""
    shares = drawn_status(png, rect)
    assert shares[status] > 0.3, f"{name}: {status} colour on {shares[status]:.0%}: {shares}"
    others = {s: v for s, v in shares.items() if s != status}
    assert max(others.values()) < 0.05, f"{name} drawn {status}, yet {others}"


@contextlib.contextmanager
def replay_page(recording: Path, names: list[str], bound: float = 60) -> Iterator[Any]:
    """A replay studio of ``recording`` and a browser on its page, once it drew a frame.

    ``bound`` is an outer safety bound on the first frame (seconds).
    """
    studio, url = start_studio(["replay", str(recording)], recording.parent)
    try:
        with headless_chromium() as driver:
            driver.get(url)
            wait_for(driver, names, lambda s: True, bound, "the page's first frame")
            yield driver
    finally:
        studio.stop()
