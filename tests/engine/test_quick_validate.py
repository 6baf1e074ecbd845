"""The quick validation path gives exactly the reference result, or gives up.

``validate_file`` first tries :mod:`~sar_framework.engine.quick_validate` (an ordinary
tree, read by the quick YAML reader) and otherwise takes the reference path (PyYAML's
composer and the full check). These tests hold the two to the same answer: the same
spec node for node (``repr`` of every attribute, so ``1`` and ``1.0`` differ, and their
order counts), no result where the reference finds any problem, and the same
diagnostics from ``validate_file`` either way.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sar_framework.engine.quick_validate import quick_validate
from sar_framework.engine.registry import Registry, discover
from sar_framework.engine.spec import TreeSpec
from sar_framework.engine.validate import ValidationResult, main_file, validate_file

from .conftest import FIXTURES, REPO, make_registry, write
from .strategies import documents, mutated_texts
from .test_errors import CASES

_SETTINGS = settings(max_examples=300, deadline=None,
                     suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
REPO_TREES = sorted((REPO / "trees").rglob("*.yaml"))


def shape(spec: TreeSpec | None) -> Any:
    """Everything a spec says, in a form where 1, 1.0 and True differ."""
    if spec is None:
        return None
    nodes = [
        (n.kind, n.category, n.name, n.uid, n.location, repr(n.attrs), n.id, n.subtree,
         {k: t.uid for k, t in n.refs.items()}, len(n.children))
        for n in spec.nodes()
    ]
    return (spec.name, spec.description, spec.source, spec.format, spec.plugin_paths, nodes)


def same_result(a: ValidationResult, b: ValidationResult) -> None:
    assert shape(a.spec) == shape(b.spec)
    assert [str(d) for d in a.diagnostics] == [str(d) for d in b.diagnostics]
    assert a.structural == b.structural
    assert (a.library, a.files, a.plugin_entries) == (b.library, b.files, b.plugin_entries)
    assert sorted(a.registry.names()) == sorted(b.registry.names())


def both_paths(path: Path, registry: Registry, plugin_paths: tuple[str, ...] = ()) -> bool:
    """Hold the quick path to the reference one on ``path``; return whether it was taken."""
    reference = validate_file(path, registry=registry, plugin_paths=plugin_paths, quick=False)
    quick = quick_validate(main_file(path), str(path), registry, plugin_paths)
    if quick is not None:
        result, reads = quick
        assert reference.ok and reference.diagnostics == [], "the quick path hid a problem"
        same_result(result, reference)
        assert [p for p, _ in reads] == list(reference.files)  # read in the same order
        assert all(data == p.read_bytes() for p, data in reads)
    same_result(validate_file(path, registry=registry, plugin_paths=plugin_paths), reference)
    return quick is not None


@pytest.mark.parametrize("path", REPO_TREES, ids=[str(p.relative_to(REPO)) for p in REPO_TREES])
def test_repository_trees(path: Path) -> None:
    taken = both_paths(path, discover(entry_points=False))
    top = yaml.safe_load(path.read_text(encoding="utf-8"))
    assert taken == ("root" in top)  # every tree the project ships goes the quick way


def test_fixtures(registry: Registry) -> None:
    taken = [both_paths(path, registry) for path in sorted(FIXTURES.rglob("*.yaml"))]
    assert any(taken)  # the mission fixture, with its include and subtree


@pytest.mark.parametrize("name", CASES)
def test_every_error_class_gives_up(name: str, tree_dir: Path, registry: Registry) -> None:
    path = write(tree_dir, "tree.yaml", CASES[name][0])
    assert not both_paths(path, registry)


ORDINARY = """
format: 1
name: every value type
description: plain, with a comma, and spaces
root:
  parallel:
    name: Both
    policy: success_on_selected
    selected: [A, "B"]
    synchronise: yes
    children:
      - retry:
          name: A
          num_failures: 0x3
          child: {timeout: {duration: 2, child: {Tick: {name: 'it''s'}}}}
      - inverter: {name: B, child: {Typed: {id: t, label: x, source: f}}}
      - Fixed: {id: f}
      - Typed: {label: y, source: f, count: 1_0, rate: 2, loud: on, note: ~}   # again
"""


def test_an_ordinary_tree_takes_the_quick_path(tree_dir: Path, registry: Registry) -> None:
    path = write(tree_dir, "tree.yaml", ORDINARY)
    assert both_paths(path, registry)


def test_reads_the_file_once_and_reports_its_bytes(tree_dir: Path, registry: Registry) -> None:
    path = write(tree_dir, "tree.yaml", ORDINARY)
    seen: list[tuple[Path, bytes]] = []
    result = validate_file(path, registry=registry, on_read=lambda p, b: seen.append((p, b)))
    assert result.ok
    assert seen == [(main_file(path), path.read_bytes())]


WITH_SUBTREES = {
    "tree.yaml": """
        format: 1
        include: [lib/a.yaml, lib/b.yaml]
        subtrees:
          twice:
            sequence:
              memory: true
              children: [{subtree: from_a}, {subtree: from_a}]
        root:
          sequence:
            memory: false
            children:
              - Fixed: {id: top}
              - subtree: twice
              - subtree: from_b
              - subtree: alias
        """,
    "lib/a.yaml": """
        format: 1
        include: [b.yaml]
        subtrees:
          from_a:
            selector:
              memory: true
              children:
                - Fixed: {id: local}
                - Typed: {label: a, source: local}   # the copy's own id
                - Typed: {label: b, source: top}     # the enclosing tree's
        """,
    "lib/b.yaml": """
        format: 1
        plugins: []
        subtrees:
          from_b: {inverter: {child: {subtree: from_a}}}
          alias: {subtree: from_b}
          unused: {Tick: {}}
        root: {Tick: {}}   # an included file's root: checked, not used
        """,
}


def test_includes_and_subtrees_take_the_quick_path(tree_dir: Path, registry: Registry) -> None:
    for name, text in WITH_SUBTREES.items():
        write(tree_dir, name, text)
    path = tree_dir / "tree.yaml"
    assert both_paths(path, registry)
    seen: list[Path] = []
    validate_file(path, registry=registry, on_read=lambda p, _: seen.append(p))
    assert seen == [main_file(tree_dir / n) for n in ("tree.yaml", "lib/a.yaml", "lib/b.yaml")]


@pytest.mark.parametrize("change", [
    ("lib/a.yaml", "include: [b.yaml]", "include: [../tree.yaml]"),  # an include cycle
    ("lib/a.yaml", "include: [b.yaml]", "include: [c.yaml]"),  # a missing include
    ("tree.yaml", "subtree: from_b", "subtree: from_c"),  # an unknown subtree
    ("lib/b.yaml", "{subtree: from_a}", "{subtree: from_b}"),  # a recursive subtree
    ("lib/b.yaml", "from_b: {", "from_a: {"),  # a subtree defined twice
    ("lib/a.yaml", "source: local}", "source: nowhere}"),  # a dangling reference
    ("lib/b.yaml", "root: {Tick: {}}", "root: {Tock: {}}"),  # an error in an included root
])
def test_problems_across_files_give_up(
    change: tuple[str, str, str], tree_dir: Path, registry: Registry
) -> None:
    for name, text in WITH_SUBTREES.items():
        write(tree_dir, name, text)
    name, old, new = change
    target = tree_dir / name
    assert old in target.read_text()
    target.write_text(target.read_text().replace(old, new))
    assert not both_paths(tree_dir / "tree.yaml", registry)
    assert not validate_file(tree_dir / "tree.yaml", registry=registry).ok


def test_plugins_key_and_plugin_paths(tree_dir: Path) -> None:
    write(tree_dir, "local/leaf.py", """
        import py_trees
        from sar_framework.engine.plugin import leaf

        @leaf()
        class LocalTick(py_trees.behaviour.Behaviour):
            def update(self):
                return py_trees.common.Status.SUCCESS
    """)
    write(tree_dir, "extra/more.py", """
        import py_trees
        from sar_framework.engine.plugin import leaf

        @leaf()
        class ExtraTick(py_trees.behaviour.Behaviour):
            def update(self):
                return py_trees.common.Status.SUCCESS
    """)
    path = write(tree_dir, "tree.yaml", """
        format: 1
        plugins: [local/leaf.py]
        root: {sequence: {memory: true, children: [{LocalTick: {}}, {ExtraTick: {}}]}}
    """)
    base = make_registry()
    assert both_paths(path, base, ("extra",))
    missing = write(tree_dir, "bad.yaml", "format: 1\nplugins: [nowhere.py]\nroot: {Tick: {}}\n")
    assert not both_paths(missing, base)


_REGISTRY = make_registry()
_SEEDS = [p.read_text(encoding="utf-8") for p in [*REPO_TREES, *sorted(FIXTURES.rglob("*.yaml"))]]
_SEEDS += [ORDINARY.lstrip("\n")]


@_SETTINGS
@given(document=documents(_REGISTRY), flow=st.sampled_from([False, None]))
def test_generated_documents(document: Any, flow: bool | None, tmp_path_factory: Any) -> None:
    path = tmp_path_factory.mktemp("quick") / "tree.yaml"
    path.write_text(yaml.safe_dump(document, sort_keys=False, default_flow_style=flow,
                                   width=1000), encoding="utf-8")
    both_paths(path, _REGISTRY)


@_SETTINGS
@given(text=mutated_texts(_SEEDS))
def test_mutated_files(text: str, tmp_path_factory: Any) -> None:
    path = tmp_path_factory.mktemp("quick-mut") / "tree.yaml"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    both_paths(path, _REGISTRY)


@_SETTINGS
@given(document=documents(_REGISTRY), flow=st.sampled_from([False, None]))
def test_generated_documents_across_two_files(
    document: Any, flow: bool | None, tmp_path_factory: Any
) -> None:
    folder = tmp_path_factory.mktemp("quick-split")
    if isinstance(document, dict) and "subtrees" in document:
        library = {"format": 1, "subtrees": document.pop("subtrees")}
        document = {"include": ["lib.yaml"], **document}
        (folder / "lib.yaml").write_text(yaml.safe_dump(library, sort_keys=False,
                                                        default_flow_style=flow, width=1000))
    path = folder / "tree.yaml"
    path.write_text(yaml.safe_dump(document, sort_keys=False, default_flow_style=flow,
                                   width=1000), encoding="utf-8")
    both_paths(path, _REGISTRY)
