"""Hot swap (engine/reloading/) on real py_trees trees, mid-tick."""

from __future__ import annotations

import sys
import textwrap
from pathlib import Path
from typing import Any

import py_trees
import pytest
from py_trees.common import Status

from sar_framework.engine.api import LoadedTree, load_tree
from sar_framework.engine.diagnostics import TreeLoadError
from sar_framework.engine.registry import Registry, discover
from sar_framework.engine.reloading.hot_swap import HotSwap, hot_swap, prepare_swap

from ..conftest import HERE

SWAP_PLUGINS = HERE / "plugins_for_tests" / "swap"


@pytest.fixture(scope="module")
def registry() -> Registry:
    reg = discover([SWAP_PLUGINS], builtins=False, entry_points=False)
    assert reg.diagnostics == []
    return reg


@pytest.fixture
def halted(registry: Registry) -> list[str]:
    """The halts the Work leaves saw (the module discover imported them from)."""
    plugin = registry.get("Work")
    assert plugin is not None
    record: list[str] = sys.modules[plugin.cls.__module__].HALTED
    record.clear()
    return record


class Mission:
    """A tree file ticked by hand, swapped for new texts of the same file."""

    def __init__(self, directory: Path, registry: Registry, text: str,
                 context: dict[str, Any] | None = None) -> None:
        py_trees.blackboard.Blackboard.clear()
        self.path = directory / "tree.yaml"
        self.registry = registry
        self.context = context or {}
        self.write(text)
        self.loaded: LoadedTree = load_tree(self.path, self.context, registry=registry)
        self.root = self.loaded.root

    def write(self, text: str) -> None:
        body = textwrap.dedent(text).strip("\n")
        self.path.write_text("format: 1\n" + body + "\n", encoding="utf-8")

    def tick(self, times: int = 1) -> Status:
        for _ in range(times):
            self.root.tick_once()
        return self.root.status

    def until_done(self, most: int = 50) -> int:
        """Tick until the root is no longer RUNNING; return how many ticks it took."""
        for count in range(1, most + 1):
            if self.tick() != Status.RUNNING:
                return count
        raise AssertionError(f"still RUNNING after {most} ticks")

    def swap(self, text: str) -> HotSwap:
        self.write(text)
        done = hot_swap(self.loaded, self.path, self.context, registry=self.registry)
        self.loaded, self.root = done.tree, done.tree.root
        return done

    def state(self) -> list[tuple[int, Status]]:
        """Every behaviour of the tree (by identity) with its status, in tree order."""
        return [(id(b), b.status) for b in self.root.iterate()]

    def node(self, name: str) -> py_trees.behaviour.Behaviour:
        found = [b for b in self.root.iterate() if b.name == name]
        assert len(found) == 1, (name, [b.name for b in self.root.iterate()])
        return found[0]


THREE = """
root:
  sequence:
    name: Main
    memory: true
    children:
      - Work: {name: A, ticks: 3}
      - Work: {name: B, ticks: 1}
      - Work: {name: C, ticks: 1, note: first}
"""


def test_a_changed_note_rebuilds_that_leaf_only(tmp_path: Path, registry: Registry,
                                                halted: list[str]) -> None:
    run = Mission(tmp_path, registry, THREE)
    assert run.tick(2) == Status.RUNNING
    a, main = run.node("A"), run.root
    done = run.swap(THREE.replace("note: first", "note: second"))
    assert done.summary.changed == ("C",)
    assert done.summary.added == done.summary.removed == done.summary.restarted == ()
    assert set(done.summary.kept) == {"Main", "A", "B"}
    assert run.root is main and run.node("A") is a and a.status == Status.RUNNING
    assert run.node("C").note == "second" and done.fresh == [run.node("C")]
    assert main.current_child is a and halted == []
    # A goes on where it was: RUNNING a third tick, SUCCESS the fourth (B starts), then
    # B and C each end a tick later.
    assert run.tick() == Status.RUNNING and a.status == Status.RUNNING
    assert run.tick() == Status.RUNNING and a.status == Status.SUCCESS and a.total == 4
    assert run.until_done() == 2 and run.root.status == Status.SUCCESS
    assert done.summary.line() == "1 changed (C); 3 kept"


def test_a_running_leaf_removed_is_halted_and_the_sequence_goes_on(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    run = Mission(tmp_path, registry, THREE)
    run.tick(2)
    a = run.node("A")
    done = run.swap(THREE.replace("      - Work: {name: A, ticks: 3}\n", ""))
    assert halted == ["A"] and a.status == Status.INVALID
    assert done.summary.removed == ("A",) and done.summary.halted == ("A",)
    assert run.root.current_child is run.node("B")
    assert run.tick() == Status.RUNNING and run.node("B").status == Status.RUNNING
    assert run.until_done() == 2 and run.root.status == Status.SUCCESS


def test_a_running_leaf_changed_is_halted_and_restarted_in_its_place(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    run = Mission(tmp_path, registry, THREE)
    run.tick(2)
    old_a = run.node("A")
    done = run.swap(THREE.replace("name: A, ticks: 3", "name: A, ticks: 1"))
    new_a = run.node("A")
    assert new_a is not old_a and halted == ["A"] and done.summary.changed == ("A",)
    assert run.root.current_child is new_a
    assert run.tick() == Status.RUNNING and new_a.status == Status.RUNNING
    assert run.tick() == Status.RUNNING and new_a.status == Status.SUCCESS


def test_a_leaf_added_before_the_running_one_waits_for_the_next_run(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    run = Mission(tmp_path, registry, THREE)
    run.tick(2)
    a = run.node("A")
    done = run.swap(THREE.replace("      - Work: {name: A", "      - Work: {name: X, ticks: 1}\n"
                                  "      - Work: {name: A"))
    assert done.summary.added == ("X",) and halted == []
    assert run.root.current_child is a
    run.tick(2)
    assert a.status == Status.SUCCESS and run.node("X").status == Status.INVALID


def test_an_invalid_file_is_refused_and_the_old_tree_keeps_ticking(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    run = Mission(tmp_path, registry, THREE)
    run.tick(2)
    before = run.state()
    run.write(THREE.replace("Work: {name: B", "Wrok: {name: B"))
    with pytest.raises(TreeLoadError) as caught:
        hot_swap(run.loaded, run.path, registry=registry)
    text = "\n".join(str(d) for d in caught.value.diagnostics)
    assert f"{run.path}:8:9:" in text and "Wrok" in text and "did you mean 'Work'" in text
    assert run.state() == before
    assert halted == []
    assert run.until_done() == 4 and run.root.status == Status.SUCCESS


def test_a_tree_that_cannot_be_built_is_refused_and_nothing_changes(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    run = Mission(tmp_path, registry, THREE)
    run.tick(2)
    before = run.state()
    # B changes (it would be halted if the swap went on); UsesContext has no zone_manager.
    run.write(THREE.replace("name: B, ticks: 1", "name: B, ticks: 5")
              .replace("      - Work: {name: C", "      - UsesContext: {}\n      - Work: {name: C"))
    with pytest.raises(TreeLoadError) as caught:
        hot_swap(run.loaded, run.path, registry=registry)
    assert "needs the context object 'zone_manager'" in str(caught.value.diagnostics[0])
    assert run.state() == before
    assert run.root.children[1].ticks == 1 and halted == []


def test_blackboard_values_and_context_objects_are_kept(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    zones = object()
    text = """
    blackboard:
      count: {type: int, initial: 10}
    root:
      sequence:
        name: Main
        memory: true
        children:
          - Work: {name: A, ticks: 1, done: "{count}"}
          - UsesContext: {name: U}
          - Work: {name: B, ticks: 5}
    """
    run = Mission(tmp_path, registry, text, context={"zone_manager": zones})
    run.tick(3)
    storage = py_trees.blackboard.Blackboard.storage
    assert storage["/count"] == 1
    new_text = text.replace("count: {type: int, initial: 10}",
                            "count: {type: int, initial: 10}\n      extra: {type: int, initial: 7}")
    new_text = new_text.replace("UsesContext: {name: U}", "UsesContext: {name: V}")
    done = run.swap(new_text)
    assert storage["/count"] == 1 and storage["/extra"] == 7
    assert done.summary.added == ("V",) and done.summary.removed == ("U",)
    assert run.node("V").zone_manager is zones


SET_TREE = """\
format: 1
blackboard:
  battery: {type: int, initial: 100}
  drain: {type: int, initial: 5}
root:
  Script: {name: Drain, code: "battery := battery - drain"}
"""


def test_values_set_from_outside_hold_for_the_swapped_file(tmp_path: Path) -> None:
    py_trees.blackboard.Blackboard.clear()
    path = tmp_path / "tree.yaml"
    path.write_text(SET_TREE)
    loaded = load_tree(path, initial_values={"battery": 50, "drain": 7})
    loaded.root.tick_once()
    storage = py_trees.blackboard.Blackboard.storage
    assert storage["/battery"] == 43
    path.write_text(SET_TREE.replace("name: Drain", "name: Pay"))
    done = hot_swap(loaded, path)
    assert done.tree.initial_values == {"battery": 50, "drain": 7}
    assert done.tree.spec.entries["/drain"].initial == 7  # the swapped file's, as set
    assert done.tree.spec.declarations[""]["battery"].initial == 50
    done.tree.root.tick_once()
    assert storage["/battery"] == 36
    # a file that no longer declares an entry set from outside is refused, as at start
    path.write_text(SET_TREE.replace("  drain: {type: int, initial: 5}\n", "")
                    .replace("battery - drain", "battery - 1"))
    with pytest.raises(TreeLoadError, match=r"--set drain=7 \(command-line argument\): the "
                                            r"tree declares no entry 'drain'"):
        hot_swap(done.tree, path)
    # and so is one declaring it in a type the value does not convert to
    path.write_text(SET_TREE.replace("drain: {type: int, initial: 5}",
                                     "drain: {type: bool, initial: true}"))
    with pytest.raises(TreeLoadError, match=r"tree.yaml:4:3: error: --set drain=7"):
        hot_swap(done.tree, path)
    py_trees.blackboard.Blackboard.clear()


def test_references_follow_the_behaviour_that_is_ticked(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    text = """
    root:
      sequence:
        name: Main
        memory: true
        children:
          - Work: {name: A, id: a, ticks: 1, note: one}
          - Peek: {name: P, work: a}
          - Work: {name: B, ticks: 3}
    """
    run = Mission(tmp_path, registry, text)
    run.tick(2)
    a = run.node("A")
    # P changes, A is kept: the new P holds the old A.
    done = run.swap(text.replace("name: P,", "name: P, id: p,"))
    assert done.summary.changed == ("P",) and run.node("P").work is a
    # A changes: P, unchanged, is rebuilt to hold the new A.
    done = run.swap(text.replace("note: one", "note: two").replace("name: P,", "name: P, id: p,"))
    assert done.summary.changed == ("A",) and done.summary.restarted == ("P",)
    assert run.node("P").work is run.node("A") is not a


SUBTREE = """
root:
  sequence:
    name: Main
    memory: true
    children:
      - Work: {name: First, ticks: 1}
      - subtree: {tree: Job, ports: {out: "{total}"}}
blackboard:
  total: {type: int, initial: 0}
subtrees:
  Job:
    ports:
      out: {type: int, direction: output}
    root:
      sequence:
        name: JobSeq
        memory: true
        children:
          - Work: {name: Long, ticks: 4, done: "{out}"}
          - Work: {name: Tail, ticks: 1, note: x}
"""


def test_a_subtree_keeps_its_running_leaf_and_its_ports(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    run = Mission(tmp_path, registry, SUBTREE)
    run.tick(4)
    long = run.node("Long")
    assert long.status == Status.RUNNING
    done = run.swap(SUBTREE.replace("note: x", "note: y"))
    assert done.summary.changed == ("Tail",) and run.node("Long") is long
    assert run.node("JobSeq").current_child is long and halted == []
    assert run.until_done() == 3 and run.root.status == Status.SUCCESS
    assert py_trees.blackboard.Blackboard.storage["/total"] == 1
    assert run.node("Tail").note == "y"


def test_a_running_subtree_removed_is_halted_by_its_parent(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    run = Mission(tmp_path, registry, SUBTREE)
    run.tick(4)
    job = run.node("JobSeq")
    done = run.swap(SUBTREE.replace('      - subtree: {tree: Job, ports: {out: "{total}"}}\n',
                                    "      - Work: {name: Instead, ticks: 1}\n"))
    assert halted == ["Long"] and job.status == Status.INVALID
    assert set(done.summary.removed) == {"JobSeq", "Long", "Tail"}
    assert done.summary.added == ("Instead",)
    assert run.root.current_child is run.node("Instead")
    assert run.until_done() == 2 and run.root.status == Status.SUCCESS


def test_a_changed_root_restarts_everything_and_halts_what_ran(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    run = Mission(tmp_path, registry, THREE)
    run.tick(2)
    done = run.swap(THREE.replace("memory: true", "memory: false"))
    assert halted == ["A"] and done.summary.changed == ("Main",)
    assert set(done.summary.restarted) == {"A", "B", "C"} and done.summary.kept == ()
    assert len(done.fresh) == 4
    assert run.tick() == Status.RUNNING and run.node("A").status == Status.RUNNING


def test_a_decorator_keeps_its_count_and_takes_a_new_child(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    text = """
    root:
      repeat:
        name: Again
        num_success: 3
        child:
          Work: {name: W, ticks: 1, note: a}
    """
    run = Mission(tmp_path, registry, text)
    run.tick(3)  # RUNNING, SUCCESS (1 of 3), RUNNING
    again = run.root
    done = run.swap(text.replace("note: a", "note: b"))
    assert run.root is again and done.summary.changed == ("W",) and halted == ["W"]
    assert again.decorated is run.node("W") and run.node("W").parent is again
    assert run.until_done() == 4 and run.root.status == Status.SUCCESS  # 2 more, 2 ticks each


def test_an_unchanged_file_keeps_everything(tmp_path: Path, registry: Registry,
                                            halted: list[str]) -> None:
    run = Mission(tmp_path, registry, SUBTREE)
    run.tick(3)
    objects = [id(b) for b in run.root.iterate()]
    done = run.swap(SUBTREE)
    assert [id(b) for b in run.root.iterate()] == objects and done.fresh == []
    assert done.summary.line() == "5 kept"
    assert set(done.tree.behaviours) == {n.uid for n in run.loaded.spec.nodes()}


def test_a_prepared_swap_changes_nothing_until_committed(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    run = Mission(tmp_path, registry, THREE)
    run.tick(2)
    before = run.state()
    run.write(THREE.replace("name: A, ticks: 3", "name: A, ticks: 9")
              .replace("      - Work: {name: C", "      - Work: {name: D}\n      - Work: {name: C"))
    run.path.write_text(run.path.read_text().replace(
        "format: 1\n", "format: 1\nblackboard:\n  fresh: {type: int, initial: 3}\n"))
    prepared = prepare_swap(run.loaded, run.path, registry=registry)
    assert sorted(b.name for b in prepared.fresh) == ["A", "D"]
    assert "/fresh" not in py_trees.blackboard.Blackboard.storage  # written on commit
    assert run.state() == before and halted == []
    run.tick()  # the old tree ticks on, as if nothing was prepared
    done = prepared.commit()
    assert halted == ["A"] and done.summary.added == ("D",) and done.summary.changed == ("A",)
    a = done.tree.behaviours[done.tree.spec.root.children[0].uid]
    assert a.ticks == 9 and any(a is b for b in done.fresh) and run.node("A") is a
    assert py_trees.blackboard.Blackboard.storage["/fresh"] == 3
    with pytest.raises(RuntimeError, match="committed already"):
        prepared.commit()


def test_a_node_with_scripts_keeps_its_wrapper_and_a_changed_one_gets_a_new_one(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    text = """
    blackboard:
      n: {type: int, initial: 0}
    root:
      sequence:
        name: Main
        memory: true
        children:
          - Work: {name: A, ticks: 2, _onSuccess: "n += 1"}
          - Work: {name: B, ticks: 1, note: x, _onSuccess: "n += 10"}
    """
    run = Mission(tmp_path, registry, text)
    run.tick()
    wrapper_a, wrapper_b = run.root.children
    a = wrapper_a.decorated
    assert a.name == "A" and a.status == Status.RUNNING
    done = run.swap(text.replace("note: x", "note: y"))
    assert run.root.children[0] is wrapper_a and wrapper_a.decorated is a
    assert run.root.children[1] is not wrapper_b and run.root.children[1].decorated.note == "y"
    assert done.summary.changed == ("B",) and run.root.current_child is wrapper_a
    assert run.until_done() == 3 and run.root.status == Status.SUCCESS
    assert py_trees.blackboard.Blackboard.storage["/n"] == 11


def test_a_parallel_keeps_its_running_children_and_takes_a_new_one(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    text = """
    root:
      parallel:
        name: Both
        policy: success_on_selected
        selected: [A]
        children:
          - Work: {name: A, ticks: 3}
          - Work: {name: B, ticks: 9, note: x}
    """
    run = Mission(tmp_path, registry, text)
    run.tick()
    both, a = run.root, run.node("A")
    done = run.swap(text.replace("note: x", "note: y"))
    assert run.root is both and run.node("A") is a and halted == ["B"]
    assert done.summary.changed == ("B",)
    assert [c.name for c in both.policy.children] == ["A"]
    assert both.policy.children[0] is a
    assert run.until_done() == 3 and both.status == Status.SUCCESS


def test_a_parallel_whose_last_running_child_leaves_goes_on_with_the_others(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    text = """
    root:
      parallel:
        name: Both
        policy: success_on_all
        children:
          - Work: {name: A, ticks: 3}
          - Work: {name: B, ticks: 9}
    """
    run = Mission(tmp_path, registry, text)
    run.tick()
    a = run.node("A")
    run.swap(text.replace("          - Work: {name: B, ticks: 9}\n", ""))
    assert halted == ["B"] and a.status == Status.RUNNING and run.root.children == [a]
    assert run.until_done() == 3 and run.root.status == Status.SUCCESS and a.total == 4


def test_a_memory_sequence_with_nothing_left_after_its_removed_child_starts_over(
        tmp_path: Path, registry: Registry, halted: list[str]) -> None:
    run = Mission(tmp_path, registry, THREE)
    run.tick(4)  # A done, B RUNNING
    a = run.node("A")
    assert a.status == Status.SUCCESS and run.root.current_child is run.node("B")
    done = run.swap(THREE.split("      - Work: {name: B", maxsplit=1)[0])
    assert halted == ["B"] and done.summary.removed == ("B", "C")
    assert run.root.status == Status.INVALID and run.node("A") is a
    assert run.tick() == Status.RUNNING and a.status == Status.RUNNING  # from the start
