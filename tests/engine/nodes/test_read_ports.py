"""The integers BT.CPP's control nodes read with ``getInput``, bound to entries.

Timeout's ``msec``, Repeat's ``num_cycles``...
(a kind's declared ``reads``) take a literal (range-checked as before) or ``{name}``,
resolved in scope, type-checked and read when BT.CPP reads it.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import py_trees
import pytest
from py_trees.common import Status

from sar_framework.engine.api import load_tree
from sar_framework.engine.building.control_build import CLOCK_KEY
from sar_framework.engine.diagnostics import TreeLoadError
from sar_framework.engine.registry import Registry, discover

from ..conftest import GENERIC_PLUGINS

Blackboard = py_trees.blackboard.Blackboard


@pytest.fixture(scope="module")
def registry() -> Registry:
    return discover([GENERIC_PLUGINS], builtins=False, entry_points=False)


@pytest.fixture(autouse=True)
def clean_blackboard() -> Iterator[None]:
    Blackboard.clear()
    yield
    Blackboard.clear()


def _load(tmp_path: Path, registry: Registry, text: str, context: dict | None = None
          ) -> py_trees.behaviour.Behaviour:
    path = tmp_path / "tree.yaml"
    path.write_text("format: 1\n" + text)
    return load_tree(path, context or {}, registry=registry).root


def test_repeat_reads_num_cycles_and_timeout_msec_from_entries(tmp_path: Path,
                                                               registry: Registry) -> None:
    now = [0.0]
    root = _load(tmp_path, registry,
                 "blackboard:\n  c: {type: int, initial: 3}\n  t: {type: int, initial: 500}\n"
                 "root:\n  Timeout:\n    msec: '{t}'\n    child:\n      Repeat:\n"
                 "        num_cycles: '{c}'\n        child: {Fixed: {status: running}}\n",
                 {CLOCK_KEY: lambda: now[0]})
    root.tick_once()
    assert root.status == Status.RUNNING and root.duration == 0.5
    assert root.decorated.limit == 3
    Blackboard.set("/t", 100)  # read when the Timeout starts: not now
    now[0] = 0.4
    root.tick_once()
    assert root.status == Status.RUNNING and root.duration == 0.5
    now[0] = 0.6
    root.tick_once()
    assert root.status == Status.FAILURE


def test_a_read_port_bound_to_an_entry_of_another_type_is_a_located_error(
        tmp_path: Path, registry: Registry) -> None:
    with pytest.raises(TreeLoadError, match=r"tree.yaml:\d+:\d+: error: .*msec"):
        _load(tmp_path, registry, "blackboard:\n  t: {type: str, initial: x}\nroot:\n"
              "  Timeout: {msec: '{t}', child: {Fixed: {status: success}}}\n")


def test_a_literal_keeps_its_range_check(tmp_path: Path, registry: Registry) -> None:
    with pytest.raises(TreeLoadError, match=r"tree.yaml:\d+:\d+: error: .*-5"):
        _load(tmp_path, registry, "root:\n  Timeout: {msec: -5, child: {Fixed: "
              "{status: success}}}\n")


def test_a_literal_given_as_text_keeps_its_range_check(tmp_path: Path,
                                                       registry: Registry) -> None:
    with pytest.raises(TreeLoadError, match=r"tree.yaml:4:17: error: port 'num_cycles': -2 "
                       r"is less than the minimum of -1"):
        _load(tmp_path, registry, "root:\n  Repeat:\n    num_cycles: '-2'\n"
              "    child: {Fixed: {status: success}}\n")


def test_a_literal_given_as_text_is_converted(tmp_path: Path, registry: Registry) -> None:
    root = _load(tmp_path, registry, "root:\n  Repeat:\n    num_cycles: '2'\n"
                 "    child: {Fixed: {status: success}}\n")
    assert root.limit == 2
    root.tick_once()  # a child that succeeds at once: Repeat yields between attempts
    assert root.status == Status.RUNNING
    root.tick_once()
    assert root.status == Status.SUCCESS


def test_parallel_thresholds_and_run_once_then_skip_read_from_entries(
        tmp_path: Path, registry: Registry) -> None:
    root = _load(tmp_path, registry,
                 "blackboard:\n  need: {type: int, initial: 1}\n  skip: {type: bool, "
                 "initial: false}\nroot:\n  Parallel:\n    success_count: '{need}'\n"
                 "    children:\n"
                 "      - RunOnce: {then_skip: '{skip}', child: {Fixed: {status: success}}}\n"
                 "      - Fixed: {status: success}\n")
    root.tick_once()
    assert root.status == Status.SUCCESS and root.success_count == 1
    assert root.children[0].then_skip is False
    Blackboard.set("/need", 3)  # more than the two children: BT.CPP throws
    with pytest.raises(RuntimeError, match="'success_count' 3 is more than the 2 children"):
        root.tick_once()


def test_an_entry_without_a_value_stops_the_tick(tmp_path: Path, registry: Registry) -> None:
    root = _load(tmp_path, registry, "blackboard:\n  c: {type: int}\nroot:\n  Repeat:\n"
                 "    num_cycles: '{c}'\n    child: {Fixed: {status: success}}\n")
    with pytest.raises(RuntimeError, match="port 'num_cycles' reads an entry that has no"):
        root.tick_once()


def test_run_once_keeps_then_skip_s_default_when_its_entry_has_no_value(
        tmp_path: Path, registry: Registry) -> None:
    """Its declaration says so (BT.CPP's RunOnce ignores that failed getInput)."""
    root = _load(tmp_path, registry, "blackboard:\n  s: {type: bool}\nroot:\n  RunOnce:\n"
                 "    then_skip: '{s}'\n    child: {Fixed: {status: success}}\n")
    root.tick_once()
    assert root.status == Status.SUCCESS and root.then_skip is True
