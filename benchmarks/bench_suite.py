"""Benchmark: where the test suite's time goes, as CPU seconds by folder and by file.

    .venv/bin/python benchmarks/bench_suite.py [--workers 5] [--top 25] [-- PYTEST ARGS]

Runs the main suite as ``make test`` does (pytest-xdist, ``--dist loadfile``) with a plugin
(this module, loaded by each worker) that records each test's CPU: its worker's own, plus
that of every process the test started and waited for (``RUSAGE_CHILDREN``). The suite is
bound by CPU on two cores, so these seconds, not its wall durations, say what a change to
the suite saves. Prints one table by test folder, one of the costliest files, and the run's
wall time and total CPU (collection and start-up included, so more than the tests' sum).
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Generator
from pathlib import Path
from typing import Any

import pytest

REPO = Path(__file__).resolve().parents[1]
RECORD_ENV = "SAR_BENCH_SUITE_RECORD"


def _cpu_s() -> tuple[float, float]:
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime, children.ru_utime + children.ru_stime


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: pytest.Item | None
                            ) -> Generator[None, Any, None]:
    """Record one test's CPU (set-up, call and tear-down) into the run's record file."""
    before = _cpu_s()
    yield
    after = _cpu_s()
    record = os.environ.get(RECORD_ENV)
    if record:
        with open(record, "a", encoding="utf-8") as out:  # one short line: appends stay whole
            out.write(json.dumps({"test": item.nodeid, "own_s": after[0] - before[0],
                                  "children_s": after[1] - before[1]}) + "\n")


def run_suite(workers: int, pytest_args: list[str], record: Path) -> tuple[int, float, float]:
    """Run pytest with this plugin; return its exit code, wall seconds and total CPU seconds."""
    env = dict(os.environ, **{RECORD_ENV: str(record)})
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(Path(__file__).parent),
                                                       env.get("PYTHONPATH")]))
    command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
               "-p", Path(__file__).stem, "-n", str(workers), "--dist", "loadfile",
               "--no-loadscope-reorder", *pytest_args]
    started = time.monotonic()
    process = subprocess.Popen(command, cwd=REPO, env=env)
    _pid, status, usage = os.wait4(process.pid, 0)
    wall = time.monotonic() - started
    return os.waitstatus_to_exitcode(status), wall, usage.ru_utime + usage.ru_stime


def table(title: str, rows: list[tuple[str, int, float]], total: float) -> None:
    """Print rows of (name, tests, CPU seconds) with their share of ``total``."""
    print(f"\n| {title} | tests | CPU s | share |\n| --- | --- | --- | --- |")
    for name, count, cpu in rows:
        print(f"| {name} | {count} | {cpu:.1f} | {100 * cpu / total:.0f} % |")


def main() -> int:
    """Run the suite once and print where its CPU went."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=5, help="xdist workers (make test: 5)")
    parser.add_argument("--top", type=int, default=25, help="files in the second table")
    parser.add_argument("pytest_args", nargs="*", help="after --: passed on to pytest")
    options = parser.parse_args()
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="bench_suite_") as folder:
        record = Path(folder) / "tests.jsonl"
        code, wall, cpu = run_suite(options.workers, options.pytest_args, record)
        lines = record.read_text(encoding="utf-8").splitlines() if record.exists() else []
    tests = [json.loads(line) for line in lines]
    if not tests:
        print("bench_suite: pytest recorded no test", file=sys.stderr)
        return 1
    by_file: dict[str, list[float]] = collections.defaultdict(list)
    for test in tests:
        by_file[test["test"].split("::")[0]].append(test["own_s"] + test["children_s"])
    by_folder: dict[str, list[float]] = collections.defaultdict(list)
    for file, cpus in by_file.items():
        by_folder["/".join(file.split("/")[:2])].extend(cpus)
    measured = sum(sum(cpus) for cpus in by_file.values())
    folders = sorted(((name, len(c), sum(c)) for name, c in by_folder.items()),
                     key=lambda row: -row[2])
    files = sorted(((name, len(c), sum(c)) for name, c in by_file.items()),
                   key=lambda row: -row[2])[:options.top]
    print(f"pytest exit {code}; {len(tests)} tests; {options.workers} workers; "
          f"load average {load_before:.1f} before, {os.getloadavg()[0]:.1f} after")
    print(f"wall {wall:.0f} s; CPU {cpu:.0f} s in all ({cpu / wall:.2f} cores busy on "
          f"average), {measured:.0f} s of it inside tests")
    table("folder", folders, measured)
    table("file", files, measured)
    return code


if __name__ == "__main__":
    sys.exit(main())
