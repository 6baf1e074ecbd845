"""The testing kit as a plugin author gets it: the package of tutorial 2, installed with pip.

The package's files are the code blocks of docs/tutorials/02_writing_a_plugin.md whose
first line names a path under ``battery_leaves/``. It is pip-installed (no deps, no build
isolation) into a target folder, and pytest runs its tests in a child process of this
venv's interpreter with only that folder added to the path: the fixtures come from the
``pytest11`` entry point of the installed sar_framework, the leaf from the package's
``sar_framework.plugins`` entry point.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
TUTORIAL = REPO / "docs" / "tutorials" / "02_writing_a_plugin.md"
pytestmark = pytest.mark.slow  # a pip install and two pytest runs in child processes
BLOCK = re.compile(r"^```(?:python|toml)\n# (battery_leaves/\S+)\n(.*?)^```", re.M | re.S)


def tutorial_files() -> dict[str, str]:
    return {path: body for path, body in BLOCK.findall(TUTORIAL.read_text())}


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The package written from the tutorial and pip-installed into a target folder."""
    root = tmp_path_factory.mktemp("plugin_package")
    for path, body in tutorial_files().items():
        (root / path).parent.mkdir(parents=True, exist_ok=True)
        (root / path).write_text(body)
    target = root / "site"
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--disable-pip-version-check",
                    "--no-deps", "--no-build-isolation", "--target", str(target),
                    str(root / "battery_leaves")], check=True, timeout=300)
    return root / "battery_leaves", target


def run_pytest(package: Path, target: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(target), "PYTEST_ADDOPTS": ""}
    env.pop("PYTEST_PLUGINS", None)
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                           "-p", "no:randomly", "tests"], cwd=package, env=env,
                          capture_output=True, text=True, timeout=300, check=False)


def test_the_tutorial_package_tests_itself_in_under_40_lines() -> None:
    files = tutorial_files()
    assert set(files) == {"battery_leaves/pyproject.toml", "battery_leaves/battery_leaves.py",
                          "battery_leaves/tests/test_battery_ok.py",
                          "battery_leaves/tests/test_battery_ok_by_path.py"}
    assert len(files["battery_leaves/tests/test_battery_ok.py"].splitlines()) < 40


def test_the_installed_package_s_tests_pass(installed: tuple[Path, Path]) -> None:
    package, target = installed
    assert not (package / "conftest.py").exists()
    assert (target / "battery_leaves.py").exists()
    done = run_pytest(package, target)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "4 passed" in done.stdout, done.stdout  # the by-path test too


def test_a_wrong_expectation_fails_with_the_tick_history(installed: tuple[Path, Path]) -> None:
    package, target = installed
    wrong = package / "tests" / "test_wrong.py"
    wrong.write_text(
        "from types import SimpleNamespace\n"
        "from sar_framework.testing import assert_statuses\n\n\n"
        "def test_wrong(sar_leaf):\n"
        "    run = sar_leaf('BatteryOk', context={'battery': SimpleNamespace(percentage=5)})\n"
        "    run.tick(2)\n"
        "    assert_statuses(run, ['SUCCESS', 'SUCCESS'])\n")
    try:
        done = run_pytest(package, target)
    finally:
        wrong.unlink()
    assert done.returncode == 1, done.stdout + done.stderr
    assert "1 failed, 4 passed" in done.stdout, done.stdout
    assert "BatteryOk: ['FAILURE', 'FAILURE'], expected ['SUCCESS', 'SUCCESS']" in done.stdout
    assert "tick 2: BatteryOk=FAILURE" in done.stdout
