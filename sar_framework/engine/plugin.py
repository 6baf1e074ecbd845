"""Leaf plugins: a py_trees behaviour plus one declaration of its params.

A plugin is an ordinary :class:`py_trees.behaviour.Behaviour` subclass marked
with :func:`leaf`. The declaration (params, blackboard ports: :mod:`.ports`) is the
single source for validation, the JSON Schema fragment, ``sar-tree plugins`` and the
constructor's kwargs::

    @leaf(
        params=[
            Param("timeout_s", float, default=10.0, minimum=0.0,
                  description="Give up after this many seconds."),
            Param("detector", ref="DetectSurvivor",
                  description="id of the DetectSurvivor leaf to read."),
        ],
        context=["zone_manager"],
    )
    class IsSurvivorDetected(py_trees.behaviour.Behaviour):
        def __init__(self, name, *, timeout_s, detector, zone_manager): ...

The loader constructs it as ``cls(name=..., <params>..., <context objects>...)``.
A reference param receives the referenced behaviour instance; a context key
receives the object the caller supplied to ``load_tree(context=...)``. A ROS
node, when the plugin needs one, arrives the py_trees_ros way, in
``setup(node=...)``, so declaring and validating a plugin never needs ROS.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

from sar_framework.engine.ports import Port

#: The attribute :func:`leaf` sets on a class; discovery looks for it.
PLUGIN_ATTRIBUTE = "__sar_plugin__"


class _Required:
    """Sentinel type for a param without a default."""

    def __repr__(self) -> str:
        return "REQUIRED"


#: Default of a param that the tree must give.
REQUIRED: Any = _Required()

#: Python types a param may have, with the JSON Schema type each maps to.
PARAM_TYPES: dict[type, str] = {str: "string", int: "integer", float: "number", bool: "boolean"}


@dataclass(frozen=True)
class Param:
    """Declaration of one plugin parameter.

    Attributes:
        name: The key in the tree file and the constructor kwarg.
        type: One of ``str``, ``int``, ``float``, ``bool``. Ignored for references.
        default: The value when the tree omits the key; :data:`REQUIRED` if it must be given.
        description: One line for docs, schema and editor hover text.
        minimum: Inclusive lower bound for numbers.
        maximum: Inclusive upper bound for numbers.
        exclusive_minimum: Exclusive lower bound for numbers (e.g. a rate > 0).
        enum: The allowed values, when the set is closed.
        ref: For a reference param: the plugin name the referenced leaf must have.
            The value in the tree is that leaf's ``id``.
    """

    name: str
    type: type = str
    default: Any = REQUIRED
    description: str = ""
    minimum: float | None = None
    maximum: float | None = None
    exclusive_minimum: float | None = None
    enum: tuple[Any, ...] | None = None
    ref: str | None = None

    def __post_init__(self) -> None:
        if self.ref is None and self.type not in PARAM_TYPES:
            raise TypeError(f"param {self.name!r}: unsupported type {self.type!r}")
        if self.ref is not None and self.default is not REQUIRED and self.default is not None:
            raise TypeError(f"param {self.name!r}: a reference can only default to None")

    @property
    def required(self) -> bool:
        """Whether the tree must give this param."""
        return self.default is REQUIRED

    @property
    def is_reference(self) -> bool:
        """Whether the value names another leaf's ``id``."""
        return self.ref is not None


@dataclass(frozen=True)
class PluginSpec:
    """Everything the engine knows about one leaf plugin.

    Attributes:
        name: The node kind in a tree file (``NavigateToZone``).
        cls: The behaviour class.
        description: First paragraph of the class docstring unless given.
        params: The declared params, in declaration order.
        context: Names of caller-supplied objects the constructor needs.
        ports: The declared ports (:mod:`.ports`), in declaration order; a leaf with
            ports is constructed with ``ports=PortValues(...)``.
        source: Where it was found (module, file or entry point); set by the registry.
    """

    name: str
    cls: type
    description: str
    params: tuple[Param, ...] = ()
    context: tuple[str, ...] = ()
    source: str = field(default="", compare=False)
    ports: tuple[Port, ...] = ()

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
) -> Callable[[_T], _T]:
    """Mark a behaviour class as a leaf plugin.

    Args:
        name: The node kind in tree files; defaults to the class name.
        params: The params the tree may set.
        context: Names of shared objects the caller must supply (e.g. ``zone_manager``).
        description: Defaults to the first paragraph of the class docstring.
        ports: The blackboard ports (:func:`.ports.InputPort`, ``OutputPort``,
            ``BidirectionalPort``).

    Returns:
        A class decorator that records a :class:`PluginSpec` on the class and returns it.

    Raises:
        TypeError: On a declaration that cannot work (duplicate or reserved param or port
            names, a port that is not a :class:`~.ports.Port`).
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
        doc = (cls.__doc__ or "").strip().split("\n\n")[0]
        text = description if description is not None else " ".join(doc.split())
        spec = PluginSpec(
            name=name or cls.__name__,
            cls=cls,
            description=text,
            params=tuple(params),
            context=tuple(context),
            ports=tuple(ports),
        )
        setattr(cls, PLUGIN_ATTRIBUTE, spec)
        return cls

    return mark
