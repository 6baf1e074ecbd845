"""Building the script nodes and the pre/post-condition wrapper from validated specs.

``Script``, ``ScriptCondition`` and ``Precondition`` become the behaviours of
:mod:`.script_nodes`; a node with any of ``_failureIf _successIf _skipIf _while
_onSuccess _onFailure _onHalted _post`` is wrapped in a
:class:`~.script_nodes.PrePostConditions`. The scripts of one node share one
:class:`~.variables.BlackboardVariables`: each variable under the absolute key validation
resolved in the node's scope. The script language is imported only when a tree has a
script.
"""

from __future__ import annotations

from py_trees.behaviour import Behaviour

from sar_framework.engine.spec import NodeSpec
from sar_framework.engine.variables import BlackboardVariables

#: The node kinds built here rather than by the plugin or py_trees builders.
SCRIPTED = frozenset({"Script", "ScriptCondition", "Precondition"})


def variables(node: NodeSpec) -> BlackboardVariables:
    """The variables of a node's scripts, on py_trees' blackboard."""
    writes = {name for script in node.scripts.values() for name in script.writes}
    return BlackboardVariables(node.name, node.script_keys, writes)


def build_scripted(node: NodeSpec, children: list[Behaviour]) -> Behaviour:
    """Build a ``Script``, ``ScriptCondition`` or ``Precondition`` node."""
    from sar_framework.engine.nodes import script_nodes

    if node.kind == "Precondition":
        return script_nodes.Precondition(
            node.name, children[0], node.scripts["if"], variables(node),
            script_nodes.ElseStatus(node.attrs.get("else", "FAILURE")))
    cls = script_nodes.Script if node.kind == "Script" else script_nodes.ScriptCondition
    return cls(node.name, node.scripts["code"], variables(node))


def with_conditions(node: NodeSpec, behaviour: Behaviour) -> Behaviour:
    """Wrap ``behaviour`` in its pre/post-condition scripts (itself when it has none)."""
    from sar_framework.engine.nodes.script_nodes import ATTRIBUTES, PrePostConditions

    scripts = {ATTRIBUTES[a]: s for a, s in node.scripts.items() if a in ATTRIBUTES}
    if not scripts:
        return behaviour
    return PrePostConditions(node.name, behaviour, variables(node), **scripts)
