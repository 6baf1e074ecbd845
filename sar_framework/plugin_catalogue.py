"""What ``sar-tree plugins`` says about each registered plugin, for people and as JSON."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from sar_framework.engine.registry import Registry


def param_text(param: Any) -> str:
    """One line for a parameter: name, type, default or (required), bounds, description.

    Args:
        param: A :class:`~sar_framework.engine.plugin.Param`.
    """
    from sar_framework.engine.plugin import REQUIRED

    kind = f"ref {param.ref}" if param.ref is not None else param.type.__name__
    parts = [f"{param.name}: {kind}"]
    parts.append("(required)" if param.default is REQUIRED else f"= {param.default!r}")
    bounds = []
    if param.minimum is not None:
        bounds.append(f">= {param.minimum}")
    if param.exclusive_minimum is not None:
        bounds.append(f"> {param.exclusive_minimum}")
    if param.maximum is not None:
        bounds.append(f"<= {param.maximum}")
    if param.enum is not None:
        bounds.append("one of " + ", ".join(str(v) for v in param.enum))
    if bounds:
        parts.append(f"[{'; '.join(bounds)}]")
    text = " ".join(parts)
    return f"{text}  {param.description}" if param.description else text


def port_text(port: Any) -> str:
    """One line for a port: name, direction, type, default or (required), description.

    Args:
        port: A :class:`~sar_framework.engine.ports.Port`.
    """
    from sar_framework.engine.ports import NO_DEFAULT

    parts = [f"{port.name}: {port.direction.value} port {port.type}"]
    if port.default is not NO_DEFAULT:
        parts.append(f"= {port.default!r}")
    elif port.required:
        parts.append("(required)")
    text = " ".join(parts)
    return f"{text}  {port.description}" if port.description else text


def port_info(port: Any) -> dict[str, Any]:
    """Describe a port as JSON-ready data.

    Args:
        port: A :class:`~sar_framework.engine.ports.Port`.
    """
    from sar_framework.engine.ports import NO_DEFAULT

    entry: dict[str, Any] = {"name": port.name, "direction": port.direction.value,
                             "type": port.type, "required": port.required,
                             "description": port.description}
    if port.default is not NO_DEFAULT:
        entry["default"] = port.default
    return entry


def plugin_info(plugin: Any) -> dict[str, Any]:
    """Describe a plugin as JSON-ready data (``sar-tree plugins --json``).

    Args:
        plugin: A :class:`~sar_framework.engine.plugin.PluginSpec`.

    Returns:
        Name, source, description, params, ports and context keys.
    """
    from sar_framework.engine.plugin import REQUIRED

    params = []
    for p in plugin.params:
        entry: dict[str, Any] = {
            "name": p.name,
            "type": "reference" if p.ref is not None else p.type.__name__,
            "required": p.default is REQUIRED,
            "description": p.description,
        }
        if p.default is not REQUIRED:
            entry["default"] = p.default
        for key in ("minimum", "maximum", "exclusive_minimum", "ref"):
            if getattr(p, key) is not None:
                entry[key] = getattr(p, key)
        if p.enum is not None:
            entry["enum"] = list(p.enum)
        params.append(entry)
    return {
        "name": plugin.name,
        "source": plugin.source,
        "class": f"{plugin.cls.__module__}.{plugin.cls.__qualname__}",
        "description": plugin.description,
        "params": params,
        "ports": [port_info(p) for p in plugin.ports],
        "context": list(plugin.context),
    }


def kind_lines(registry: Registry | None = None) -> list[str]:
    """What ``sar-tree plugins --kinds`` prints: every node kind that is not a leaf plugin.

    py_trees' composites and decorators (snake_case keys), the script nodes, and
    BT.CPP's and Nav2's controls, decorators and built-in leaves, each with its category,
    its description, how it ticks unlike the BT.CPP node it is exported as (a py_trees
    kind's ``differences``) and its attributes (ports as ports; children and the pre- and
    post-conditions left out), as their declarations give them; then the controls and
    decorators ``registry``'s plugins add.
    """
    from sar_framework.engine.nodes.node_kinds import KINDS

    lines = []
    added = {k.name: k.kind for k in registry.kind_plugins()} if registry is not None else {}
    for key, kind in (*sorted(KINDS.items()), *sorted(added.items())):
        lines.append(f"{key}  [{kind.category.value}]")
        lines.append(f"    {kind.description}")
        if kind.differences:
            lines.append(f"    Unlike BT.CPP: {kind.differences}")
        for attr in kind.settings():
            if attr.port is not None:
                lines.append(f"    - {port_text(attr.port)}")
                continue
            parts = [f"{attr.name}: {attr.type.value}",
                     "(required)" if attr.required else f"= {attr.default!r}"]
            if attr.enum is not None:
                parts.append("[one of " + ", ".join(str(v) for v in attr.enum) + "]")
            lines.append(f"    - {' '.join(parts)}  {attr.description}")
    return lines
