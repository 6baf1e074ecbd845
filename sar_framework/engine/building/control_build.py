"""The builders of BT.CPP's node kinds that need more than their attributes.

Each kind of :mod:`~..nodes.control_kinds` names its builder in its declaration
(``build``): its behaviour class, called with its attributes, or one of the functions
here, called as ``builder(node, children, context)``. The clock-driven kinds read the
build context's ``clock`` (:data:`CLOCK_KEY`: seconds; default ``time.monotonic``): a
runner on ROS time passes ``context={CLOCK_KEY: now}``, so a tree behaves the same at any
simulation speed. The blackboard nodes get a :class:`~..variables.Variables` in which each
port bound to an entry is a variable named like the port, leading to the key validation
resolved in the node's scope (``node.bindings``); a Switch reads its variable and cases
through a :class:`~.port_values.PortValues`, as a leaf reads its ports. The ports a kind
``reads`` are read from their entries by :func:`reading_ports`.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Mapping
from typing import Any

import py_trees

from sar_framework.engine.building.port_values import PortValues
from sar_framework.engine.nodes.control_kinds import SWITCH_CASES
from sar_framework.engine.nodes.controls import conditionals, leaves
from sar_framework.engine.nodes.controls.read_ports import PortReader
from sar_framework.engine.nodes.decorators import queues, updated
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.engine.spec import NodeSpec
from sar_framework.engine.variables import BlackboardVariables

CLOCK_KEY = "clock"
"""The build-context key of the clock (a callable returning seconds)."""


Behaviour = py_trees.behaviour.Behaviour
ControlBuilder = Callable[[NodeSpec, list[Behaviour], Mapping[str, Any]], Behaviour]


def bound_variables(node: NodeSpec, *ports: str) -> BlackboardVariables:
    """A view of py_trees' blackboard for ``node``: each named port bound to an entry.

    Args:
        node: The validated node (its ``bindings`` resolved).
        ports: The ports to include; those bound to a literal or to nothing are left out.

    Returns:
        Variables named like the ports; the ports that write are writable.
    """
    keys = {name: binding.key for name in ports
            if (binding := node.bindings.get(name)) is not None and binding.key is not None}
    writable = [name for name in keys if node.bindings[name].port.direction.writes]
    return BlackboardVariables(node.name, keys, writable)


def is_bound(node: NodeSpec, port: str) -> bool:
    """Whether ``node``'s ``port`` is bound to a blackboard entry (not a literal)."""
    binding = node.bindings.get(port)
    return binding is not None and binding.key is not None


def _literal_text(value: Any) -> str:
    """A literal as BT.CPP's XML would hold it (a YAML list as ``a;b;c``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, list):
        return ";".join(_literal_text(item) for item in value)
    return str(value)


def clock_of(context: Mapping[str, Any]) -> Callable[[], float]:
    """The build context's clock (:data:`CLOCK_KEY`), else ``time.monotonic``."""
    clock = context.get(CLOCK_KEY)
    return clock if callable(clock) else time.monotonic


def switch(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
           ) -> Behaviour:
    """``Switch2`` .. ``Switch6``: the variable and cases read as a leaf reads its ports."""
    names = [f"case_{i}" for i in range(1, SWITCH_CASES[node.kind] + 1)]
    ports = PortValues(node.name, {n: node.bindings[n] for n in ("variable", *names)})
    cases = ["" if is_bound(node, n) else node.bindings[n].value for n in names]
    reads = [n if is_bound(node, n) else None for n in names]
    return conditionals.Switch(node.name, children, cases, "variable",
                               ports,  # type: ignore[arg-type]  # reads only
                               case_variables=reads)


def updated_decorator(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                      ) -> Behaviour:
    """``SkipUnlessUpdated`` or ``WaitValueUpdate``: the class of that name, on ``entry``."""
    cls = getattr(updated, node.kind)
    return cls(node.name, children[0], "entry", bound_variables(node, "entry"))


def loop(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
         ) -> Behaviour:
    """``LoopInt`` .. ``LoopString``: a literal queue, or a shared list's entry."""
    shared = is_bound(node, "queue")
    literal = None if shared else _literal_text(node.bindings["queue"].value)
    return queues.Loop(node.name, children[0], literal, bound_variables(node, "queue", "value"),
                       item=queues.ITEM_TYPES[node.kind],
                       queue_variable="queue" if shared else None,
                       value="value" if is_bound(node, "value") else None,
                       if_empty=node.attrs["if_empty"])


def was_updated(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                ) -> Behaviour:
    """``WasEntryUpdated`` on its ``entry``."""
    return updated.WasEntryUpdated(node.name, "entry", bound_variables(node, "entry"))


def set_blackboard(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                   ) -> Behaviour:
    """``SetBlackboard``: a literal or an entry's value copied to ``output_key``."""
    value = "{value}" if is_bound(node, "value") else node.bindings["value"].value
    variables = bound_variables(node, "value", "output_key")
    return leaves.SetBlackboard(node.name, value, "output_key", variables)


def unset_blackboard(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                     ) -> Behaviour:
    """``UnsetBlackboard`` of ``key``."""
    return leaves.UnsetBlackboard(node.name, "key", bound_variables(node, "key"))


def reading_ports(base: ControlBuilder, ports: tuple[str, ...], each_tick: bool,
                  keep_default: bool = False) -> ControlBuilder:
    """``base``, reading those of ``ports`` bound to entries when BT.CPP reads them.

    Such a port is read from its entry (the node's
    :class:`~.controls.read_ports.PortReader`) on every tick (``each_tick``) or when the
    node starts, not passed as a literal.

    Args:
        base: Builds the node from its attributes.
        ports: The integer (or boolean) ports BT.CPP reads with ``getInput``.
        each_tick: Read on every tick, else when the node starts.
        keep_default: An entry without a value leaves the port at its default (BT.CPP
            ignores that failed ``getInput``), instead of stopping the tick as BT.CPP's
            "Missing parameter" does.
    """

    def build(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
              ) -> Behaviour:
        attrs = dict(node.attrs)
        bound = [port for port in ports if is_bound(node, port)]
        for port in ports:
            binding = node.bindings.get(port)  # a literal converted ('450' -> 450)
            if port in bound:
                default = binding.port.default  # type: ignore[union-attr]
                attrs[port] = 0 if default is NO_DEFAULT else default  # until read
            elif binding is not None and binding.value is not NO_DEFAULT:
                attrs[port] = binding.value
        behaviour = base(dataclasses.replace(node, attrs=attrs), children, context)
        if bound:
            defaults = ({port: node.bindings[port].port.default for port in bound}
                        if keep_default else None)
            behaviour.port_reader = PortReader(  # type: ignore[attr-defined]
                node.name, bound_variables(node, *bound),
                {port: node.bindings[port].port.type for port in bound}, each_tick, defaults)
        return behaviour

    return build
