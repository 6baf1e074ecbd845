"""Nav2's controls and decorators are the Nav2 plugin package's, found through the registry.

The engine core names none of them; a tree uses them as it uses BT.CPP's kinds.
"""

from __future__ import annotations

import re
from pathlib import Path

from py_trees.blackboard import Blackboard
from py_trees.common import Status

from sar_framework.engine.api import load_spec, load_tree
from sar_framework.engine.diagnostics import TreeLoadError
from sar_framework.engine.registry import Registry, discover
from sar_framework.engine.rendering.text_tree import render_text

REPO = Path(__file__).resolve().parents[2]
GENERIC = REPO / "tests" / "engine" / "plugins_for_tests" / "generic"
NAV2_NAMES = ("RecoveryNode", "PipelineSequence", "RoundRobin", "RateController",
              "SingleTrigger", "GoalUpdatedController", "PathLongerOnApproach",
              "DistanceController", "SpeedController", "GoalUpdater")


def _registry() -> Registry:
    return discover([GENERIC], entry_points=False)


def _load(tmp_path: Path, text: str):  # type: ignore[no-untyped-def]
    path = tmp_path / "tree.yaml"
    path.write_text("format: 1\n" + text, encoding="utf-8")
    return load_tree(path, {}, registry=_registry()).root


def test_the_engine_core_and_the_runner_name_no_nav2_node() -> None:
    pattern = re.compile(r"\b(" + "|".join(NAV2_NAMES) + r")\b")
    found = [f"{path.relative_to(REPO)}: {match.group(1)}"
             for folder in ("engine", "runner")
             for path in sorted((REPO / "sar_framework" / folder).rglob("*.py"))
             for match in [pattern.search(path.read_text(encoding="utf-8"))] if match]
    assert found == []


def test_a_param_nav2_s_wait_no_longer_takes_says_what_to_write(tmp_path: Path) -> None:
    """The Wait leaf's own declaration (not the engine) knows its 'duration' moved."""
    path = tmp_path / "tree.yaml"
    path.write_text("format: 1\nroot:\n  Wait: {duration: 2.0}\n", encoding="utf-8")
    try:
        load_spec(path, registry=_registry())
    except TreeLoadError as exc:
        assert "tree.yaml:3:" in str(exc), str(exc)
        assert "unknown param 'duration' for plugin 'Wait': 'Wait' is Nav2's Wait" in str(exc)
        assert "write Dwell: {duration: ...}" in str(exc)
    else:
        raise AssertionError("Wait: {duration: ...} was accepted")


def test_every_nav2_control_and_decorator_is_a_plugin_kind() -> None:
    specs = {k.name: k for k in _registry().kind_plugins()}
    assert set(NAV2_NAMES) <= set(specs)
    assert all(specs[n].cls.__module__.startswith("sar_plugins.nav2.") for n in NAV2_NAMES)


def test_a_bad_rate_is_a_located_error(tmp_path: Path) -> None:
    try:
        _load(tmp_path, "root:\n  RateController: {hz: 0, child: {Fixed: {status: success}}}\n")
    except TreeLoadError as exc:
        assert "tree.yaml:3:" in str(exc) and "hz" in str(exc), str(exc)
    else:
        raise AssertionError("hz: 0 was accepted")


def test_recovery_node_reads_number_of_retries_from_an_entry(tmp_path: Path) -> None:
    root = _load(tmp_path, "blackboard:\n  n: {type: int, initial: 2}\nroot:\n  RecoveryNode:\n"
                 "    number_of_retries: '{n}'\n    children:\n"
                 "      - Fixed: {status: failure}\n      - Fixed: {status: success}\n")
    root.tick_once()
    assert root.status == Status.FAILURE and root.number_of_retries == 2
    Blackboard.set("/n", 0)
    root.tick_once()
    assert root.status == Status.FAILURE and root.number_of_retries == 0


def test_render_shows_the_symbol_the_declaration_gives(tmp_path: Path) -> None:
    path = tmp_path / "tree.yaml"
    path.write_text("format: 1\nroot:\n  RecoveryNode:\n    children:\n"
                    "      - PipelineSequence: {children: [Fixed: {status: success}]}\n"
                    "      - Fixed: {status: success}\n", encoding="utf-8")
    text = render_text(load_spec(path, registry=_registry()), unicode=False)
    assert "{o} RecoveryNode" in text and "[-] PipelineSequence" in text, text
