"""The static check of a compiled script against its variables' declared types.

Types are the names ports declare: ``int``, ``float``, ``bool``, ``str``, ``object`` (any
value: not checked) and anything else (``list``, ``geometry_msgs/msg/PoseStamped``), which
is opaque: it can be read, copied into an entry of the same type and nothing more. The
check follows the operators' rules in :mod:`.values`, so a script it passes fails at run
time only on values (an unset variable, ``2.5`` into an ``int``, an integer condition
that is not 0 or 1), never on types. Expressions whose type cannot be known are ``any``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from . import nodes, values
from .errors import ScriptError

ANY = "any"
NUMERIC = ("int", "float", "bool")
_ALIASES = {"object": ANY, "any": ANY, "": ANY, "string": "str", "double": "float"}


def normalised(type_name: str) -> str:
    """A declared type name as the check uses it (``object`` -> ``any``)."""
    return _ALIASES.get(type_name, type_name)


def _a(t: str) -> str:
    if t == ANY:
        return "a value of any type"
    return ("an " if t[:1] in "aeiou" else "a ") + t


def _kind(t: str) -> str:
    if t in NUMERIC:
        return "number"
    if t in ("str", ANY):
        return t
    return "opaque"


def check(statements: Sequence[nodes.Node], text: str, types: Mapping[str, str], *,
          closed: bool = True, condition: bool = False) -> list[ScriptError]:
    """Return the type problems of a script's parsed ``statements`` (its ``text``).

    :meth:`.CompiledScript.check` documents the arguments; this module does not know
    that class, so the two do not import each other.
    """
    checker = _Checker({name: normalised(t) for name, t in types.items()}, closed)
    last = ANY
    try:
        for statement in statements:
            last = checker.infer(statement)
    except RecursionError:
        return [ScriptError("the script is nested too deeply", 1, 1, text)]
    if condition and _kind(last) in ("str", "opaque"):
        checker.problem(statements[-1], f"a condition must give a number or "
                                                f"true/false, not {_a(last)}")
    return [problem.in_script(text) for problem in checker.problems]


class _Checker:
    def __init__(self, scope: dict[str, str], closed: bool) -> None:
        self.scope = scope
        self.closed = closed
        self.problems: list[ScriptError] = []

    def problem(self, node: nodes.Node, message: str) -> str:
        self.problems.append(node.fail(message))
        return ANY

    def infer(self, node: nodes.Node) -> str:
        if isinstance(node, nodes.Literal):
            return "bool" if isinstance(node.value, bool) else type(node.value).__name__
        if isinstance(node, nodes.Name):
            if node.name in self.scope:
                return self.scope[node.name]
            if self.closed:
                return self.problem(node, f"unknown variable {node.name!r}")
            return ANY
        if isinstance(node, nodes.Unary):
            return self.unary(node)
        if isinstance(node, nodes.Binary):
            return self.binary(node, self.infer(node.left), self.infer(node.right))
        if isinstance(node, nodes.Compare):
            return self.compare(node)
        if isinstance(node, nodes.Conditional):
            condition = self.infer(node.condition)
            if _kind(condition) == "opaque":
                self.problem(node, f"{_a(condition)} cannot be the condition of '?:'")
            then, otherwise = self.infer(node.then), self.infer(node.otherwise)
            if then == otherwise:
                return then
            if {then, otherwise} <= set(NUMERIC):
                return "float" if "float" in (then, otherwise) else "int"
            return ANY
        if isinstance(node, nodes.Assign):
            return self.assign(node)
        raise AssertionError(f"unknown node {node!r}")  # pragma: no cover

    def unary(self, node: nodes.Unary) -> str:
        t = self.infer(node.operand)
        if _kind(t) in ("str", "opaque"):
            return self.problem(node, f"prefix '{node.op}' does not apply to {_a(t)}")
        if node.op == "!":
            return "bool"
        if node.op == "~" or t in ("int", "bool"):
            return "int"
        return "float" if t == "float" else ANY

    def binary(self, node: nodes.Binary, left: str, right: str) -> str:
        op, kinds = node.op, {_kind(left), _kind(right)}
        clash = f"'{op}' does not apply to {_a(left)} and {_a(right)}"
        if "opaque" in kinds:
            return self.problem(node, clash)
        if op == "..":
            if kinds == {"number"}:
                return self.problem(node, "'..' needs a string on one side, not two numbers")
            return "str"
        if op == "+" and left == right == "str":
            return "str"
        if "str" in kinds:
            if op == "+" and ANY in kinds:
                return ANY
            return self.problem(node, clash)
        if op in ("&&", "||"):
            return "bool"
        if op in ("&", "|", "^"):
            return "int"
        if op == "/":
            return "float"
        if ANY in kinds:
            return ANY
        return "int" if {left, right} <= {"int", "bool"} else "float"

    def compare(self, node: nodes.Compare) -> str:
        types = [self.infer(operand) for operand in node.operands]
        for i, (_op, where) in enumerate(node.ops):
            pair = (types[i], types[i + 1])
            kinds = {_kind(pair[0]), _kind(pair[1])}
            if "opaque" in kinds:
                self.problems.append(ScriptError(f"cannot compare {_a(pair[0])} with "
                                                 f"{_a(pair[1])}", where.column, where.line))
            elif kinds == {"str", "number"}:
                for operand in node.operands[i:i + 2]:
                    self.text_as_number(operand)
        return "bool"

    def text_as_number(self, node: nodes.Node, target: str = "") -> bool:
        """Whether ``node`` (when a string literal) reads as a number; notes it when not."""
        if isinstance(node, nodes.Literal) and isinstance(node.value, str):
            try:
                values.string_to_number(node.value, {})
            except values.OperationError as error:
                self.problem(node, str(error) + target)
                return False
        return True

    def assign(self, node: nodes.Assign) -> str:
        value = self.infer(node.value)
        name, op = node.name, node.op
        if name not in self.scope:
            if op == ":=" or not self.closed:
                self.scope[name] = value
                return value
            hint = " (use ':=' to create it)" if op == "=" else ""
            self.problem(node, f"unknown variable {name!r}{hint}")
            self.scope[name] = value
            return value
        target = self.scope[name]
        if op in nodes.COMPOUND:
            if (_kind(target), _kind(value)) in (("number", "number"), ("number", ANY),
                                                 (ANY, "number"), (ANY, ANY)):
                return target
            if op == "+=" and {_kind(target), _kind(value)} <= {"str", ANY}:
                return target
            return self.problem(node, f"'{op}' does not apply to {name!r} ({_a(target)}) and "
                                      f"{_a(value)}")
        self.assignable(node, target, value)
        return target

    def assignable(self, node: nodes.Assign, target: str, value: str) -> None:
        if ANY in (target, value) or target == value:
            return
        wrong = f"cannot assign {_a(value)} to {node.name!r}, which is {_a(target)}"
        if _kind(target) == "number" and _kind(value) == "number":
            literal = node.value
            if (isinstance(literal, nodes.Literal) and target in ("int", "bool")
                    and isinstance(literal.value, float) and not literal.value.is_integer()):
                self.problem(node, wrong)
            return
        if _kind(target) == "number" and value == "str" and isinstance(node.value,
                                                                       nodes.Literal):
            self.text_as_number(node.value, f" (assigned to {node.name!r}, {_a(target)})")
            return
        self.problem(node, wrong)
