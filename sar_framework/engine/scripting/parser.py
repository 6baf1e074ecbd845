"""Parsing a script's text into :mod:`.nodes`, with BehaviorTree.CPP 4.7.3's rules.

The grammar (``grammar.lark``, parsed by lark's LALR parser) fixes precedence; this module
adds what a context-free tower cannot say: BT.CPP's three operand groups (arithmetic
``+ - * /`` and prefix ``-``; bitwise ``& | ^`` and prefix ``~ !``; concatenation ``..``)
may not be mixed in one comparison's operands without parentheses, an assignment's left
side must be a variable, and literals must fit BT.CPP's types. Enum names are replaced by
their values here, so the evaluator never looks them up.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from typing import TYPE_CHECKING

from . import nodes, values
from .errors import ScriptError

if TYPE_CHECKING:  # lark is imported on the first parse: a tree without scripts never pays
    import lark
    from lark import Token, Tree
    from lark.exceptions import UnexpectedInput

#: Operator -> the group BT.CPP puts it in (dsl::groups in scripting/operators.hpp).
GROUPS = {"+": "arithmetic", "-": "arithmetic", "*": "arithmetic", "/": "arithmetic",
          "&": "bitwise", "|": "bitwise", "^": "bitwise", "~": "bitwise", "!": "bitwise",
          "..": "concatenation"}
_NUMBERS = {"INT", "HEX", "FLOAT"}
_ASSIGN_OPS = {"DEFINE", "ASSIGN", "ADD_ASSIGN", "SUB_ASSIGN", "MUL_ASSIGN", "DIV_ASSIGN"}


@functools.lru_cache(maxsize=1)
def _lark() -> lark.Lark:
    import lark

    grammar = resources.files(__package__).joinpath("grammar.lark").read_text()
    return lark.Lark(grammar, parser="lalr", lexer="contextual", maybe_placeholders=False)


@dataclass
class Parsed:
    """A parsed script: its statements and the variables it reads and writes, in order."""

    statements: list[nodes.Node]
    reads: dict[str, None] = field(default_factory=dict)
    writes: dict[str, None] = field(default_factory=dict)


def parse(text: str, enums: Mapping[str, int]) -> Parsed:
    """Parse ``text``; raise :class:`ScriptError` for every kind of bad script.

    Args:
        text: The script.
        enums: Enum names the script may use, with their integer values.

    Returns:
        The statements, reads and writes.
    """
    from lark.exceptions import UnexpectedInput

    if not text.strip():
        raise ScriptError("empty script", 1, 1, text)
    try:
        tree = _lark().parse(text)
    except UnexpectedInput as error:
        raise _syntax_error(text, error).in_script(text) from None
    builder = _Builder(enums)
    try:
        statements = [builder.build(child) for child in tree.children
                      if not (isinstance(child, str) and child.type == "SEMI")]
    except ScriptError as error:
        raise error.in_script(text) from None
    except RecursionError:
        raise ScriptError("the script is nested too deeply", 1, 1, text) from None
    return Parsed(statements, builder.reads, builder.writes)


def _end_position(text: str) -> tuple[int, int]:
    body = text.rstrip()
    line = body.count("\n") + 1
    return line, len(body) - (body.rfind("\n") + 1)


def _syntax_error(text: str, error: UnexpectedInput) -> ScriptError:
    from lark.exceptions import UnexpectedCharacters, UnexpectedToken

    if isinstance(error, UnexpectedCharacters):
        char = text[error.pos_in_stream] if error.pos_in_stream < len(text) else ""
        what = "unterminated string" if char in ("'", '"') else f"unexpected character {char!r}"
        return ScriptError(what, error.column, error.line)
    token = error.token if isinstance(error, UnexpectedToken) else None
    if token is None or token.type == "$END":
        line, column = _end_position(text)
        if text.rstrip().endswith(";"):
            return ScriptError("nothing after the last ';' (BT.CPP refuses a trailing ';')",
                               column, line)
        return ScriptError("the script ends in the middle of an expression", column + 1, line)
    expected = set(getattr(error, "expected", ()) or ())
    what = f"unexpected {token.value!r}"
    if token.type == "QUESTION":
        what += " ('?:' cannot be chained: put the inner one in parentheses)"
    elif token.type in _ASSIGN_OPS:
        what += " (assignments cannot be chained: separate them with ';')"
    elif token.type == "SEMI":
        what += " (an expression must come before each ';')"
    elif "SEMI" in expected:
        what += " (is an operator or a ';' missing before it?)"
    elif "RPAR" in expected:
        what += " (expected ')')"
    return ScriptError(what, token.column, token.line)


def _position(token: Token) -> nodes.Position:
    return nodes.Position(token.line, token.column)


class _Builder:
    """Turns lark's tree into nodes, checking groups, targets and literals on the way."""

    def __init__(self, enums: Mapping[str, int]) -> None:
        self.enums = enums
        self.reads: dict[str, None] = {}
        self.writes: dict[str, None] = {}

    def build(self, item: Tree | Token, checked: bool = False) -> nodes.Node:
        if isinstance(item, str):  # a lark Token is a str; a Tree is not
            return self.atom(item)
        kind = item.data
        kids = item.children
        if kind in ("binary", "unary") and not checked and self.op_of(item) in GROUPS:
            self.check_groups([item])
            checked = True
        if kind == "paren":
            return self.build(kids[1])
        if kind == "unary":
            op = kids[0]
            return nodes.Unary(op.value, self.build(kids[1], checked), _position(op))
        if kind == "binary":
            op = kids[1]
            inner = checked and op.value in GROUPS
            left, right = self.build(kids[0], inner), self.build(kids[2], inner)
            return nodes.Binary(op.value, left, right, _position(op))
        if kind == "compare":
            operands = kids[0::2]
            self.check_groups(operands)
            built = [self.build(operand, True) for operand in operands]
            ops = [(op.value, _position(op)) for op in kids[1::2]]
            return nodes.Compare(built, ops, ops[0][1])
        if kind == "conditional":
            condition, question, then, _colon, otherwise = kids
            return nodes.Conditional(self.build(condition), self.build(then),
                                     self.build(otherwise), _position(question))
        if kind == "assignment":
            return self.assignment(*kids)
        if len(kids) == 1 and isinstance(kids[0], str):  # an aliased atom
            return self.atom(kids[0])
        raise AssertionError(f"unexpected parse node {kind}")  # pragma: no cover

    @staticmethod
    def op_of(item: Tree) -> str:
        op = item.children[0] if item.data == "unary" else item.children[1]
        return op.value

    def group_ops(self, item: Tree | Token, found: list[Token]) -> None:
        """Collect, in source order, the group operators of one operand (not inside parens)."""
        if isinstance(item, str) or item.data not in ("binary", "unary"):
            return
        if self.op_of(item) not in GROUPS:
            return
        if item.data == "unary":
            found.append(item.children[0])
            self.group_ops(item.children[1], found)
        else:
            self.group_ops(item.children[0], found)
            found.append(item.children[1])
            self.group_ops(item.children[2], found)

    def check_groups(self, operands: list[Tree | Token]) -> None:
        found: list[Token] = []
        for operand in operands:
            self.group_ops(operand, found)
        if not found:
            return
        first = found[0]
        for op in found[1:]:
            if GROUPS[op.value] != GROUPS[first.value]:
                raise ScriptError(
                    f"'{op.value}' ({GROUPS[op.value]}) cannot be mixed with '{first.value}' "
                    f"({GROUPS[first.value]}) without parentheses", op.column, op.line)

    def assignment(self, target: Tree | Token, op: Token, value: Tree | Token) -> nodes.Node:
        while not isinstance(target, str) and target.data == "paren":
            target = target.children[1]
        if not isinstance(target, str) and target.data == "name":
            target = target.children[0]
        if not (isinstance(target, str) and target.type == "NAME"):
            raise ScriptError(f"the left side of '{op.value}' must be a variable",
                              op.column, op.line)
        name = target.value
        if name in self.enums:
            raise ScriptError(f"{name!r} is an enum name and cannot be assigned",
                              target.column, target.line)
        if op.value in nodes.COMPOUND:
            self.reads.setdefault(name)
        self.writes.setdefault(name)
        return nodes.Assign(op.value, name, self.build(value), _position(target))

    def atom(self, token: Token) -> nodes.Node:
        where = _position(token)
        kind, text = token.type, token.value
        if kind == "NAME":
            if text in self.enums:
                return nodes.Literal(int(self.enums[text]), where)
            self.reads.setdefault(text)
            return nodes.Name(text, where)
        if kind == "STRING":
            return nodes.Literal(text[1:-1], where)
        if kind in ("TRUE", "FALSE"):
            return nodes.Literal(kind == "TRUE", where)
        if kind in _NUMBERS:
            return nodes.Literal(self.number(token), where)
        raise ScriptError(f"invalid number {text!r}", token.column, token.line)

    @staticmethod
    def number(token: Token) -> int | float:
        kind, text = token.type, token.value
        if kind == "FLOAT":
            number = float(text)
            if number in (float("inf"), float("-inf")):
                raise ScriptError(f"number {text!r} is out of range", token.column, token.line)
            return number
        number = int(text, 16) if kind == "HEX" else int(text)
        if not values.INT64_MIN <= number <= values.INT64_MAX:
            raise ScriptError(f"integer {text!r} does not fit in 64 bits", token.column,
                              token.line)
        return number
