"""Build the behaviours of BT.CPP's node kinds (:mod:`.control_kinds`).

One builder per kind, called as ``builder(node, children, context)``. The clock-driven
ones, and every ``timeout`` (:class:`ClockTimeout`), read the build context's ``clock``
(:data:`CLOCK_KEY`: seconds; default ``time.monotonic``): a runner on ROS time passes
``context={CLOCK_KEY: now}``, so a tree behaves the same at any simulation speed. The
blackboard nodes get a :class:`~..variables.Variables` in which each port bound to an
entry is a variable named like the port, leading to the key validation resolved in the
node's scope (``node.bindings``); a Switch reads its variable and cases through a
:class:`~.port_values.PortValues`, as a leaf reads its ports.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Mapping
from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine.building.port_values import PortValues
from sar_framework.engine.nodes.control_kinds import CONTROL_KINDS, READ_PORTS, SWITCH_CASES
from sar_framework.engine.nodes.controls import conditionals, leaves, parallels, sequences
from sar_framework.engine.nodes.controls.read_ports import PortReader
from sar_framework.engine.nodes.decorators import converters, loops, queues, timing, updated
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.engine.spec import Category, NodeSpec
from sar_framework.engine.variables import BlackboardVariables

CLOCK_KEY = "clock"
"""The build-context key of the clock (a callable returning seconds)."""


class ClockTimeout(py_trees.decorators.Timeout):
    """py_trees' ``Timeout``, with ``duration`` measured on ``clock``.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        duration: Seconds on ``clock``.
        clock: Returns the current time in seconds.
    """

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, duration: float,
                 clock: Callable[[], float]) -> None:
        super().__init__(name=name, child=child, duration=duration)
        self.clock = clock
        self.finish_time = 0.0

    def initialise(self) -> None:
        """Start the bound on this activation."""
        self.finish_time = self.clock() + self.duration
        self.feedback_message = ""

    def update(self) -> Status:
        """FAILURE (halting the child) once the bound passed while the child runs.

        Returns:
            FAILURE on timeout, else the child's status.
        """
        if self.decorated.status == Status.RUNNING and self.clock() > self.finish_time:
            self.feedback_message = "timed out"
            self.decorated.stop(Status.INVALID)
            return Status.FAILURE
        if self.decorated.status == Status.RUNNING:
            self.feedback_message = f"{self.finish_time - self.clock():.2f} s left"
        else:
            self.feedback_message = "child finished before the timeout"
        return self.decorated.status


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


def _plain(cls: type) -> ControlBuilder:
    """A control or decorator whose attributes (other than name) are its keyword args."""

    def build(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
              ) -> Behaviour:
        if node.category is Category.DECORATOR:
            return cls(node.name, children[0], **node.attrs)
        if node.category is Category.COMPOSITE:
            return cls(node.name, children, **node.attrs)
        return cls(node.name, **node.attrs)

    return build


def _clocked(cls: type) -> ControlBuilder:
    """A decorator or leaf that also takes the build context's clock."""

    def build(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
              ) -> Behaviour:
        head = [children[0]] if children else []
        return cls(node.name, *head, **node.attrs, clock=clock_of(context))

    return build


def _switch(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
            ) -> Behaviour:
    names = [f"case_{i}" for i in range(1, SWITCH_CASES[node.kind] + 1)]
    ports = PortValues(node.name, {n: node.bindings[n] for n in ("variable", *names)})
    cases = ["" if is_bound(node, n) else node.bindings[n].value for n in names]
    reads = [n if is_bound(node, n) else None for n in names]
    return conditionals.Switch(node.name, children, cases, "variable",
                               ports,  # type: ignore[arg-type]  # reads only
                               case_variables=reads)


def _updated(cls: type) -> ControlBuilder:
    def build(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
              ) -> Behaviour:
        return cls(node.name, children[0], "entry", bound_variables(node, "entry"))

    return build


def _loop(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
          ) -> Behaviour:
    shared = is_bound(node, "queue")
    literal = None if shared else _literal_text(node.bindings["queue"].value)
    return queues.Loop(node.name, children[0], literal, bound_variables(node, "queue", "value"),
                       item=queues.ITEM_TYPES[node.kind],
                       queue_variable="queue" if shared else None,
                       value="value" if is_bound(node, "value") else None,
                       if_empty=node.attrs["if_empty"])


def _was_updated(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                 ) -> Behaviour:
    return updated.WasEntryUpdated(node.name, "entry", bound_variables(node, "entry"))


def _set_blackboard(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                    ) -> Behaviour:
    value = "{value}" if is_bound(node, "value") else node.bindings["value"].value
    variables = bound_variables(node, "value", "output_key")
    return leaves.SetBlackboard(node.name, value, "output_key", variables)


def _unset_blackboard(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                      ) -> Behaviour:
    return leaves.UnsetBlackboard(node.name, "key", bound_variables(node, "key"))


#: Kinds whose port, when its entry has no value, keeps its default (BT.CPP ignores the
#: failed ``getInput``); the others stop the tick, as BT.CPP throws "Missing parameter".
_DEFAULT_WHEN_UNSET = frozenset({"RunOnce"})


def reading_ports(base: ControlBuilder, ports: tuple[str, ...], each_tick: bool
                  ) -> ControlBuilder:
    """``base``, reading those of ``ports`` bound to entries when BT.CPP reads them.

    Such a port is read from its entry (the node's
    :class:`~.controls.read_ports.PortReader`) on every tick (``each_tick``) or when the
    node starts, not passed as a literal.

    Args:
        base: Builds the node from its attributes.
        ports: The integer (or boolean) ports BT.CPP reads with ``getInput``.
        each_tick: Read on every tick, else when the node starts.
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
                        if node.kind in _DEFAULT_WHEN_UNSET else None)
            behaviour.port_reader = PortReader(  # type: ignore[attr-defined]
                node.name, bound_variables(node, *bound),
                {port: node.bindings[port].port.type for port in bound}, each_tick, defaults)
        return behaviour

    return build


def _each(wrap: Callable[[type], ControlBuilder], module: Any, *kinds: str
          ) -> dict[str, ControlBuilder]:
    """``kinds`` built by ``wrap`` of the class of that name in ``module``."""
    return {kind: wrap(getattr(module, kind)) for kind in kinds}


_BUILDERS: dict[str, ControlBuilder] = {
    **_each(_plain, sequences, "Sequence", "SequenceWithMemory", "ReactiveSequence",
            "AsyncSequence", "AsyncFallback", "Fallback", "ReactiveFallback"),
    **_each(_plain, parallels, "Parallel", "ParallelAll"),
    **_each(_plain, conditionals, "IfThenElse", "WhileDoElse"),
    **{key: _switch for key in SWITCH_CASES},
    **_each(_plain, converters, "Inverter", "ForceSuccess", "ForceFailure",
            "KeepRunningUntilFailure"),
    **_each(_plain, loops, "Repeat", "RetryUntilSuccessful", "RunOnce"),
    **_each(_clocked, timing, "Delay", "Timeout"),
    **{key: _loop for key in queues.ITEM_TYPES},
    "WasEntryUpdated": _was_updated,
    **_each(_updated, updated, "SkipUnlessUpdated", "WaitValueUpdate"),
    **_each(_plain, leaves, "AlwaysSuccess", "AlwaysFailure"),
    "Sleep": _clocked(leaves.Sleep),
    "SetBlackboard": _set_blackboard,
    "UnsetBlackboard": _unset_blackboard,
}
#: Each kind's builder; the kinds with ports BT.CPP reads (READ_PORTS) read them from entries.
CONTROL_BUILDERS: dict[str, ControlBuilder] = {
    kind: reading_ports(build, *READ_PORTS[kind]) if kind in READ_PORTS else build
    for kind, build in _BUILDERS.items()}
assert set(CONTROL_BUILDERS) == {k.key for k in CONTROL_KINDS}, "a kind without a builder"
