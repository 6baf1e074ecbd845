"""Scripts in a BT.CPP file: the pre/post-condition attributes and the script nodes' code.

BT.CPP 4 reads eight attributes on every node as scripts (``_failureIf _successIf _skipIf
_while`` before it ticks, ``_onSuccess _onFailure _onHalted _post`` after; BT.CPP's
``PreCondNames``/``PostCondNames``), and ``Script``/``ScriptCondition``'s ``code`` and
``Precondition``'s ``if``. Our tree language has the same attributes with the same
meaning (:data:`~sar_framework.engine.nodes.kind_model.CONDITION_ATTRS`,
docs/reference/scripts.md), so import and export copy them as written. On import each
script is compiled (a syntax error is reported with its column inside the script) and its
variables become blackboard uses: what it reads, then what it assigns.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from sar_framework.engine.nodes.kind_model import CONDITION_ATTRS
from sar_framework.interop.btcpp_models import PortModel

#: The pre/post-condition attributes, in BT.CPP's order.
CONDITION_NAMES: tuple[str, ...] = tuple(a.name for a in CONDITION_ATTRS)


@dataclass(frozen=True)
class ScriptVariables:
    """The blackboard variables one script uses.

    Attributes:
        reads: Names it reads (``@name`` for the root blackboard's).
        writes: Names it assigns.
    """

    reads: tuple[str, ...]
    writes: tuple[str, ...]


def script_variables(text: str) -> ScriptVariables | str:
    """Compile ``text``; return its variables, or the syntax error as a message.

    Args:
        text: The script as written in the attribute.

    Returns:
        The variables, or ``"<message> (column N of the script)"``.
    """
    from sar_framework.engine.scripting import ScriptError, compile_script

    try:
        script = compile_script(text)
    except ScriptError as error:
        where = f"line {error.line}, " if error.line > 1 else ""
        return f"{error.message} ({where}column {error.column} of the script)"
    return ScriptVariables(tuple(script.reads), tuple(script.writes))


def split_conditions(tag: str, attrs: dict[str, str]
                     ) -> tuple[dict[str, str], dict[str, str], list[str]]:
    """Split an element's attributes: the rest, the pre/post conditions, what is dropped.

    An attribute starting with ``_`` that is no condition (``_autoremap`` aside) is
    dropped with a warning: BT.CPP keeps it as an attribute no node reads.

    Args:
        tag: The element name (for messages).
        attrs: Its attributes.

    Returns:
        The other attributes, the conditions (name -> script), the warnings.
    """
    conditions = {k: v for k, v in attrs.items() if k in CONDITION_NAMES}
    dropped = [f"'{key}' on <{tag}> is not a pre/post condition BT.CPP knows (it keeps it "
               f"as an attribute no node reads): dropped; the conditions are "
               f"{', '.join(CONDITION_NAMES)}" for key in attrs
               if key.startswith("_") and key != "_autoremap" and key not in conditions]
    rest = {k: v for k, v in attrs.items() if not k.startswith("_") or k == "_autoremap"}
    return rest, conditions, dropped


def script_uses(tag: str, texts: dict[str, str]
                ) -> tuple[list[tuple[str, PortModel, str]], list[str]]:
    """The blackboard uses of a node's scripts, and their syntax errors.

    Args:
        tag: The node's element name (for messages).
        texts: Script attribute -> its text.

    Returns:
        ``(entry, port, who)`` per variable (reads first, then writes, as an input or
        output port named after the attribute), and one message per script that does not
        compile.
    """
    uses: list[tuple[str, PortModel, str]] = []
    errors: list[str] = []
    for key, text in texts.items():
        found = script_variables(text)
        if isinstance(found, str):
            errors.append(f"script '{key}' of <{tag}>: {found}")
            continue
        who = f"<{tag}> script '{key}'"
        uses += [(name, PortModel(key, "input", "any"), who) for name in found.reads]
        uses += [(name, PortModel(key, "output", "any"), who) for name in found.writes]
    return uses, errors


def condition_scripts(scripts: dict[str, Any]) -> dict[str, str]:
    """A spec node's pre/post-condition scripts as BT.CPP attributes (name -> text).

    Args:
        scripts: ``NodeSpec.scripts`` (compiled scripts by attribute).

    Returns:
        The condition attributes' texts, in BT.CPP's order.
    """
    return {name: str(scripts[name].text) for name in CONDITION_NAMES
            if name in scripts}
