"""Building: every node kind becomes the plain py_trees object, subtrees, ids, context."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import py_trees
import pytest

from sar_framework.engine.api import load_tree
from sar_framework.engine.diagnostics import TreeLoadError
from sar_framework.engine.nodes.node_kinds import PY_TREES_KINDS as KINDS
from sar_framework.engine.nodes.node_kinds import UNSUPPORTED_DECORATORS
from sar_framework.engine.registry import Registry

from ..conftest import Checker, write

Status = py_trees.common.Status


@pytest.fixture
def load(tree_dir: Path, registry: Registry) -> Callable[..., py_trees.behaviour.Behaviour]:
    def run(text: str, **context: object) -> py_trees.behaviour.Behaviour:
        write(tree_dir, "tree.yaml", text)
        return load_tree("tree.yaml", context=context, registry=registry).root

    return run


DECORATOR_ATTRS = {
    "one_shot": "policy: on_successful_completion",
    "retry": "num_failures: 3",
    "repeat": "num_success: -1",
    "timeout": "duration: 2.5",
    "condition": "status: failure",
}


@pytest.mark.parametrize("key", sorted(k for k, v in KINDS.items() if v.category.value ==
                                       "decorator"))
def test_every_decorator_builds_its_py_trees_class(load: Callable[..., object], key: str) -> None:
    extra = DECORATOR_ATTRS.get(key, "")
    root = load(f"format: 1\nroot:\n  {key}:\n    {extra}\n    child: {{Fixed: {{}}}}\n")
    assert type(root) is getattr(py_trees.decorators, KINDS[key].class_name)
    assert root.name == KINDS[key].class_name
    assert type(root.decorated).__name__ == "Fixed"
    root.tick_once()
    assert root.status in (Status.SUCCESS, Status.FAILURE, Status.RUNNING)


def test_decorator_arguments(load: Callable[..., py_trees.behaviour.Behaviour]) -> None:
    root = load("format: 1\nroot:\n  sequence:\n    memory: false\n    children:\n"
                "      - one_shot: {policy: on_successful_completion, child: {Tick: {}}}\n"
                "      - retry: {num_failures: 3, child: {Tick: {}}}\n"
                "      - repeat: {num_success: 2.0, child: {Tick: {}}}\n"
                "      - timeout: {duration: 2, child: {Tick: {}}}\n"
                "      - condition: {status: running, child: {Tick: {}}}\n")
    one_shot, retry, repeat, timeout, condition = root.children
    assert one_shot.policy == py_trees.common.OneShotPolicy.ON_SUCCESSFUL_COMPLETION
    assert retry.num_failures == 3
    assert repeat.num_success == 2 and type(repeat.num_success) is int
    assert timeout.duration == 2.0 and type(timeout.duration) is float
    assert condition.succeed_status == Status.RUNNING


def test_supported_decorators_exist_in_this_py_trees() -> None:
    for kind in KINDS.values():
        if kind.category.value == "decorator":
            assert hasattr(py_trees.decorators, kind.class_name)
    assert set(UNSUPPORTED_DECORATORS) == {"eternal_guard", "status_to_blackboard", "for_each"}


@pytest.mark.parametrize(
    ("attrs", "policy", "synchronise"),
    [("policy: success_on_all", "SuccessOnAll", True),
     ("policy: success_on_all\n    synchronise: false", "SuccessOnAll", False),
     ("policy: success_on_one", "SuccessOnOne", None),
     ("policy: success_on_selected\n    selected: [B]", "SuccessOnSelected", True)],
)
def test_parallel_policies(load: Callable[..., py_trees.behaviour.Behaviour], attrs: str,
                           policy: str, synchronise: bool | None) -> None:
    root = load(f"format: 1\nroot:\n  parallel:\n    {attrs}\n"
                "    children: [Fixed: {name: A}, Fixed: {name: B}]\n")
    assert isinstance(root, py_trees.composites.Parallel)
    assert type(root.policy).__name__ == policy
    if synchronise is not None:
        assert root.policy.synchronise is synchronise
    if policy == "SuccessOnSelected":
        assert root.policy.children == [root.children[1]]
    root.tick_once()
    assert root.status == Status.SUCCESS


def test_leaf_params_defaults_and_types(load: Callable[..., py_trees.behaviour.Behaviour]) -> None:
    root = load("format: 1\nroot:\n  sequence:\n    memory: true\n    children:\n"
                "      - Fixed: {id: f, status: failure}\n"
                "      - Typed: {name: T, label: x, count: 2.0, rate: 3, source: f}\n")
    fixed, typed = root.children
    assert typed.name == "T"
    assert typed.kwargs == {"count": 2, "rate": 3.0, "label": "x", "loud": False, "note": None,
                            "source": fixed}
    assert type(typed.kwargs["count"]) is int and type(typed.kwargs["rate"]) is float


def test_missing_context_names_plugin_and_key(tree_dir: Path, registry: Registry) -> None:
    write(tree_dir, "tree.yaml", "format: 1\nroot:\n  sequence:\n    memory: true\n"
          "    children: [AdvanceZone: {}, LogNoDetection: {}]\n")
    with pytest.raises(TreeLoadError) as info:
        load_tree("tree.yaml", registry=registry)
    assert [str(d) for d in info.value.diagnostics] == [
        "tree.yaml:5:16: error: plugin 'AdvanceZone' needs the context object 'zone_manager': "
        "pass load_tree(..., context={'zone_manager': ...})",
        "tree.yaml:5:33: error: plugin 'LogNoDetection' needs the context object "
        "'zone_manager': pass load_tree(..., context={'zone_manager': ...})",
    ]


def test_a_referenced_leaf_that_fails_is_reported_once(tree_dir: Path,
                                                      registry: Registry) -> None:
    """Regression: a failed leaf was built again for each reference (duplicate diagnostic)."""
    write(tree_dir, "tree.yaml", "format: 1\nroot:\n  sequence:\n    memory: true\n"
          "    children: [DetectSurvivor: {id: d}, IsSurvivorDetected: {detector: d}]\n")
    with pytest.raises(TreeLoadError) as info:
        load_tree("tree.yaml", registry=registry)
    assert [str(d) for d in info.value.diagnostics] == [
        "tree.yaml:5:16: error: plugin 'DetectSurvivor' needs the context object "
        "'zone_manager': pass load_tree(..., context={'zone_manager': ...})",
    ]


def test_context_objects_are_passed(load: Callable[..., py_trees.behaviour.Behaviour]) -> None:
    zm = object()
    root = load("format: 1\nroot: {AdvanceZone: {}}\n", zone_manager=zm)
    assert root.kwargs == {"zone_manager": zm}


def test_constructor_exception_is_a_diagnostic(tree_dir: Path, registry: Registry) -> None:
    write(tree_dir, "tree.yaml", "format: 1\nroot: {Exploding: {}}\n")
    with pytest.raises(TreeLoadError) as info:
        load_tree("tree.yaml", registry=registry)
    assert str(info.value) == (
        "tree.yaml:2:8: error: cannot construct Exploding 'Exploding': RuntimeError: boom"
    )


SUBTREES = """\
format: 1
subtrees:
  detect_and_read:
    sequence:
      name: DetectAndRead
      memory: true
      children:
        - Fixed: {id: source}
        - Typed: {label: inner, source: source}
        - Typed: {label: outer, source: top}
root:
  sequence:
    memory: true
    children:
      - Fixed: {id: top}
      - subtree: detect_and_read
      - subtree: detect_and_read
"""


def test_subtree_copies_have_local_ids(tree_dir: Path, registry: Registry) -> None:
    write(tree_dir, "tree.yaml", SUBTREES)
    loaded = load_tree("tree.yaml", registry=registry)
    top, first, second = loaded.root.children
    assert first is not second and first.name == second.name == "DetectAndRead"
    for copy in (first, second):
        source, inner, outer = copy.children
        assert inner.kwargs["source"] is source  # the copy's own 'source' id
        assert outer.kwargs["source"] is top  # then the enclosing tree
    assert first.children[0] is not second.children[0]
    uids = sorted(loaded.behaviours)
    assert uids == ["0", "0.0", "0.1", "0.1.0", "0.1.1", "0.1.2", "0.2", "0.2.0", "0.2.1",
                    "0.2.2"]
    spec_first = loaded.spec.root.children[1]
    assert spec_first.subtree == "detect_and_read" and spec_first.uid == "0.1"


def test_duplicate_id_inside_one_copy(check: Checker) -> None:
    assert check("format: 1\nsubtrees:\n  s:\n    sequence:\n      memory: true\n"
                 "      children: [Fixed: {id: a}, Fixed: {id: a}]\n"
                 "root: {inverter: {child: {subtree: s}}}\n") == [
        "tree.yaml:6:34: error: duplicate id 'a' (first used at tree.yaml:6:18)"
    ]


def test_reference_into_a_copy_from_outside_fails(check: Checker) -> None:
    assert check("format: 1\nsubtrees:\n  s: {Fixed: {id: inner}}\n"
                 "root:\n  sequence:\n    memory: true\n"
                 "    children: [subtree: s, Typed: {label: x, source: inner}]\n") == [
        "tree.yaml:7:54: error: 'source' names no leaf: there is no id 'inner'"
    ]


INCLUDED = """\
format: 1
include: [more.yaml]
subtrees:
  lib:
    sequence:
      memory: true
      children: [Fixd: {}, subtree: more]
"""


def test_errors_in_included_files_point_into_them(check: Checker) -> None:
    files = {
        "tree.yaml": "format: 1\ninclude: [lib/lib.yaml]\nroot: {subtree: lib}\n",
        "lib/lib.yaml": INCLUDED,
        "lib/more.yaml": "format: 1\nsubtrees:\n  more: {retry: {num_failures: 0, "
                         "child: {Tick: {}}}}\n",
    }
    assert check(files=files) == [
        "lib/lib.yaml:7:18: error: unknown plugin 'Fixd' (did you mean 'Fixed'?)",
        "lib/more.yaml:3:32: error: 'num_failures' must be >= 1, got 0",
    ]


def test_include_cycle(check: Checker) -> None:
    files = {
        "tree.yaml": "format: 1\ninclude: [a.yaml]\nroot: {Tick: {}}\n",
        "a.yaml": "format: 1\ninclude: [b.yaml]\n",
        "b.yaml": "format: 1\ninclude: [a.yaml]\n",
    }
    assert check(files=files) == [
        "b.yaml:2:11: error: include cycle: a.yaml -> b.yaml -> a.yaml"
    ]


def test_self_include_and_missing_include(check: Checker) -> None:
    assert check("format: 1\ninclude: [tree.yaml, nope.yaml]\nroot: {Tick: {}}\n") == [
        "tree.yaml:2:11: error: include cycle: tree.yaml -> tree.yaml",
        "tree.yaml:2:22: error: included file 'nope.yaml' does not exist",
    ]


def test_diamond_include_is_fine_and_duplicate_subtree_is_not(check: Checker) -> None:
    files = {
        "tree.yaml": "format: 1\ninclude: [a.yaml, b.yaml]\nroot: {subtree: d}\n",
        "a.yaml": "format: 1\ninclude: [d.yaml]\n",
        "b.yaml": "format: 1\ninclude: [d.yaml]\nsubtrees:\n  a_only: {Tick: {}}\n",
        "d.yaml": "format: 1\nsubtrees:\n  d: {Tick: {}}\n",
    }
    assert check(files=files) == []
    files["b.yaml"] += "  d: {Fixed: {}}\n"
    assert check(files=files) == [
        "b.yaml:5:3: error: subtree 'd' is defined twice (first at d.yaml:3:3)"
    ]


def test_tree_plugins_key_loads_local_plugins(tree_dir: Path, registry: Registry) -> None:
    write(tree_dir, "local/extra.py", "import py_trees\nfrom sar_framework.engine.plugin "
          "import leaf\n\n@leaf()\nclass LocalOnly(py_trees.behaviour.Behaviour):\n"
          "    def update(self):\n        return py_trees.common.Status.SUCCESS\n")
    write(tree_dir, "tree.yaml", "format: 1\nplugins: [local]\nroot: {LocalOnly: {}}\n")
    loaded = load_tree("tree.yaml", registry=registry)
    assert type(loaded.root).__name__ == "LocalOnly"
    assert loaded.spec.plugin_paths == [str(tree_dir / "local")]
    assert "LocalOnly" not in registry  # the shared registry is not modified


def test_tree_ticks_like_hand_built(load: Callable[..., py_trees.behaviour.Behaviour]) -> None:
    root = load("format: 1\nroot:\n  selector:\n    memory: false\n    children:\n"
                "      - inverter: {child: {Fixed: {status: success}}}\n"
                "      - failure_is_success: {child: {Fixed: {status: failure}}}\n")
    root.tick_once()
    assert root.status == Status.SUCCESS
    assert [c.status for c in root.children] == [Status.FAILURE, Status.SUCCESS]


def test_library_file_validates_but_does_not_load(tree_dir: Path, registry: Registry) -> None:
    from sar_framework.engine.api import load_spec, validate

    write(tree_dir, "lib.yaml", "format: 1\nsubtrees:\n  s: {Tick: {}}\n  t: {Fixd: {}}\n")
    result = validate("lib.yaml", registry=registry)
    assert [str(d) for d in result.diagnostics] == [
        "lib.yaml:4:7: error: unknown plugin 'Fixd' (did you mean 'Fixed'?)"
    ]
    write(tree_dir, "lib.yaml", "format: 1\nsubtrees:\n  s: {Tick: {}}\n")
    result = validate("lib.yaml", registry=registry)
    assert result.ok and result.spec is None and result.library == 1
    with pytest.raises(TreeLoadError) as info:
        load_spec("lib.yaml", registry=registry)
    assert str(info.value) == ("lib.yaml:1:1: error: missing 'root': this file only defines "
                               "subtrees; include it from a tree file")
