"""Tick one leaf, or a small tree written as YAML text, and keep a record of every tick.

::

    run = tree_from_yaml('''
        sequence:
          memory: true
          children:
            - Countdown: {name: Wait, ticks: 2}
    ''')
    run.tick(3)
    run.statuses("Wait")        # [Status.RUNNING, Status.RUNNING, Status.SUCCESS]
    run.feedback("Wait")        # ['2 to go', '1 to go', 'done (SUCCESS)']

    run = leaf_run("Countdown", {"ticks": 1}, blackboard={"/goal": 3})

    run.entries()               # the tree's blackboard entries now: {'goal': ..., ...}
    run.entry("goal")           # one of them (KeyError, with did-you-mean, if undeclared)
    run.history[0].entries      # as they were after the first tick

The text is a node (the tree's ``root``) or a whole tree file (with ``format: 1``). It is
loaded by the engine's loader, so it is validated exactly like a tree file; a problem
raises :class:`~sar_framework.engine.api.TreeLoadError` with every diagnostic (located in
a temporary ``tree.yaml``; a bare node is preceded there by three header lines). Values for
the py_trees blackboard (for plugins that read it) are set before the first tick, or, as
a list of mappings, one mapping before each tick.
"""

from __future__ import annotations

import tempfile
import textwrap
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import py_trees
import yaml
from py_trees.common import Status

from sar_framework.engine.api import LoadedTree, load_tree
from sar_framework.engine.diagnostics import did_you_mean
from sar_framework.engine.registry import Registry

Blackboard = Mapping[str, Any] | Sequence[Mapping[str, Any]] | None


@dataclass
class TickRecord:
    """What every node showed after one tick.

    Attributes:
        tick: 1 for the first tick.
        statuses: Behaviour name -> status.
        feedback: Behaviour name -> feedback message.
        entries: The tree's blackboard entries that were set: name -> value.
    """

    tick: int
    statuses: dict[str, Status] = field(default_factory=dict)
    feedback: dict[str, str] = field(default_factory=dict)
    entries: dict[str, Any] = field(default_factory=dict)


class TreeRun:
    """A loaded tree, ticked on demand, with the record of every tick.

    Args:
        loaded: The tree, as :func:`~sar_framework.engine.api.load_tree` returns it.
        blackboard: Blackboard values: one mapping (set before the first tick) or a list
            of mappings (the i-th set before tick i+1).

    Attributes:
        root: The root behaviour.
        history: One record per tick, oldest first.
    """

    def __init__(self, loaded: LoadedTree, blackboard: Blackboard = None) -> None:
        self.loaded = loaded
        self.root = loaded.root
        self.history: list[TickRecord] = []
        if blackboard is None:
            self._blackboard: list[Mapping[str, Any]] = []
        elif isinstance(blackboard, Mapping):
            self._blackboard = [blackboard]
        else:
            self._blackboard = list(blackboard)

    def tick(self, times: int = 1) -> Status:
        """Tick the root ``times`` times; return its status."""
        for _ in range(times):
            index = len(self.history)
            if index < len(self._blackboard):
                for key, value in self._blackboard[index].items():
                    py_trees.blackboard.Blackboard.set(key, value)
            self.root.tick_once()
            record = TickRecord(index + 1)
            for behaviour in self.root.iterate():
                record.statuses[behaviour.name] = behaviour.status
                record.feedback[behaviour.name] = behaviour.feedback_message
            record.entries = self.entries()
            self.history.append(record)
        return self.root.status

    def tick_until_done(self, max_ticks: int = 100) -> Status:
        """Tick until the root is SUCCESS or FAILURE (at most ``max_ticks``); return it."""
        for _ in range(max_ticks):
            if self.tick() in (Status.SUCCESS, Status.FAILURE):
                break
        return self.root.status

    def node(self, name: str) -> py_trees.behaviour.Behaviour:
        """The behaviour called ``name``; raises KeyError when none or several are."""
        found = [b for b in self.root.iterate() if b.name == name]
        if len(found) != 1:
            names = sorted({b.name for b in self.root.iterate()})
            raise KeyError(f"{len(found)} behaviours are called {name!r}; names: {names}")
        return found[0]

    def statuses(self, name: str | None = None) -> list[Status]:
        """The status of ``name`` (default: the root) after each tick so far."""
        key = self.root.name if name is None else self.node(name).name
        return [record.statuses[key] for record in self.history]

    def feedback(self, name: str | None = None) -> list[str]:
        """The feedback message of ``name`` (default: the root) after each tick so far."""
        key = self.root.name if name is None else self.node(name).name
        return [record.feedback[key] for record in self.history]

    def entries(self) -> dict[str, Any]:
        """The tree's blackboard entries that are set now: name -> value.

        Names as the tree writes them (``goal``, a subtree's ``Follow@0_2/path``); entries
        declared but never written are left out.
        """
        storage = py_trees.blackboard.Blackboard.storage
        return {name: storage[key] for name, key in self.loaded.entries.items()
                if key in storage}

    def entry(self, name: str) -> Any:
        """The current value of the tree's entry ``name``.

        Raises:
            KeyError: The tree has no such entry (with the names it has, and the closest),
                or it is not set yet.
        """
        keys = self.loaded.entries
        if name not in keys:
            raise KeyError(f"the tree has no entry {name!r}{did_you_mean(name, list(keys))}; "
                           f"entries: {sorted(keys)}")
        storage = py_trees.blackboard.Blackboard.storage
        if keys[name] not in storage:
            raise KeyError(f"entry {name!r} is not set yet")
        return storage[keys[name]]

    def table(self) -> str:
        """The history as text: one line per tick, ``name=STATUS`` for every node."""
        return "\n".join(
            f"tick {r.tick}: " + ", ".join(f"{n}={s.name}" for n, s in r.statuses.items())
            for r in self.history)

    def shutdown(self) -> None:
        """Stop the tree and shut every behaviour down; clear the blackboard."""
        self.root.stop(Status.INVALID)
        for behaviour in self.root.iterate():
            behaviour.shutdown()
        py_trees.blackboard.Blackboard.clear()


def tree_from_yaml(text: str, *, context: Mapping[str, Any] | None = None,
                   plugin_paths: Sequence[str | Path] = (), registry: Registry | None = None,
                   blackboard: Blackboard = None) -> TreeRun:
    """Load a node or a tree file given as YAML text.

    Args:
        text: A node (``sequence: {...}``) or a tree document (with ``format: 1``);
            indentation common to every line is removed.
        context: Shared objects the plugins declared they need.
        plugin_paths: Extra plugin files, dirs or modules (relative to the working dir).
        registry: The plugins; default: built-ins and installed entry points.
        blackboard: Blackboard values (see :class:`TreeRun`).

    Returns:
        The loaded tree, not ticked yet.

    Raises:
        TreeLoadError: The text is not a valid tree; the message lists every problem.
    """
    text = textwrap.dedent(text).strip("\n") + "\n"
    if not any(line.startswith("format:") for line in text.splitlines()):
        text = "format: 1\nname: test\nroot:\n" + textwrap.indent(text, "  ")
    with tempfile.TemporaryDirectory(prefix="sar_tree_") as folder:
        path = Path(folder) / "tree.yaml"
        path.write_text(text, encoding="utf-8")
        loaded = load_tree(path, context, registry=registry,
                           plugin_paths=[str(Path(p).resolve()) for p in plugin_paths])
    return TreeRun(loaded, blackboard)


def leaf_run(plugin: str, params: Mapping[str, Any] | None = None, **kwargs: Any) -> TreeRun:
    """Load one leaf of ``plugin`` with ``params`` as a tree of its own.

    Args:
        plugin: The plugin name.
        params: Its params (``name`` and ``id`` too); defaults fill in the rest.
        **kwargs: As for :func:`tree_from_yaml` (context, plugin_paths, registry, blackboard).

    Returns:
        The one-leaf tree, not ticked yet.
    """
    node = yaml.safe_dump({plugin: dict(params or {})}, default_flow_style=True, width=10**6)
    return tree_from_yaml(node, **kwargs)


def declared_leaf(cls: type, name: str | None = None, **values: Any) -> Any:
    """Construct a leaf plugin's class as the loader does: declared defaults, then ``values``.

    For tests that build a leaf by hand (to hand it a context object or another leaf):
    the defaults come from the class's ``@leaf`` declaration, the one place they are written.

    Args:
        cls: A class marked with ``@leaf``.
        name: The behaviour's name; the plugin's name by default.
        **values: Params, context objects and references, overriding the defaults.

    Returns:
        The constructed behaviour.

    Raises:
        TypeError: ``cls`` is not a leaf plugin.
    """
    from sar_framework.engine.plugin import PLUGIN_ATTRIBUTE, REQUIRED

    spec = getattr(cls, PLUGIN_ATTRIBUTE, None)
    if spec is None or spec.cls is not cls:
        raise TypeError(f"{cls.__name__} carries no @leaf declaration of its own")
    kwargs = {p.name: p.default for p in spec.params if p.default is not REQUIRED}
    return cls(name=name or spec.name, **{**kwargs, **values})
