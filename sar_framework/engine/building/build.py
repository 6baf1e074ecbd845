"""TreeSpec -> plain py_trees behaviours, plus a ``uid -> behaviour`` map.

The builder creates exactly the objects a hand-written py_trees tree would hold:
composites, decorators and the plugin classes themselves, with no wrapper behaviour in
between, so a loaded tree ticks as fast as a hand-built one. A node of a declared kind
(composite, decorator, BT.CPP leaf; built-in or a plugin's) is built by the builder its
declaration names (:mod:`.kind_builders`). A leaf plugin is constructed as
``cls(name=..., **params, **context_objects)``; a reference param receives the referenced
leaf's behaviour, which is built first (validation has ruled out reference cycles). A leaf
that declares ports also receives ``ports=PortValues(...)`` (:mod:`.port_values`), and
entries with an initial value are written to py_trees' blackboard before the tree is
returned. Script nodes and the pre/post-condition wrapper (:mod:`..nodes.script_nodes`)
share one :class:`~..variables.BlackboardVariables` per node.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Mapping
from typing import Any, Protocol

import py_trees

from sar_framework.engine.building.kind_builders import KindBuilder, builder_of
from sar_framework.engine.building.port_values import PortValues, write_initial
from sar_framework.engine.diagnostics import Diagnostic, TreeLoadError
from sar_framework.engine.nodes.node_kinds import KINDS
from sar_framework.engine.plugin import PluginSpec
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.engine.registry import Registry
from sar_framework.engine.spec import NodeSpec, TreeSpec
from sar_framework.engine.variables import BlackboardVariables

Behaviour = py_trees.behaviour.Behaviour


def variables(node: NodeSpec) -> BlackboardVariables:
    """The variables of a node's scripts, on py_trees' blackboard."""
    writes = {name for script in node.scripts.values() for name in script.writes}
    return BlackboardVariables(node.name, node.script_keys, writes)


def build_scripted(node: NodeSpec, children: list[Behaviour], context: Mapping[str, Any]
                   ) -> Behaviour:
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


class _LeafPlan:
    """How to call one plugin's constructor (worked out once per plugin)."""

    __slots__ = ("cls", "context", "name", "plain", "ports", "refs")

    def __init__(self, plugin: PluginSpec) -> None:
        self.name = plugin.name
        self.cls = plugin.cls
        self.refs = tuple(p.name for p in plugin.params if p.ref is not None)
        self.context = plugin.context
        self.ports = bool(plugin.ports)
        # Constructed from the spec's attrs alone (the common case, done in one step).
        self.plain = not self.refs and not self.context and not self.ports


def _missing_context(node: NodeSpec, plan: _LeafPlan, key: str) -> Diagnostic:
    return Diagnostic(
        node.location,
        f"plugin '{plan.name}' needs the context object '{key}': "
        f"pass load_tree(..., context={{'{key}': ...}})",
    )


class Adopter(Protocol):
    """Hands the builder behaviours that already exist (a hot swap's kept nodes)."""

    def top(self, node: NodeSpec, make: Callable[[NodeSpec], Behaviour | None]
            ) -> Behaviour | None:
        """The behaviour to insert for ``node`` (wrappers included), or None to build it."""

    def leaf(self, node: NodeSpec) -> Behaviour | None:
        """The existing leaf behaviour a reference to ``node`` receives, or None."""


def build(
    spec: TreeSpec, registry: Registry, context: Mapping[str, Any] | None = None, *,
    adopter: Adopter | None = None, keep_entries: Collection[str] = (),
) -> tuple[Behaviour, dict[str, Behaviour]]:
    """Build the behaviours of a validated tree.

    Args:
        spec: The validated tree.
        registry: The registry it was validated against (for the plugin classes).
        context: Shared objects plugins declared they need, by name.
        adopter: Existing behaviours to insert instead of building (see
            :mod:`.hot_swap`); the map returned holds only what was built.
        keep_entries: Blackboard keys whose initial values are not written (they hold
            a running mission's values).

    Returns:
        The root behaviour and the ``NodeSpec.uid -> behaviour`` map (a node with
        pre/post-conditions maps to their wrapper; its ``decorated`` is the node).

    Raises:
        TreeLoadError: Context objects are missing (one diagnostic per leaf and key),
            or plugin constructors raised.
    """
    builder = _Builder(registry, context if context is not None else {}, adopter)
    root = builder.make(spec.root)
    if builder.problems or root is None:
        raise TreeLoadError(builder.problems)
    write_initial({k: e.initial for k, e in spec.entries.items()
                   if e.initial is not NO_DEFAULT and k not in keep_entries})
    return root, {**builder.built, **builder.wrapped}


class _Builder:
    """One build: behaviours made so far, per-plugin plans, problems."""

    def __init__(self, registry: Registry, context: Mapping[str, Any],
                 adopter: Adopter | None = None) -> None:
        self.registry = registry
        self.context = context
        self.adopter = adopter
        self.plans: dict[str, _LeafPlan] = {}
        self.built: dict[str, Behaviour] = {}
        self.failed: set[str] = set()  # leaves already reported: a reference must not retry
        self.problems: list[Diagnostic] = []
        self.wrapped: dict[str, Behaviour] = {}  # uid -> its pre/post-condition wrapper

    def leaf(self, node: NodeSpec) -> Behaviour | None:
        done = self.built.get(node.uid)
        if done is not None:
            return done
        if node.uid in self.failed:
            return None
        if self.adopter is not None:
            done = self.adopter.leaf(node)
            if done is not None:
                self.built[node.uid] = done
                return done
        behaviour = self._construct(node)
        if behaviour is None:
            self.failed.add(node.uid)
        else:
            self.built[node.uid] = behaviour
        return behaviour

    def _construct(self, node: NodeSpec) -> Behaviour | None:
        plan = self.plans.get(node.kind)
        if plan is None:
            plugin = self.registry.get(node.kind)
            if plugin is None:  # validation guarantees it; a stale registry does not
                self.problems.append(Diagnostic(node.location, f"unknown plugin '{node.kind}'"))
                return None
            plan = self.plans[node.kind] = _LeafPlan(plugin)
        kwargs = node.attrs
        if plan.refs or plan.context or plan.ports:
            kwargs = dict(kwargs)
            if plan.ports:
                kwargs["ports"] = PortValues(node.name, node.bindings)
            for name in plan.refs:
                target = node.refs.get(name)
                if target is not None:
                    kwargs[name] = self.leaf(target)
            for key in plan.context:
                if key in self.context:
                    kwargs[key] = self.context[key]
                else:
                    self.problems.append(_missing_context(node, plan, key))
            if self.problems:
                return None
        try:
            behaviour = plan.cls(name=node.name, **kwargs)
        except Exception as exc:
            self._cannot_construct(node, exc)
            return None
        return behaviour

    def _cannot_construct(self, node: NodeSpec, exc: Exception) -> None:
        self.problems.append(
            Diagnostic(
                node.location,
                f"cannot construct {node.kind} '{node.name}': {type(exc).__name__}: {exc}",
            )
        )

    def make(self, node: NodeSpec) -> Behaviour | None:
        """Build ``node`` and its children; wrap it in its pre/post-conditions, if any."""
        if self.adopter is not None:
            adopted = self.adopter.top(node, self.make)
            if adopted is not None:
                return adopted
        behaviour = self.make_node(node)
        if behaviour is None or not node.scripts:
            return self.inserted(node, behaviour)
        wrapped = with_conditions(node, behaviour)
        if wrapped is not behaviour:
            self.wrapped[node.uid] = wrapped
        return self.inserted(node, wrapped)

    def inserted(self, node: NodeSpec, behaviour: Behaviour | None) -> Behaviour | None:
        """Wrap a subtree's top node in its insertion's pre/post-conditions, if any."""
        use = node.use if behaviour is not None else None
        while use is not None:  # innermost insertion first
            behaviour = with_conditions(use, behaviour)  # type: ignore[arg-type]
            use = use.use
        return behaviour

    def make_node(self, node: NodeSpec) -> Behaviour | None:
        """Build ``node`` and its children, without its pre/post-conditions.

        A node kind (built-in or a plugin's) is built as its declaration says; a leaf
        plugin is constructed from its params.
        """
        kind = KINDS.get(node.kind) or self.registry.kind(node.kind)
        if kind is not None:
            return self.control(node, builder_of(kind))
        plan = self.plans.get(node.kind)
        if plan is None or not plan.plain:
            return self.leaf(node)
        # A plain leaf: nothing can have built it before (only references do that).
        attrs = node.attrs
        try:
            behaviour = plan.cls(name=node.name, **attrs) if attrs else plan.cls(name=node.name)
        except Exception as exc:
            self._cannot_construct(node, exc)
            self.failed.add(node.uid)
            return None
        self.built[node.uid] = behaviour
        return behaviour

    def control(self, node: NodeSpec, build: KindBuilder) -> Behaviour | None:
        """Build a node of a declared kind: its children, then itself."""
        children = [self.make(child) for child in node.children]
        if self.problems:
            return None
        try:
            behaviour = build(node, children, self.context)
        except Exception as exc:
            self._cannot_construct(node, exc)
            return None
        self.built[node.uid] = behaviour
        return behaviour
