"""The cache of validated trees: a hit is exactly a fresh validation, a change is a miss."""

from __future__ import annotations

import os
import pickle
import shutil
from pathlib import Path
from typing import Any

import py_trees
import pytest
import yaml
from hypothesis import HealthCheck, given, settings

from sar_framework import cli
from sar_framework.engine import cache
from sar_framework.engine.api import load_spec, load_tree
from sar_framework.engine.diagnostics import TreeLoadError
from sar_framework.engine.plugin import Param, leaf
from sar_framework.engine.registry import Registry, default_registry
from sar_framework.engine.spec import TreeSpec
from sar_framework.engine.validate import ValidationResult, validate_file

from .conftest import FIXTURES, REPO, make_registry, write
from .strategies import documents

_REGISTRY = make_registry()
_CONTEXT = {"zone_manager": object()}


# -- helpers ----------------------------------------------------------------------------
class Calls:
    """Counts full validations (the cache's misses)."""

    def __init__(self) -> None:
        self.count = 0


@pytest.fixture
def full_validations(monkeypatch: pytest.MonkeyPatch) -> Calls:
    calls = Calls()
    real = cache.validation.validate_file

    def counting(*args: Any, **kwargs: Any) -> ValidationResult:
        calls.count += 1
        return real(*args, **kwargs)

    monkeypatch.setattr(cache.validation, "validate_file", counting)
    return calls


def fresh(path: str | Path, registry: Registry | None = None) -> ValidationResult:
    return validate_file(path, registry=registry)


def shape(spec: TreeSpec) -> list[tuple[Any, ...]]:
    """Every node, with its refs as indexes into the walk (the identity structure)."""
    nodes = list(spec.nodes())
    index = {id(n): i for i, n in enumerate(nodes)}
    out = []
    for node in nodes:
        refs = {name: index.get(id(target), -1) for name, target in node.refs.items()}
        out.append((node.uid, node.kind, node.category, node.name, node.location, node.attrs,
                    node.id, node.subtree, len(node.children), refs))
    return out


def assert_same(cached: TreeSpec, reference: TreeSpec) -> None:
    assert cached == reference
    assert shape(cached) == shape(reference)
    assert all(-1 not in row[-1].values() for row in shape(cached))  # refs stay in the tree
    # Locations are real SourceLocations: printed, hashed and ordered alike.
    for a, b in zip(cached.nodes(), reference.nodes(), strict=True):
        assert str(a.location) == str(b.location)
        assert hash(a.location) == hash(b.location)


def entries(folder: Path) -> list[Path]:
    return sorted(folder.glob("*.tree")) if folder.is_dir() else []


def admit(path: str | Path, registry: Registry | None = _REGISTRY, **kwargs: Any) -> None:
    """Load twice: the first clean load leaves a marker, the second stores the entry."""
    for _ in range(2):
        load_spec(path, registry=registry, **kwargs)


def hit_twice(path: str | Path, registry: Registry | None, calls: Calls) -> list[TreeSpec]:
    """Miss twice (marker, then entry), then hit from memory and from disk (a new
    process); return both hits."""
    first = cache.validate(path, registry=registry)
    assert first.spec is not None and calls.count == 1
    stored = cache.validate(path, registry=registry)
    assert calls.count == 2, "the first load only leaves a marker"
    memory = cache.validate(path, registry=registry)
    cache.clear_memory()
    disk = cache.validate(path, registry=registry)
    assert calls.count == 2, "the third and fourth loads must be hits"
    assert memory.diagnostics == disk.diagnostics == []
    assert memory.spec is not stored.spec and disk.spec is not memory.spec
    return [memory.spec, disk.spec]  # type: ignore[list-item]


# -- hits equal fresh validations ------------------------------------------------------
_FIXTURE_TREES = sorted(FIXTURES.rglob("*.yaml"))
_REPO_TREES = sorted((REPO / "trees").rglob("*.yaml"))


@pytest.mark.parametrize("name", [str(p.relative_to(FIXTURES)) for p in _FIXTURE_TREES])
def test_fixture_trees_hit_equal_fresh(
    name: str, tree_cache: Path, full_validations: Calls, tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    shutil.copytree(FIXTURES, tmp_path / "trees")
    monkeypatch.chdir(tmp_path)
    path = f"trees/{name}"
    reference = fresh(path, _REGISTRY).spec
    if reference is None:
        pytest.skip("not a loadable tree (subtrees only)")
    for spec in hit_twice(path, _REGISTRY, full_validations):
        assert_same(spec, reference)


@pytest.mark.parametrize("name", [str(p.relative_to(REPO)) for p in _REPO_TREES])
def test_repo_trees_hit_equal_fresh(
    name: str, tree_cache: Path, full_validations: Calls, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(REPO)
    reference = fresh(name).spec
    if reference is None:
        pytest.skip("not a loadable tree (subtrees only)")
    for spec in hit_twice(name, None, full_validations):
        assert_same(spec, reference)


def test_shared_references_stay_shared(tree_cache: Path, tree_dir: Path) -> None:
    write(tree_dir, "tree.yaml", """
        format: 1
        root:
          sequence:
            memory: true
            children:
              - DetectSurvivor: {id: detect}
              - IsSurvivorDetected: {detector: detect}
              - BroadcastSurvivorTF: {id: tf, detector: detect}
              - NotifyBase: {detector: detect, broadcaster: tf}
        """)
    load_spec("tree.yaml", registry=_REGISTRY)
    cache.clear_memory()
    spec = load_spec("tree.yaml", registry=_REGISTRY)
    detect, checked, broadcast, notify = spec.root.children
    assert checked.refs["detector"] is detect
    assert broadcast.refs["detector"] is detect
    assert notify.refs == {"detector": detect, "broadcaster": broadcast}
    assert notify.refs["broadcaster"] is broadcast
    assert_same(spec, fresh("tree.yaml", _REGISTRY).spec)  # type: ignore[arg-type]


def test_load_tree_hit_builds_the_same_tree(
    tree_cache: Path, full_validations: Calls, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(REPO)
    path = "tests/engine/fixtures/search_and_rescue.yaml"
    cold = load_tree(path, context=_CONTEXT, registry=_REGISTRY, cache=False)
    admit(path)
    cache.clear_memory()
    warm = load_tree(path, context=_CONTEXT, registry=_REGISTRY)
    assert full_validations.count == 3  # cache=False, then the marker and the entry

    def outline(root: py_trees.behaviour.Behaviour) -> list[tuple[str, str]]:
        return [(type(b).__name__, b.name) for b in root.iterate()]

    assert outline(warm.root) == outline(cold.root)
    assert sorted(warm.behaviours) == sorted(cold.behaviours)
    assert_same(warm.spec, cold.spec)


# -- admission: stored the second time ---------------------------------------------------
def test_first_clean_load_leaves_only_a_marker(
    included_tree: Path, tree_cache: Path, full_validations: Calls
) -> None:
    load_spec("tree.yaml", registry=_REGISTRY)
    (marker,) = entries(tree_cache)
    assert marker.stat().st_size < 512  # no tree in it
    cache.clear_memory()  # a new process: the marker is on disk
    load_spec("tree.yaml", registry=_REGISTRY)
    assert full_validations.count == 2  # a marker is a miss; this load stores the entry
    assert marker.stat().st_size > 512
    cache.clear_memory()
    load_spec("tree.yaml", registry=_REGISTRY)
    assert full_validations.count == 2


def test_a_file_edited_between_loads_is_never_encoded(
    included_tree: Path, full_validations: Calls, monkeypatch: pytest.MonkeyPatch
) -> None:
    encoded: list[TreeSpec] = []
    real = cache._encode

    def counting(spec: TreeSpec, file_index: dict[str, int]) -> bytes | None:
        encoded.append(spec)
        return real(spec, file_index)

    monkeypatch.setattr(cache, "_encode", counting)
    for name in ("one", "two", "three"):  # an edit-and-run loop
        write(included_tree.parent, "tree.yaml", f"{_MAIN}name: {name}\n")
        assert load_spec("tree.yaml", registry=_REGISTRY).name == name
    assert encoded == []
    load_spec("tree.yaml", registry=_REGISTRY)  # the same content again: now stored
    assert len(encoded) == 1
    assert full_validations.count == 4


# -- changes miss ----------------------------------------------------------------------
_MAIN = """
    format: 1
    include: [lib/handling.yaml]
    root:
      sequence:
        memory: true
        children:
          - DetectSurvivor: {id: detect}
          - subtree: handle
    """
_LIB = """
    format: 1
    subtrees:
      handle:
        IsSurvivorDetected: {detector: detect}
    """


@pytest.fixture
def included_tree(tree_cache: Path, tree_dir: Path) -> Path:
    write(tree_dir, "lib/handling.yaml", _LIB)
    return write(tree_dir, "tree.yaml", _MAIN)


def test_changed_main_file_misses(included_tree: Path, full_validations: Calls) -> None:
    admit("tree.yaml")
    included_tree.write_text(included_tree.read_text() + "name: renamed\n")
    spec = load_spec("tree.yaml", registry=_REGISTRY)
    assert full_validations.count == 3
    assert spec.name == "renamed"


def test_changed_included_file_misses(included_tree: Path, full_validations: Calls) -> None:
    admit("tree.yaml")
    lib = included_tree.parent / "lib" / "handling.yaml"
    lib.write_text(lib.read_text().replace("{detector: detect}", "{name: Renamed, "
                                           "detector: detect}"))
    spec = load_spec("tree.yaml", registry=_REGISTRY)
    assert full_validations.count == 3
    assert spec.root.children[1].name == "Renamed"


def test_deleted_included_file_gives_its_diagnostic(
    included_tree: Path, full_validations: Calls
) -> None:
    admit("tree.yaml")
    (included_tree.parent / "lib" / "handling.yaml").unlink()
    with pytest.raises(TreeLoadError) as caught:
        load_spec("tree.yaml", registry=_REGISTRY)
    assert "does not exist" in str(caught.value)


def _registry_with(default: int) -> Registry:
    """One plugin, ``Counter``, whose ``count`` param defaults to ``default``."""

    @leaf("Counter", params=[Param("count", int, default=default)])
    class Counter(py_trees.behaviour.Behaviour):
        """Counts."""

        def __init__(self, name: str, *, count: int) -> None:
            super().__init__(name)
            self.count = count

    registry = Registry()
    registry.add(Counter, "tests/engine/test_cache.py")
    return registry


def test_changed_plugin_declaration_misses(
    tree_cache: Path, tree_dir: Path, full_validations: Calls
) -> None:
    write(tree_dir, "tree.yaml", "format: 1\nroot: {Counter: {}}\n")
    one, two = _registry_with(1), _registry_with(2)
    assert one.fingerprint() != two.fingerprint()
    for _ in range(2):  # marker, then entry, for each registry
        assert load_spec("tree.yaml", registry=one).root.attrs == {"count": 1}
        assert load_spec("tree.yaml", registry=two).root.attrs == {"count": 2}
    assert full_validations.count == 4
    cache.clear_memory()  # each registry has its own entry: both still hit
    assert load_spec("tree.yaml", registry=one).root.attrs == {"count": 1}
    assert load_spec("tree.yaml", registry=two).root.attrs == {"count": 2}
    assert full_validations.count == 4


def test_local_plugin_file_is_part_of_the_key(
    tree_cache: Path, tree_dir: Path, full_validations: Calls
) -> None:
    write(tree_dir, "plugins/counter.py", """
        import py_trees
        from sar_framework.engine.plugin import Param, leaf

        @leaf(params=[Param("count", int, default=3)])
        class LocalCounter(py_trees.behaviour.Behaviour):
            def __init__(self, name, *, count):
                super().__init__(name)
        """)
    write(tree_dir, "tree.yaml", "format: 1\nplugins: [plugins/counter.py]\n"
                                 "root: {LocalCounter: {}}\n")
    first = cache.validate("tree.yaml", registry=_REGISTRY)
    cache.validate("tree.yaml", registry=_REGISTRY)  # stores the entry
    cache.clear_memory()
    second = cache.validate("tree.yaml", registry=_REGISTRY)
    assert full_validations.count == 2
    assert second.registry.get("LocalCounter") is not None  # the build can find it
    assert_same(second.spec, first.spec)  # type: ignore[arg-type]
    plugin = tree_dir / "plugins" / "counter.py"
    os.utime(plugin, ns=(plugin.stat().st_atime_ns, plugin.stat().st_mtime_ns + 10**9))
    cache.validate("tree.yaml", registry=_REGISTRY)
    assert full_validations.count == 3


# -- a broken cache is a silent miss ---------------------------------------------------
def _corrupt(kind: str, path: Path) -> None:
    data = path.read_bytes()
    if kind == "garbage":
        path.write_bytes(b"\x80\x05not a pickle at all")
    elif kind == "truncated":
        path.write_bytes(data[: len(data) // 2])
    elif kind == "empty":
        path.write_bytes(b"")
    elif kind == "other_version":
        path.write_bytes(b"SARTREE\0\x00\x63" + data[10:])
    elif kind == "foreign_pickle":
        path.write_bytes(data[:10] + pickle.dumps({"not": "an entry"}))
    elif kind == "wrong_shape":
        path.write_bytes(data[:10] + pickle.dumps(("k", 1, 2, 3, 4, b"x")))
    elif kind == "bad_spec":
        state = list(pickle.loads(data[10:]))
        state[-1] = pickle.dumps(("head", [], [], []))
        path.write_bytes(data[:10] + pickle.dumps(tuple(state)))
    elif kind == "directory":
        path.unlink()
        path.mkdir()


@pytest.mark.parametrize("kind", ["garbage", "truncated", "empty", "other_version",
                                  "foreign_pickle", "wrong_shape", "bad_spec", "directory"])
def test_broken_entry_is_a_silent_miss(
    kind: str, included_tree: Path, tree_cache: Path, full_validations: Calls
) -> None:
    admit("tree.yaml")
    reference = load_spec("tree.yaml", registry=_REGISTRY)  # a hit
    (stored,) = entries(tree_cache)
    assert full_validations.count == 2
    _corrupt(kind, stored)
    cache.clear_memory()
    assert_same(load_spec("tree.yaml", registry=_REGISTRY), reference)
    assert full_validations.count == 3
    if kind != "directory":  # the full path wrote a good entry again (or a marker)
        admit("tree.yaml")
        cache.clear_memory()
        before = full_validations.count
        assert_same(load_spec("tree.yaml", registry=_REGISTRY), reference)
        assert full_validations.count == before


# -- errors are never cached -----------------------------------------------------------
def test_errors_are_never_cached(tree_cache: Path, tree_dir: Path, full_validations: Calls) -> None:
    write(tree_dir, "tree.yaml", """
        format: 1
        root:
          sequence:
            children:
              - NavigateToZon: {}
              - DetectSurvivor: {id: d, bogus: 1}
        """)
    first = cache.validate("tree.yaml", registry=_REGISTRY)
    second = cache.validate("tree.yaml", registry=_REGISTRY)
    reference = validate_file("tree.yaml", registry=_REGISTRY)
    assert first.diagnostics and first.spec is None
    assert first.diagnostics == second.diagnostics == reference.diagnostics
    assert first.structural == second.structural == reference.structural
    assert full_validations.count == 2
    assert entries(tree_cache) == []


def test_subtree_library_is_not_cached(included_tree: Path, tree_cache: Path) -> None:
    first = cache.validate("lib/handling.yaml", registry=_REGISTRY)
    second = cache.validate("lib/handling.yaml", registry=_REGISTRY)
    assert first.library == second.library == 1
    assert entries(tree_cache) == []


# -- switching it off and broken directories -------------------------------------------
def test_cache_false_neither_reads_nor_writes(
    included_tree: Path, tree_cache: Path, full_validations: Calls
) -> None:
    load_spec("tree.yaml", registry=_REGISTRY, cache=False)
    load_spec("tree.yaml", registry=_REGISTRY, cache=False)
    assert full_validations.count == 2
    assert not tree_cache.exists()


@pytest.mark.parametrize("value", ["0", "off", "False"])
def test_environment_switch_disables(
    value: str, included_tree: Path, tree_cache: Path, full_validations: Calls,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setenv(cache.ENV_SWITCH, value)
    load_spec("tree.yaml", registry=_REGISTRY)
    load_spec("tree.yaml", registry=_REGISTRY)
    assert full_validations.count == 2
    assert not tree_cache.exists()


def test_cli_no_cache_and_same_output_on_a_hit(
    tree_cache: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(REPO)
    tree = "trees/search_and_rescue.yaml"
    assert cli.main(["validate", "--no-cache", tree]) == 0
    cold = capsys.readouterr().out
    assert not tree_cache.exists()
    for _ in range(3):  # marker, entry, hit
        assert cli.main(["validate", tree]) == 0
    marked, stored, hit = capsys.readouterr().out.splitlines()
    assert entries(tree_cache)
    assert cold.strip() == marked == stored == hit
    assert "nodes)" in hit


def test_unwritable_cache_dir_still_loads(
    included_tree: Path, tmp_path: Path, full_validations: Calls,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    blocker = tmp_path / "not-a-dir"
    blocker.write_text("a file where the cache dir would go")
    monkeypatch.setenv(cache.ENV_DIR, str(blocker / "cache"))
    reference = load_spec("tree.yaml", registry=_REGISTRY, cache=False)
    assert_same(load_spec("tree.yaml", registry=_REGISTRY), reference)
    cache.clear_memory()
    assert_same(load_spec("tree.yaml", registry=_REGISTRY), reference)


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0,
                    reason="root writes into read-only directories")
def test_read_only_cache_dir_still_loads(
    included_tree: Path, tree_cache: Path, full_validations: Calls
) -> None:
    tree_cache.mkdir(mode=0o500)
    try:
        reference = load_spec("tree.yaml", registry=_REGISTRY, cache=False)
        assert_same(load_spec("tree.yaml", registry=_REGISTRY), reference)
        assert entries(tree_cache) == []
    finally:
        tree_cache.chmod(0o700)


def test_missing_cache_dir_is_created_private(included_tree: Path, tree_cache: Path) -> None:
    assert not tree_cache.exists()
    load_spec("tree.yaml", registry=_REGISTRY)
    assert len(entries(tree_cache)) == 1
    assert tree_cache.stat().st_mode & 0o077 == 0
    assert not list(tree_cache.glob(".tmp-*"))  # written atomically, nothing left over


def test_default_directory_follows_xdg(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.delenv(cache.ENV_DIR, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert cache.directory() == tmp_path / "sar_framework" / "trees"
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/ignored")
    assert cache.directory() == Path.home() / ".cache" / "sar_framework" / "trees"


# -- display paths ---------------------------------------------------------------------
def test_hit_from_another_directory_has_its_display_paths(
    included_tree: Path, full_validations: Calls, monkeypatch: pytest.MonkeyPatch
) -> None:
    root = included_tree.parent
    (root / "elsewhere").mkdir()
    admit("tree.yaml")  # stored from the tree's directory
    cache.clear_memory()
    for cwd, path in ((root / "elsewhere", "../tree.yaml"), (root / "lib", "../tree.yaml"),
                      (root, "./tree.yaml"), (root.parent, str(included_tree))):
        monkeypatch.chdir(cwd)
        hit = load_spec(path, registry=_REGISTRY)
        reference = validate_file(path, registry=_REGISTRY).spec
        assert reference is not None
        assert_same(hit, reference)
        assert hit.source == path
    assert full_validations.count == 2
    monkeypatch.chdir(root / "lib")
    files = {n.location.file for n in load_spec("../tree.yaml", registry=_REGISTRY).nodes()}
    assert files == {"../tree.yaml", "handling.yaml"}


# -- generated documents -----------------------------------------------------------------
@settings(max_examples=150, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(document=documents(_REGISTRY))
def test_generated_documents_load_alike(
    document: Any, tmp_path_factory: pytest.TempPathFactory
) -> None:
    path = tmp_path_factory.mktemp("cached") / "tree.yaml"
    path.write_text(yaml.safe_dump(document, sort_keys=False), encoding="utf-8")
    reference = validate_file(path, registry=_REGISTRY)
    first = cache.validate(path, registry=_REGISTRY)
    stored = cache.validate(path, registry=_REGISTRY)
    cache.clear_memory()
    second = cache.validate(path, registry=_REGISTRY)
    for result in (first, stored, second):
        assert result.diagnostics == reference.diagnostics
        if reference.spec is None:
            assert result.spec is None
        else:
            assert result.spec is not None
            assert_same(result.spec, reference.spec)


def test_default_registry_is_shared_key(tree_cache: Path) -> None:
    # The fingerprint is stable while nothing changes (or every load would miss).
    registry = default_registry()
    assert registry.fingerprint() == registry.fingerprint()
    assert registry.copy().fingerprint() == registry.fingerprint()

