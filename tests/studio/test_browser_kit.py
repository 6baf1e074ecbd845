"""The browser kit itself: why a browser is missing, in one line; colours counted right."""

from __future__ import annotations

import io

import pytest

from sar_framework.testing import browser


def test_no_browser_is_said_in_one_line(monkeypatch) -> None:
    pytest.importorskip("selenium")
    monkeypatch.setattr(browser.shutil, "which", lambda name: None)
    reason = browser.browser_missing()
    assert reason == ("no chromium with chromedriver "
                      "(apt-get install chromium chromium-driver)")


def test_colour_share_counts_one_colour_in_a_box() -> None:
    image_module = pytest.importorskip("PIL.Image")
    image = image_module.new("RGB", (10, 10), (255, 255, 255))
    for x in range(5):
        for y in range(10):
            image.putpixel((x, y), (143, 217, 143))
    png = io.BytesIO()
    image.save(png, "PNG")
    green = browser.hex_rgb("#8fd98f")
    assert browser.colour_share(png.getvalue(), (0, 0, 10, 10), green) == 0.5
    assert browser.colour_share(png.getvalue(), (0, 0, 5, 10), green) == 1.0
    assert browser.colour_share(png.getvalue(), (5, 0, 5, 10), green) == 0.0
