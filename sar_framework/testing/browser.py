"""A real browser for the studio's tests, benchmark and pictures: Debian's chromium, headless.

:func:`browser_missing` says why no browser can be driven here (or None);
:func:`headless_chromium` opens one through selenium with the system's
``/usr/bin/chromedriver`` (selenium is given both paths and told to stay offline, so it
never downloads a browser or a driver); :func:`record_mission` records the reference
mission with a fault; :func:`start_studio` starts ``sar-tree studio``
in a child process and returns it with the page's address; :func:`colour_share` measures
how much of a screenshot's rectangle is one colour (how the tests check node colours).
"""

from __future__ import annotations

import contextlib
import io
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from sar_framework.testing.processes import NodeProcess

CHROMEDRIVER = Path("/usr/bin/chromedriver")
REPO = Path(__file__).resolve().parents[2]
REFERENCE_TREE = REPO / "trees" / "search_and_rescue.yaml"
#: Where Debian installs chromium (``apt-get install chromium chromium-driver``).
CHROMIUM_NAMES = ("chromium", "chromium-browser")


def _chromium() -> str | None:
    return next((found for name in CHROMIUM_NAMES if (found := shutil.which(name))), None)


def browser_missing() -> str | None:
    """Why the studio's browser tests cannot run here, in one line; None when they can."""
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed (requirements/dev.txt)"
    if _chromium() is None or not CHROMEDRIVER.is_file():
        return "no chromium with chromedriver (apt-get install chromium chromium-driver)"
    return None


@contextlib.contextmanager
def headless_chromium(width: int = 1400, height: int = 900) -> Iterator[Any]:
    """A selenium WebDriver on headless chromium, quit on leaving the block.

    Args:
        width: Window width, CSS pixels.
        height: Window height.
    """
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    os.environ.setdefault("SE_OFFLINE", "true")  # selenium manager: never download
    # Its profile and temporary files in a folder removed after it quit (chromium leaves an
    # org.chromium.Chromium.* folder in the temp dir otherwise).
    with tempfile.TemporaryDirectory(prefix="chromium_") as folder:
        options = webdriver.ChromeOptions()
        options.binary_location = _chromium() or CHROMIUM_NAMES[0]
        for argument in ("--headless=new", "--no-sandbox", "--disable-gpu",
                         "--disable-dev-shm-usage", "--force-device-scale-factor=1",
                         f"--window-size={width},{height}", f"--user-data-dir={folder}/profile"):
            options.add_argument(argument)
        service = Service(str(CHROMEDRIVER), env={**os.environ, "TMPDIR": folder})
        driver = webdriver.Chrome(service=service, options=options)
        try:
            yield driver
        finally:
            driver.quit()


def record_mission(path: Path, sim_param: str, speed: float = 20.0,
                   timeout: float = 1800.0) -> Path:
    """Record the reference mission with one simulator fault or setting; return ``path``.

    Args:
        path: The ``.mcap`` to write (the report goes beside it).
        sim_param: One ``--sim-param`` (``abort_goal_numbers:=[2]``, ``speed_scale:=0.25``).
        speed: The simulator's speed factor.
        timeout: Seconds the run may take.
    """
    subprocess.run([sys.executable, "-m", "sar_framework", "run", str(REFERENCE_TREE),
                    "--speed", f"{speed:g}", "--sim-param", sim_param, "--record", str(path),
                    "--report-dir", str(path.with_suffix(""))],
                   check=True, capture_output=True, timeout=timeout, cwd=REPO)
    return path


def start_studio(args: Sequence[str], log_dir: Path, label: str = "studio"
                 ) -> tuple[NodeProcess, str]:
    """Start ``sar-tree studio ARGS`` (a free port) and wait for its address.

    Returns:
        The process (stop it when done) and the page's URL with the token.
    """
    process = NodeProcess(["-m", "sar_framework", "studio", *args], label,
                          log_dir=log_dir).start()
    try:
        url = process.wait_for_output(r"open: (http://\S+)", timeout=60).group(1)
    except AssertionError:
        process.stop()
        raise
    return process, url


def colour_share(png: bytes, box: tuple[float, float, float, float],
                 rgb: tuple[int, int, int], tolerance: int = 6) -> float:
    """The share of a screenshot's pixels inside ``box`` that are the colour ``rgb``.

    Args:
        png: The screenshot.
        box: ``(left, top, width, height)`` in the screenshot's pixels.
        rgb: The colour.
        tolerance: Largest difference per channel still counted.
    """
    import numpy as np
    from PIL import Image

    image = Image.open(io.BytesIO(png)).convert("RGB")
    left, top, width, height = (round(v) for v in box)
    crop = np.asarray(image.crop((left, top, left + max(width, 1), top + max(height, 1))),
                      dtype=np.int16)
    same = np.all(np.abs(crop - np.array(rgb, dtype=np.int16)) <= tolerance, axis=2)
    return float(same.mean())


def hex_rgb(colour: str) -> tuple[int, int, int]:
    """``"#8fd98f"`` -> ``(143, 217, 143)``."""
    return int(colour[1:3], 16), int(colour[3:5], 16), int(colour[5:7], 16)
