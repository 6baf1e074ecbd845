"""Helpers for the end-to-end tests: ``sar-tree run`` as a real process, its children, files."""

from __future__ import annotations

import json
import os
import re
import time
from pathlib import Path
from typing import Any

from sar_testing.processes import NodeProcess

REPO = Path(__file__).resolve().parents[2]
DEFAULT_TREE = REPO / "trees" / "search_and_rescue.yaml"
SKIP_TREE = REPO / "trees" / "examples" / "patrol_skip_unreachable.yaml"
SIX_ZONES = REPO / "config" / "examples" / "six_zones.yaml"
SIX_SURVIVORS = REPO / "config" / "examples" / "six_zones_survivors.yaml"
FAST = "40"  # speed factor for the tests that are not about the default run
NAV2_TREE = REPO / "trees" / "examples" / "search_and_rescue_nav2.yaml"

SPEC_LINES = [
    "--- Zone 1/4: zone_a (-3.00, 3.00) ---",
    "Reached zone_a.",
    "Detection request for zone_a: FOUND at (-2.50, 3.20)",
    "Report received: survivor_1 at (-2.50, 3.20). Acknowledged.",
    "--- Zone 2/4: zone_b (3.50, 3.00) ---",
    "Reached zone_b.",
    "No survivor found at zone_b.",
    "--- Zone 3/4: zone_c (4.00, -3.00) ---",
    "Reached zone_c.",
    "Detection request for zone_c: FOUND at (4.10, -2.50)",
    "Report received: survivor_2 at (4.10, -2.50). Acknowledged.",
    "--- Zone 4/4: zone_d (-3.50, -3.00) ---",
    "Reached zone_d.",
    "No survivor found at zone_d.",
    "All zones visited. Returning to base.",
    "Reached base station.",
    "Mission complete.",
]


PROGRESS = re.compile(r"^\[\s*([0-9.]+)s\] \w+\s*\| (.*)$", re.MULTILINE)
SAME_MOMENT_S = 0.05
"""Lines of two processes read within this many seconds may come in either order."""


def in_order(text: str, lines: list[str]) -> None:
    """Every line is printed, in order; lines from two processes may swap at one moment."""
    printed = [(float(t), message) for t, message in PROGRESS.findall(text)]
    start, last = 0, 0.0
    for line in lines:
        found = next((i for i in range(start, len(printed)) if printed[i][1] == line), None)
        if found is None:  # printed a moment before the previous line, by another process
            found = next((i for i in range(len(printed)) if printed[i][1] == line
                          and printed[i][0] >= last - SAME_MOMENT_S), None)
        assert found is not None, f"missing (or out of order): {line!r}\n{text}"
        assert printed[found][0] >= last - SAME_MOMENT_S, f"out of order: {line!r}\n{text}"
        start, last = max(start, found + 1), max(last, printed[found][0])


def sar_tree_run(args: list[str], report_dir: Path, label: str = "sar_tree_run") -> NodeProcess:
    """A started ``python -m sar_framework run ...`` process (output in its log file).

    Args:
        args: Arguments after ``run`` (``--report-dir`` is added).
        report_dir: The report folder (also where the process's own output goes).
        label: Name of the output file.
    """
    report_dir.mkdir(parents=True, exist_ok=True)
    logs = report_dir.parent / f"{report_dir.name}_out"
    logs.mkdir(exist_ok=True)
    process = NodeProcess(["-m", "sar_framework", "run", *args, "--report-dir", str(report_dir)],
                          label, log_dir=logs)
    return process.start()


def run_to_end(args: list[str], report_dir: Path, timeout: float = 120.0) -> tuple[int, str]:
    """Run ``sar-tree run`` to its end; return the exit code and everything it printed."""
    process = sar_tree_run(args, report_dir)
    try:
        code = process.wait(timeout=timeout)
    finally:
        process.stop()
    return code, process.output


def child_pids(pid: int) -> list[int]:
    """The pids of the direct children of ``pid`` (from /proc)."""
    children = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        # "pid (comm) state ppid ...": comm may hold spaces, so split after the last ')'
        fields = stat[stat.rindex(")") + 2:].split()
        if int(fields[1]) == pid:
            children.append(int(entry.name))
    return children


def alive(pid: int) -> bool:
    """Whether ``pid`` runs (zombies count as gone)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return state[state.rindex(")") + 2:].split()[0] != "Z"


def wait_gone(pids: list[int], timeout: float = 30.0) -> list[int]:
    """Wait until every pid has ended; return those still alive after ``timeout``.

    ``timeout`` is an outer safety bound: a stop takes well under a second.
    """
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and any(alive(p) for p in pids):  # outer safety bound
        time.sleep(0.05)
    return [p for p in pids if alive(p)]


def read_json(path: Path) -> dict[str, Any]:
    """A JSON file as a dict."""
    return json.loads(path.read_text(encoding="utf-8"))


def read_jsonl(path: Path) -> list[dict[str, Any]]:
    """A JSON Lines file as a list of dicts."""
    return [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines()
            if line.strip()]


def no_traceback(text: str) -> bool:
    """True if no Python traceback was printed."""
    return "Traceback (most recent call last)" not in text


def env_domain() -> str:
    """The ROS_DOMAIN_ID the test run leased (inherited by the children)."""
    return os.environ["ROS_DOMAIN_ID"]
