"""``sar-tree studio live --run TREE``: one command starts the mission and shows it."""

from __future__ import annotations

import json
import time
import urllib.request
from pathlib import Path

import pytest
from e2e.helpers import DEFAULT_TREE, FAST

from sar_framework.testing.browser import start_studio

pytestmark = [pytest.mark.ros, pytest.mark.slow]


def frame(url: str) -> dict:
    base = url.split("?", maxsplit=1)[0]
    with urllib.request.urlopen(f"{base}api/frame", timeout=10) as answer:
        return json.load(answer)


def test_run_starts_the_mission_and_the_end_stays(tmp_path: Path) -> None:
    studio, url = start_studio(["live", "--run", str(DEFAULT_TREE), "--speed", FAST], tmp_path)
    try:
        deadline = time.monotonic() + 150
        seen: set[str] = set()
        while time.monotonic() < deadline:
            now = frame(url)
            seen.update(status for status, _message, _visited in now["nodes"].values())
            if now["complete"]:
                break
            time.sleep(0.3)
        assert now["complete"] and now["status"] == "SUCCESS", now
        assert {"RUNNING", "SUCCESS"} <= seen
        assert now["robot"] is not None and len(now["path"]) > 10
        with urllib.request.urlopen(f"{url.split('?')[0]}api/hello", timeout=10) as answer:
            hello = json.load(answer)
        assert hello["tree"]["source"] == "file"  # the --run tree, with its params
        studio.wait_for_output(r"Mission SUCCESS", timeout=30)  # the mission's own lines
        time.sleep(1.0)
        assert frame(url)["tick"] == now["tick"]  # over: nothing more, the end stays
    finally:
        assert studio.stop() == 0
