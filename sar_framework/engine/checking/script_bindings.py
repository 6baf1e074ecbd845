"""Scripts in a tree file: compiled where they are written, their variables resolved per scope.

Every script attribute (``Script``'s and ``ScriptCondition``'s ``code``,
``Precondition``'s ``if`` and the pre/post-conditions ``_skipIf`` ... ``_post`` of any
node) is compiled once, when its node is read; a syntax error is reported at the file
column of the culprit (the value's column plus the error's, plus one for a quoted
scalar). Each variable a script reads or writes resolves in the node's scope exactly as
a port's ``{key}`` does (``@name`` is the root's ``name``) and joins the same entry
checks (:mod:`.entries`): a ``:=`` or ``=`` writes, a read reads. After the walk each
script is type-checked against its entries' types (declared, else a port writer's).

The script language (lark) is imported only when a tree has a script.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from sar_framework.engine.checking.entries import DataScope, Entries, Report
from sar_framework.engine.diagnostics import SourceLocation
from sar_framework.engine.ports import ENTRY_NAME, EntryRef
from sar_framework.engine.reading.document import DocPath, Document
from sar_framework.engine.spec import NodeSpec

if TYPE_CHECKING:
    from sar_framework.engine.scripting import CompiledScript, ScriptError

#: Attributes whose script is a condition (its last value must be true/false or a number).
CONDITIONS = frozenset({"if", "_failureIf", "_successIf", "_skipIf", "_while"})


class ScriptBindings:
    """Script handling for one validation run.

    Args:
        entries: The tree's entries (reads and writes are noted there).
        report: Where problems go.
    """

    def __init__(self, entries: Entries, report: Report) -> None:
        self.entries = entries
        self.report = report
        self.origins: dict[int, tuple[SourceLocation, int, bool]] = {}
        self.pending: list[tuple[NodeSpec, str, CompiledScript]] = []

    def compile(self, doc: Document, path: DocPath, text: Any) -> CompiledScript | None:
        """Compile one script attribute's text; report a syntax error at its file column."""
        if not isinstance(text, str) or not text.strip():
            return None  # the schema check reports it
        from sar_framework.engine.scripting import ScriptError, compile_script

        node = doc.nodes[path]
        quoted = getattr(node, "style", None) in ('"', "'")
        start = doc.where(path)
        block = getattr(node, "style", None) in ("|", ">")
        try:
            script = compile_script(text)
        except ScriptError as error:
            what = f"script '{path[-1]}' of {owner_in(doc, path)}"
            self.report(self.at(start, quoted, block, error), f"{what}: {error.message}")
            return None
        self.origins[id(script)] = (start, quoted, block)
        return script

    @staticmethod
    def at(start: SourceLocation, quoted: bool, block: bool, error: ScriptError) -> SourceLocation:
        """The file location of a script error (in a block scalar: its line, at the indicator)."""
        if block:
            return SourceLocation(start.file, start.line + error.line, start.col)
        column = (start.col + int(quoted) if error.line == 1 else 1) + error.column - 1
        return SourceLocation(start.file, start.line + error.line - 1, column)

    def bind(self, spec: NodeSpec, scope: DataScope) -> None:
        """Resolve the variables of a node's scripts in ``scope``; note reads and writes."""
        who = owner(spec.name, spec.kind)
        for attr, script in spec.scripts.items():
            where = self.origins[id(script)][0]
            what = f"script '{attr}' of {who}"
            for names, note in ((script.reads, self.entries.read),
                                (script.writes, self.entries.write)):
                for name in names:
                    ref = EntryRef(name.lstrip("@"), name.startswith("@"))
                    if not ENTRY_NAME.match(ref.name):
                        self.report(where, f"{what}: '{name}' is not a valid entry name")
                        continue
                    key = spec.script_keys.get(name)
                    if key is None and name not in spec.script_keys:
                        key = self.entries.resolve(scope, ref, where, what, name)
                        spec.script_keys[name] = key  # type: ignore[assignment]
                    if key is not None:
                        note(key, "any", where, what)
            self.pending.append((spec, attr, script))

    def check(self) -> None:
        """Type-check every bound script against its entries' types."""
        for spec, attr, script in self.pending:
            if any(key is None for key in spec.script_keys.values()):
                continue  # an unknown name, already reported
            types = {name: self.type_of(key) for name, key in spec.script_keys.items()}
            start, quoted, block = self.origins[id(script)]
            what = f"script '{attr}' of {owner(spec.name, spec.kind)}"
            for problem in script.check(types, condition=attr in CONDITIONS):
                self.report(self.at(start, quoted, block, problem), f"{what}: {problem.message}")

    def type_of(self, key: str) -> str:
        """An entry's type: declared, else the first typed port writing it, else ``any``."""
        for decl in self.entries.declared.get(key, ()):
            return decl.type
        for use in self.entries.writes.get(key, ()):
            if use.type != "any":
                return use.type
        return "any"


def owner(name: str, kind: str) -> str:
    """How a script's node is named in a message: ``Alert (Script)``, or just ``Script``."""
    return f"{name} ({kind})" if name != kind else kind


def owner_in(doc: Document, path: DocPath) -> str:
    """:func:`owner` of the node whose script attribute stands at ``path`` in ``doc``."""
    attrs = doc.value
    for step in path[:-1]:
        attrs = attrs[step]
    kind = str(path[-2])
    name = attrs.get("name") if isinstance(attrs, dict) else None
    return owner(name if isinstance(name, str) else kind, kind)
