"""Test-run set-up shared by every test.

Each test process gets a ROS environment of its own before anything imports rclpy:
loopback-only discovery and a ROS_DOMAIN_ID leased for it (see sar_testing.ros_env). Under
pytest-xdist (``-n 2``) every worker process leases its own domain, so the missions two
workers run at once never see each other's nodes; the controller, which runs no test,
leases none. Child processes inherit their test process's domain.

Before anything starts, the run removes Fast DDS shared-memory files no live process uses
(sar_testing.shm_zombies): a half-made one left by a killed process hangs the next ROS
process given its port.

A run leaves nothing behind: every process it starts gets a temp folder of the run's own
(``TMPDIR``) and a marker. After the last test the run fails, naming each file, when that
folder is not empty (a test did not remove what it made), and it removes the Fast DDS files
its processes left in /dev/shm, saying how many (sar_testing.leftovers). The ROS domain
locks stay machine-wide (``SAR_ROS_DOMAIN_LOCKS``).

Tests marked ``soak`` (long repetitions under load) run only when asked for by name:
``-m soak``.
"""

from __future__ import annotations

import importlib.util
import os
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings
from sar_testing.leftovers import SessionLeftovers
from sar_testing.ros_env import DomainLease, apply_local_ros_env, lease_domain_id
from sar_testing.shm_zombies import remove_unused_fastdds_files
from sar_testing.temp_dirs import launch_tmpdir  # noqa: F401 - a fixture for every test

from sar_framework.testing.ros_env import LOCKS_ENV, lock_folder

REPO_ROOT = Path(__file__).resolve().parent.parent
# Two test workers (and other work) share the cores: a property test's examples are the same,
# only timing-based health checks and deadlines would fail them at random.
settings.register_profile("shared_cores", deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("shared_cores")
_lease: DomainLease | None = None
_leftovers: SessionLeftovers | None = None


def is_xdist_controller(config: pytest.Config) -> bool:
    """Whether this process hands the tests to xdist workers instead of running them."""
    return not hasattr(config, "workerinput") and bool(config.getoption("numprocesses", None))


def pytest_configure(config: pytest.Config) -> None:
    """Lease a domain id and set the ROS environment for this test process."""
    global _lease, _leftovers  # noqa: PLW0603 - one lease per test process, one run
    if not hasattr(config, "workerinput"):  # once per run, before any ROS process starts
        remove_unused_fastdds_files()
        os.environ.setdefault(LOCKS_ENV, str(lock_folder()))
        tempfile.gettempdir()  # this process (pytest's own tmp_path) keeps the usual one
        _leftovers = SessionLeftovers()
        _leftovers.start()
    if is_xdist_controller(config):
        return
    _lease = lease_domain_id()
    apply_local_ros_env(_lease.domain_id)


@pytest.hookimpl(hookwrapper=True)
def pytest_sessionfinish(session: pytest.Session) -> Iterator[None]:
    """After the last test (and the workers' end): fail the run if it left anything."""
    yield
    if _leftovers is None:
        return
    left, removed = _leftovers.finish()
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")

    def say(line: str, **markup: bool) -> None:
        if reporter is not None:
            reporter.write_line(line, **markup)
        else:
            sys.stderr.write(line + "\n")

    if removed:
        say(f"removed {len(removed)} Fast DDS file(s) the run's processes left in /dev/shm")
    if left:
        for line in ["the tests left these in their temp folder (now removed):", *left]:
            say(line, red=True)
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


def pytest_unconfigure(config: pytest.Config) -> None:
    """Release the domain id."""
    if _lease is not None:
        _lease.release()


def pytest_report_header(config: pytest.Config) -> str:
    """Show which domain this run uses."""
    if is_xdist_controller(config):
        return "ROS: LOCALHOST discovery, a ROS_DOMAIN_ID leased by each worker"
    return f"ROS: LOCALHOST discovery, ROS_DOMAIN_ID={_lease.domain_id if _lease else '?'}"


def slow_first(items: list[pytest.Item]) -> None:
    """Put the files holding ``slow`` tests first, each file's tests kept together, in order.

    Under ``-n 2 --dist loadfile --no-loadscope-reorder`` the workers take files in this
    order: the long end-to-end files start at once and the many quick files fill the gaps,
    instead of two long files left for the end.
    """
    slow_files = {item.path for item in items if "slow" in item.keywords}
    items.sort(key=lambda item: item.path not in slow_files)  # stable: file order kept


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Leave out soak tests unless ``-m`` names them; skip ROS tests without rclpy.

    ROS tests are skipped, with a reason, in an environment without rclpy (the compat venv).
    """
    if "soak" not in (config.getoption("markexpr", "") or ""):
        soak = [item for item in items if "soak" in item.keywords]
        if soak:
            config.hook.pytest_deselected(items=soak)
            items[:] = [item for item in items if "soak" not in item.keywords]
    if hasattr(config, "workerinput"):
        slow_first(items)
    if importlib.util.find_spec("rclpy") is not None:
        return
    skip = pytest.mark.skip(reason="rclpy is not installed in this interpreter")
    for item in items:
        if "ros" in item.keywords:
            item.add_marker(skip)


@pytest.fixture
def repo_root() -> Path:
    """The repository's root folder."""
    return REPO_ROOT


def _ros_pair() -> Iterator[tuple[object, object]]:
    """A node and a single-threaded executor on a fresh rclpy context."""
    from sar_testing.spin import ros_node

    with ros_node("sar_test") as pair:
        yield pair


#: A node and a single-threaded executor on a fresh rclpy context.
ros = pytest.fixture(_ros_pair, name="ros")
#: The same, one for the module (servers the tests share are discovered once).
module_ros = pytest.fixture(_ros_pair, scope="module", name="module_ros")
