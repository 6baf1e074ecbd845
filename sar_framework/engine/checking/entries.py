"""Blackboard entries, resolved statically: scopes, absolute keys and the checks on them.

Every name a node uses (a port bound to ``{goal}``, a script's variable) belongs to
a scope and resolves to an absolute py_trees key, as BT.CPP 4 resolves it at run time:

- the main tree's scope is the root, ``/``: ``{goal}`` is ``/goal``;
- each subtree insertion has its own scope, ``/<Subtree>@<uid>`` (the uid's dots, and
  any character of the name but letters, digits, ``_`` and ``-``, become ``_``: py_trees
  reads ``a.b`` as attribute ``b`` of ``a``);
- ``{@goal}`` always names the root's ``/goal``;
- a subtree use remaps an inner name to an entry of the parent scope
  (``ports: {path: "{plan}"}``) or gives it a literal; with ``autoremap: true`` every
  other name goes to the parent's entry of the same name, except names starting with
  ``_`` (BT.CPP's private keys) and the definition's own ``blackboard:`` entries.

:class:`Entries` collects every read, write and declaration while the semantic walk
resolves bindings, then :meth:`Entries.check` reports, all at once: a read of an entry
nothing writes, that has no initial value and is not declared (with did-you-mean: an
entry of its scope under a close name); readers and writers (or
declarations) whose types disagree. Unknown names in a scope that declares its entries
are reported while resolving, with a did-you-mean (with ``autoremap``, a name the
subtree does not declare is checked against the parent's declarations).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from sar_framework.engine.diagnostics import SourceLocation, did_you_mean
from sar_framework.engine.ports import NO_DEFAULT, EntryRef, compatible
from sar_framework.engine.spec import Declared, Entry

#: Reports a problem: ``error(where, message)``.
Report = Callable[[SourceLocation, str], None]


@dataclass
class DataScope:
    """The names of one scope and where they lead.

    Attributes:
        prefix: Key prefix, ``""`` for the root scope, else ``/<Subtree>@<uid>``.
        label: For messages (``the main tree``, ``subtree 'Follow'``).
        declared: Names the scope declares, or None when it declares none (any name goes).
        remap: Names remapped to absolute keys of the parent scope (None: a remap that
            failed, already reported; its uses are not checked again).
        local: Names that stay in this scope even with ``autoremap``.
        autoremap: Whether other names go to the parent's entry of the same name.
        parent: The enclosing scope (None for the root).
    """

    prefix: str
    label: str
    declared: dict[str, Declared] | None = None
    remap: dict[str, str | None] = field(default_factory=dict)
    local: set[str] = field(default_factory=set)
    autoremap: bool = False
    parent: DataScope | None = None

    def root(self) -> DataScope:
        """Return the root scope."""
        scope = self
        while scope.parent is not None:
            scope = scope.parent
        return scope

    def key(self, name: str) -> str | None:
        """Return the absolute key ``name`` leads to from this scope (None: a broken remap)."""
        if name in self.remap:
            return self.remap[name]
        if (self.autoremap and self.parent is not None and not name.startswith("_")
                and name not in self.local):
            return self.parent.key(name)
        return f"{self.prefix}/{name}"


@dataclass(frozen=True)
class Use:
    """One read or write of an entry by a node."""

    key: str
    type: str
    where: SourceLocation
    who: str


class Entries:
    """The entries of one tree: declarations, initial values, reads and writes.

    Args:
        report: Where problems go.
    """

    def __init__(self, report: Report) -> None:
        self.report = report
        self.declared: dict[str, list[Declared]] = {}
        self.initial: dict[str, Any] = {}
        self.reads: dict[str, list[Use]] = {}
        self.writes: dict[str, list[Use]] = {}
        #: Each scope's ``blackboard:`` section as declared: ``""`` for the main tree,
        #: else the subtree definition's name.
        self.scopes: dict[str, dict[str, Declared]] = {}

    def declare(self, key: str, entry: Declared) -> None:
        """Note a declaration of ``key`` (and its initial value)."""
        self.declared.setdefault(key, []).append(entry)
        if entry.initial is not NO_DEFAULT:
            self.initial[key] = entry.initial

    def set_initial(self, key: str, value: Any) -> None:
        """Note a value written to ``key`` before the first tick."""
        self.initial[key] = value

    def resolve(
        self, scope: DataScope, ref: EntryRef, where: SourceLocation, what: str,
        shown: str = "",
    ) -> str | None:
        """Return the absolute key of ``ref`` in ``scope``; report a name it does not declare.

        Args:
            scope: The node's scope.
            ref: The entry as written.
            where: Where it is written.
            what: What names it, for the message (``port 'goal'``).
            shown: The name as written, when not ``{name}`` (a script's ``@name``).

        Returns:
            The key, or None after reporting an undeclared name.
        """
        home = scope.root() if ref.root else scope
        while (home.declared is not None and ref.name not in home.declared and home.autoremap
               and home.parent is not None and not ref.name.startswith("_")):
            home = home.parent  # autoremapped: the parent's declarations decide
        if home.declared is not None and ref.name not in home.declared:
            names = list(home.declared)
            hint = did_you_mean(ref.name, names) or (
                f" (declared: {', '.join(names)})" if names else " (it declares none)")
            self.report(where, f"{what}: '{shown or ref}' is not an entry of {home.label}{hint}")
            return None
        return f"/{ref.name}" if ref.root else scope.key(ref.name)  # None: reported

    def read(self, key: str, type_: str, where: SourceLocation, who: str) -> None:
        """Note that ``who`` reads ``key`` as ``type_``."""
        self.reads.setdefault(key, []).append(Use(key, type_, where, who))

    def write(self, key: str, type_: str, where: SourceLocation, who: str) -> None:
        """Note that ``who`` writes ``key`` as ``type_``."""
        self.writes.setdefault(key, []).append(Use(key, type_, where, who))

    # -- after the walk -----------------------------------------------------------------
    def check(self) -> None:
        """Report unwritten reads and type disagreements, every one."""
        for key, reads in self.reads.items():
            writes = self.writes.get(key, [])
            declared = self.declared.get(key, [])
            if not writes and key not in self.initial and not any(d.caller_sets
                                                                  for d in declared):
                hint = self.similar(key) or (" (declare it under 'blackboard:' if the "
                                             "caller sets it)")
                for use in reads:
                    self.report(use.where, f"{use.who} reads '{key[1:]}', but nothing writes "
                                f"it and it has no initial value{hint}")
            for use in reads:
                self.check_read(use, writes, declared)
        for key, writes in self.writes.items():
            for use in writes:
                for decl in self.declared.get(key, []):
                    if not compatible(use.type, decl.type):
                        self.report(use.where, f"{use.who} writes {use.type} to '{key[1:]}', "
                                    f"declared {decl.type}{_at(decl.where)}")
                        break

    def similar(self, key: str) -> str:
        """A did-you-mean for a read of ``key``: an entry of its scope written or set."""
        scope, _, name = key.rpartition("/")
        known = {*self.writes, *self.initial, *self.declared} - {key}
        return did_you_mean(name, [k[len(scope) + 1:] for k in known
                                   if k.rpartition("/")[0] == scope])

    def check_read(self, use: Use, writes: list[Use], declared: list[Declared]) -> None:
        """Report the first declaration or writer whose type ``use`` cannot read."""
        for decl in declared:
            if not compatible(decl.type, use.type):
                self.report(use.where, f"{use.who} reads '{use.key[1:]}' as {use.type}, "
                            f"declared {decl.type}{_at(decl.where)}")
                return
        if declared:
            return
        for writer in writes:
            if not compatible(writer.type, use.type):
                self.report(use.where, f"{use.who} reads '{use.key[1:]}' as {use.type}, but "
                            f"{writer.who} at {writer.where} writes {writer.type}")
                return

    def entries(self) -> dict[str, Entry]:
        """Return every entry the tree declares, initialises, reads or writes, by key."""
        out: dict[str, Entry] = {}
        for key, decls in self.declared.items():
            first = decls[0]
            out[key] = Entry(key, first.type, NO_DEFAULT, first.description)
        for table in (self.writes, self.reads):
            for key, uses in table.items():
                if key not in out:
                    typed = [u.type for u in uses if u.type != "any"]
                    out[key] = Entry(key, typed[0] if typed else "any")
        for key, value in self.initial.items():
            out.setdefault(key, Entry(key)).initial = value
        return out


def _at(where: SourceLocation | None) -> str:
    return f" at {where}" if where is not None else ""
