"""Leaf plugins: a py_trees behaviour plus one declaration of its params.

A plugin is an ordinary :class:`py_trees.behaviour.Behaviour` subclass marked
with :func:`leaf`. The declaration (params: :class:`~sar_framework.engine.param.Param`, the
type every node parameter is declared with too; blackboard ports: :mod:`.ports`) is the
single source for validation, the JSON Schema fragment, ``sar-tree plugins`` and the
constructor's kwargs::

    @leaf(
        params=[
            Param("timeout_s", float, default=10.0, minimum=0.0,
                  description="Give up after this many seconds."),
            Param("scanner", ref="ScanShelf",
                  description="id of the ScanShelf leaf to read."),
        ],
        context=["inventory"],
    )
    class IsShelfScanned(py_trees.behaviour.Behaviour):
        def __init__(self, name, *, timeout_s, scanner, inventory): ...

The loader constructs it as ``cls(name=..., <params>..., <context objects>...)``.
A reference param receives the referenced behaviour instance; a context key
receives the object the caller supplied to ``load_tree(context=...)``. A ROS
node, when the plugin needs one, arrives the py_trees_ros way, in
``setup(node=...)``, so declaring and validating a plugin never needs ROS.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TypeVar

from sar_framework.engine.param import PARAM_TYPES, REQUIRED, Param
from sar_framework.engine.ports import Port

__all__ = ["PARAM_TYPES", "PLUGIN_ATTRIBUTE", "REQUIRED", "Param", "PluginSpec",
           "constructor_problems", "leaf"]

#: The attribute :func:`leaf` sets on a class; discovery looks for it.
PLUGIN_ATTRIBUTE = "__sar_plugin__"


@dataclass(frozen=True)
class PluginSpec:
    """Everything the engine knows about one leaf plugin.

    Attributes:
        name: The node kind in a tree file (``NavigateToPose``).
        cls: The behaviour class.
        description: First paragraph of the class docstring unless given.
        params: The declared params, in declaration order.
        context: Names of caller-supplied objects the constructor needs.
        ports: The declared ports (:mod:`.ports`), in declaration order; a leaf with
            ports is constructed with ``ports=PortValues(...)``.
        source: Where it was found (module, file or entry point); set by the registry.
        condition: Whether it is a condition (BT.CPP's ``Condition``: it answers in the tick,
            never RUNNING) rather than an action; palettes and exports say which.
        moved: Params it no longer takes: ``(param, what to write now)`` each, the message
            validation gives a tree that still sets one.
    """

    name: str
    cls: type
    description: str
    params: tuple[Param, ...] = ()
    context: tuple[str, ...] = ()
    source: str = field(default="", compare=False)
    ports: tuple[Port, ...] = ()
    condition: bool = False
    moved: tuple[tuple[str, str], ...] = ()

    def param(self, name: str) -> Param | None:
        """Return the declared param called ``name``, or None."""
        for p in self.params:
            if p.name == name:
                return p
        return None

    def port(self, name: str) -> Port | None:
        """Return the declared port called ``name``, or None."""
        for p in self.ports:
            if p.name == name:
                return p
        return None


_T = TypeVar("_T", bound=type)


def leaf(
    name: str | None = None,
    *,
    params: Sequence[Param] = (),
    context: Sequence[str] = (),
    description: str | None = None,
    ports: Sequence[Port] = (),
    condition: bool = False,
    moved: Mapping[str, str] | None = None,
) -> Callable[[_T], _T]:
    """Mark a behaviour class as a leaf plugin.

    Args:
        name: The node kind in tree files; defaults to the class name.
        params: The params the tree may set.
        context: Names of shared objects the caller must supply (e.g. an app's ``inventory``).
        description: Defaults to the first paragraph of the class docstring.
        ports: The blackboard ports (:func:`.ports.InputPort`, ``OutputPort``,
            ``BidirectionalPort``).
        condition: A condition (answers in the tick), not an action.
        moved: Params it no longer takes -> what to write now (validation's message).

    Returns:
        A class decorator that records a :class:`PluginSpec` on the class and returns it.

    Raises:
        TypeError: On a declaration that cannot work (duplicate or reserved param or port
            names, a port that is not a :class:`~.ports.Port`, or a param type a tree file
            cannot give: lists are for node parameters).
    """
    reserved = {"name", "id", "ports"}

    def mark(cls: _T) -> _T:
        seen: set[str] = set()
        for p in (*params, *ports):
            if not isinstance(p, (Param, Port)):
                raise TypeError(f"{cls.__name__}: {p!r} is not a Param or a Port")
            what = "param" if isinstance(p, Param) else "port"
            if p.name in reserved or p.name in seen or p.name in context:
                raise TypeError(f"{cls.__name__}: {what} name {p.name!r} is reserved or repeated")
            seen.add(p.name)
            if isinstance(p, Param) and p.ref is None and p.type not in PARAM_TYPES:
                raise TypeError(f"{cls.__name__}: param {p.name!r}: a leaf param is a str, "
                                "int, float or bool")
        doc = (cls.__doc__ or "").strip().split("\n\n")[0]
        text = description if description is not None else " ".join(doc.split())
        spec = PluginSpec(
            name=name or cls.__name__,
            cls=cls,
            description=text,
            params=tuple(params),
            context=tuple(context),
            ports=tuple(ports),
            condition=condition,
            moved=tuple((moved or {}).items()),
        )
        setattr(cls, PLUGIN_ATTRIBUTE, spec)
        return cls

    return mark


def constructor_problems(spec: PluginSpec) -> list[str]:
    """What a leaf's ``__init__`` says against its declaration: defaults live in ``@leaf`` only.

    Each declared param, context object and ``ports`` (when the leaf has ports) must be a
    keyword argument of ``__init__`` without a default (or reach a ``**kwargs``): the loader
    always passes the declared value, so a default there is a second copy that can drift.

    Args:
        spec: The leaf's declaration.

    Returns:
        One sentence per problem; empty when the constructor agrees.
    """
    try:
        parameters = inspect.signature(spec.cls.__init__).parameters
    except (TypeError, ValueError):
        return []
    takes_any = any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values())
    names = [p.name for p in spec.params] + list(spec.context) + (["ports"] if spec.ports else [])
    problems = []
    for name in names:
        parameter = parameters.get(name)
        if parameter is None:
            if not takes_any:
                problems.append(f"__init__ does not take the declared {name!r}")
        elif parameter.default is not inspect.Parameter.empty:
            problems.append(f"__init__ repeats a default for {name!r} ({parameter.default!r}); "
                            "the @leaf declaration is where defaults live")
    return problems
