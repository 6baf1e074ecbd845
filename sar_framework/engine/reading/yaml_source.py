"""Safe YAML in, composed nodes with positions out; YAML-level problems as diagnostics.

A tree file is composed (not constructed) with PyYAML's safe loader, using the
libyaml C composer when available: the result is a graph of
:class:`yaml.nodes.Node` that keeps every value's line and column. Nothing is
ever constructed from a tag other than the core JSON-like ones, so no Python
object can come out of a file.

YAML-level problems become diagnostics here: syntax errors (worded by PyYAML's
pure-Python parser, the reference), duplicate mapping keys, non-string keys,
merge keys, aliases and unsupported tags.
"""

from __future__ import annotations

import re
import threading
from collections.abc import Callable
from itertools import accumulate
from pathlib import Path
from typing import Any

import yaml
from yaml.constructor import SafeConstructor
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from sar_framework.engine.diagnostics import Diagnostic, SourceLocation

_TAG = "tag:yaml.org,2002:"
STR_TAG = _TAG + "str"
MAP_TAG = _TAG + "map"
SEQ_TAG = _TAG + "seq"
MERGE_TAG = _TAG + "merge"

#: Largest file the engine reads; a tree of 100,000 nodes stays well below.
MAX_FILE_BYTES = 8 * 1024 * 1024

# libyaml's C composer recurses once per nesting level; a pathological file could
# overflow the C stack (``- - - - ...`` on one long line). With flow nesting bounded
# (MAX_FLOW_DEPTH) and no line longer than _INLINE_MAX_LINE, block nesting stays below
# about 2 levels per indentation column plus 1 per character of a line, so the text is
# composed in the caller's thread; otherwise in a thread with a stack sized for the text.
_INLINE_MAX_LINE = 1000
_STACK_BYTES_PER_CHAR = 320
_stack_lock = threading.Lock()

#: Deepest flow nesting (``[`` / ``{``) accepted. libyaml's time grows with the square
#: of the flow depth (100,000 levels take minutes), and no valid tree comes close.
MAX_FLOW_DEPTH = 1000
# Flow brackets, skipping one-line quoted scalars and comments (a conservative lexer:
# it may over-count, which only matters beyond MAX_FLOW_DEPTH).
_FLOW_TOKENS = re.compile(r""""(?:[^"\\\n]|\\.)*"|'(?:[^'\n]|'')*'|(?<!\S)#[^\n]*|[\[\]{}]""")

_NOT_BRACKETS = bytes(b for b in range(256) if b not in b"[]{}")
_BRACKET_STEP = {ord("["): 1, ord("{"): 1, ord("]"): -1, ord("}"): -1}

#: PyYAML's safe loader, with libyaml's C composer when installed.
SafeLoader: type = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


_constructor = SafeConstructor()
#: How PyYAML's safe constructor builds each core scalar tag other than str.
SCALAR_BUILDERS: dict[str, Callable[[ScalarNode], Any]] = {
    _TAG + "null": _constructor.construct_yaml_null,
    _TAG + "bool": _constructor.construct_yaml_bool,
    _TAG + "int": _constructor.construct_yaml_int,
    _TAG + "float": _constructor.construct_yaml_float,
    _TAG + "timestamp": _constructor.construct_yaml_timestamp,
}


def location(node: Node, file: str) -> SourceLocation:
    """Return where ``node`` starts, 1-based.

    Args:
        node: A composed YAML node.
        file: The file name to print.

    Returns:
        The node's location.
    """
    mark = node.start_mark
    return SourceLocation(file, mark.line + 1, mark.column + 1)


def _syntax_diagnostic(exc: yaml.YAMLError, text: str, file: str) -> Diagnostic:
    mark = getattr(exc, "problem_mark", None)
    if isinstance(exc, yaml.reader.ReaderError):
        line = text.count("\n", 0, exc.position) + 1
        col = exc.position - (text.rfind("\n", 0, exc.position) + 1) + 1
        code = exc.character if isinstance(exc.character, int) else ord(exc.character)
        return Diagnostic(
            SourceLocation(file, line, col),
            f"YAML: unacceptable character #x{code:04x}: {exc.reason}",
        )
    if mark is None:
        return Diagnostic(SourceLocation(file, 1, 1), f"YAML: {exc}")
    parts = [p for p in (getattr(exc, "context", None), getattr(exc, "problem", None)) if p]
    return Diagnostic(
        SourceLocation(file, mark.line + 1, mark.column + 1), "YAML: " + ", ".join(parts)
    )


def _too_deep(text: str, file: str) -> Diagnostic | None:
    """Report flow nesting deeper than :data:`MAX_FLOW_DEPTH`, before composing."""
    if text.count("[") + text.count("{") <= MAX_FLOW_DEPTH:
        return None  # cannot nest deeper than there are openers
    # Next bound, at C speed: the largest rise of the running bracket balance. Brackets
    # inside quotes or comments are counted too (a closer there could hide depth, which
    # only a deliberately crafted file would do: the cost then is time, not a crash).
    # (UTF-8 multi-byte sequences never contain ASCII bytes.)
    brackets = text.encode("utf-8", "surrogatepass").translate(None, _NOT_BRACKETS)
    balance = list(accumulate(map(_BRACKET_STEP.__getitem__, brackets)))
    if max(balance) - min(0, *balance) <= MAX_FLOW_DEPTH:
        return None
    depth = 0
    for match in _FLOW_TOKENS.finditer(text):
        char = match.group()
        if char in "[{":
            depth += 1
            if depth > MAX_FLOW_DEPTH:
                pos = match.start()
                line = text.count("\n", 0, pos) + 1
                col = pos - (text.rfind("\n", 0, pos) + 1) + 1
                return Diagnostic(
                    SourceLocation(file, line, col),
                    f"YAML: nested deeper than {MAX_FLOW_DEPTH} levels of [ ] or {{ }}",
                )
        elif char in "]}" and depth:
            depth -= 1
    return None


def _compose_with(loader_cls: type, text: str) -> Node | None:
    loader = loader_cls(text)
    try:
        return loader.get_single_node()
    finally:
        loader.dispose()


def _compose_big(text: str) -> Node | None:
    """Compose ``text`` in a thread whose stack fits any nesting the text can hold."""
    result: list[Any] = [None, None]

    def work() -> None:
        try:
            result[0] = _compose_with(SafeLoader, text)
        except BaseException as exc:  # re-raised in the caller's thread
            result[1] = exc

    size = 1024 * 1024 + _STACK_BYTES_PER_CHAR * len(text)
    with _stack_lock:
        previous = threading.stack_size(size)
        try:
            worker = threading.Thread(target=work, name="sar-yaml-compose")
            worker.start()
        except RuntimeError as exc:  # no memory for such a stack
            raise yaml.YAMLError(f"cannot parse a file this complex: {exc}") from exc
        finally:
            threading.stack_size(previous)
    worker.join()
    if result[1] is not None:
        raise result[1]
    return result[0]


def compose(text: str, file: str) -> tuple[Node | None, list[Diagnostic]]:
    """Compose one YAML document, safely.

    Args:
        text: The YAML text.
        file: The file name to print in diagnostics.

    Returns:
        The root node (None for an empty document or on error) and the diagnostics.
    """
    deep = _too_deep(text, file)
    if deep is not None:
        return None, [deep]
    try:
        if max(map(len, text.split("\n"))) < _INLINE_MAX_LINE:
            root = _compose_with(SafeLoader, text)
        else:
            root = _compose_big(text)
    except yaml.YAMLError as fast_error:
        # Word the error the way PyYAML's reference (pure-Python) parser does.
        try:
            _compose_with(yaml.SafeLoader, text)
        except yaml.YAMLError as exc:
            return None, [_syntax_diagnostic(exc, text, file)]
        except RecursionError:
            pass
        return None, [_syntax_diagnostic(fast_error, text, file)]
    except RecursionError:  # only without libyaml: the pure composer recurses
        return None, [Diagnostic(SourceLocation(file, 1, 1), "YAML: nested too deeply")]
    if root is None:
        return None, []
    diagnostics: list[Diagnostic] = []
    if "&" in text and "*" in text:
        diagnostics = _alias_diagnostics(text, file)
    return (None if diagnostics else root), diagnostics


def _alias_diagnostics(text: str, file: str) -> list[Diagnostic]:
    """Report every alias (``*name``); only run when the text may contain one."""
    out = []
    for event in yaml.parse(text, Loader=SafeLoader):
        if isinstance(event, yaml.AliasEvent):
            mark = event.start_mark
            out.append(
                Diagnostic(
                    SourceLocation(file, mark.line + 1, mark.column + 1),
                    f"YAML aliases (*{event.anchor}) are not supported; "
                    "reuse part of a tree with a subtree",
                )
            )
    return out


def read(path: Path, file: str) -> tuple[Node | None, list[Diagnostic]]:
    """Read and compose a YAML file.

    Args:
        path: The file to read.
        file: Its name as printed in diagnostics.

    Returns:
        The root node (None on error or for an empty file) and the diagnostics.
    """
    here = SourceLocation(file, 1, 1)
    try:
        with path.open("rb") as stream:
            data = stream.read(MAX_FILE_BYTES + 1)  # never more, whatever the file is
    except IsADirectoryError:
        return None, [Diagnostic(here, "is a directory, not a tree file")]
    except FileNotFoundError:
        return None, [Diagnostic(here, "no such file")]
    except OSError as exc:
        return None, [Diagnostic(here, f"cannot read: {exc.strerror or exc}")]
    if len(data) > MAX_FILE_BYTES:
        return None, [Diagnostic(here, f"file too large (limit {MAX_FILE_BYTES} bytes)")]
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        col = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        return None, [Diagnostic(SourceLocation(file, line, col), "file is not valid UTF-8")]
    return compose(text, file)


_KIND_WORDS = {MappingNode: "a mapping", SequenceNode: "a list"}
_PYTHON_TAG = re.compile(r"^tag:yaml\.org,2002:python/")


class Reader:
    """Reads composed nodes of one file, reporting YAML-level problems.

    Args:
        file: The file name to print.
        diagnostics: Where problems are appended.
    """

    __slots__ = ("diagnostics", "file")

    def __init__(self, file: str, diagnostics: list[Diagnostic]) -> None:
        self.file = file
        self.diagnostics = diagnostics

    def error(self, node: Node, message: str) -> None:
        """Record a problem at ``node``."""
        self.diagnostics.append(Diagnostic(location(node, self.file), message))

    def _tag_problem(self, node: Node) -> str:
        tag = node.tag
        short = "!!" + tag[len(_TAG) :] if tag.startswith(_TAG) else tag
        if _PYTHON_TAG.match(tag):
            return f"YAML tag '{short}' is not allowed (safe YAML only)"
        return f"unsupported YAML tag '{short}'"

    def scalar(self, node: ScalarNode) -> tuple[bool, Any]:
        """Return ``(ok, value)`` for a scalar node, with PyYAML's safe semantics.

        Args:
            node: A scalar node.

        Returns:
            ``(True, value)``, or ``(False, None)`` after reporting an unsupported tag.
        """
        tag = node.tag
        if tag == STR_TAG:
            return True, node.value
        builder = SCALAR_BUILDERS.get(tag)
        if builder is None:
            self.error(node, self._tag_problem(node))
            return False, None
        try:
            value = builder(node)
        except Exception:  # PyYAML raises ValueError, KeyError, AttributeError, ...
            self.error(node, f"YAML: '{node.value}' is not a valid {tag[len(_TAG):]}")
            return False, None
        return True, value

    def items(self, node: MappingNode) -> list[tuple[str, Node, Node]] | None:
        """Return a mapping's ``(key, key_node, value_node)`` entries.

        Duplicate keys (the later one wins, as in PyYAML), non-string keys, merge
        keys and tagged mappings are reported; bad entries are left out.

        Args:
            node: A mapping node.

        Returns:
            The entries, or None when the mapping itself carries an unsupported tag.
        """
        if node.tag != MAP_TAG:
            self.error(node, self._tag_problem(node))
            return None
        out: list[tuple[str, Node, Node]] = []
        index: dict[str, int] = {}
        for key_node, value_node in node.value:
            if key_node.tag == STR_TAG and type(key_node) is ScalarNode:
                key = key_node.value
            else:
                self._bad_key(key_node)
                continue
            at = index.get(key)
            if at is None:
                index[key] = len(out)
                out.append((key, key_node, value_node))
            else:
                line = out[at][1].start_mark.line + 1
                self.error(key_node, f"duplicate key '{key}' (first defined on line {line})")
                out[at] = (key, key_node, value_node)
        return out

    def _bad_key(self, key_node: Node) -> None:
        if key_node.tag == MERGE_TAG:
            self.error(key_node, "YAML merge keys (<<) are not supported")
            return
        if type(key_node) is ScalarNode:
            ok, value = self.scalar(key_node)
            if not ok:
                return
            what = f"{type(value).__name__} {key_node.value!r}"
        else:
            what = _KIND_WORDS.get(type(key_node), "a node")
        self.error(key_node, f"a mapping key must be a string, got {what}")

    def sequence(self, node: SequenceNode) -> list[Node] | None:
        """Return a sequence's items, or None (reported) when it carries a bad tag."""
        if node.tag != SEQ_TAG:
            self.error(node, self._tag_problem(node))
            return None
        return node.value

    def to_python(self, node: Node) -> Any:
        """Convert a node to plain Python values (dict, list, str, int, ...).

        Problems are reported and the offending entries left out (None for a bad
        scalar). With no problems, the result equals ``yaml.safe_load`` of the text.

        Args:
            node: A composed node.

        Returns:
            The plain value.
        """
        if type(node) is ScalarNode:
            return self.scalar(node)[1]
        if type(node) is SequenceNode:
            items = self.sequence(node)
            return None if items is None else [self.to_python(n) for n in items]
        entries = self.items(node)
        if entries is None:
            return None
        return {key: self.to_python(value) for key, _, value in entries}
