"""The validated tree: what a tree file means, before any behaviour exists.

The loader turns a YAML document into a :class:`TreeSpec`; the builder turns a
:class:`TreeSpec` into py_trees behaviours; the renderer draws a
:class:`TreeSpec`. Nothing here imports py_trees or ROS.

Node kinds fall in three categories::

    composite   sequence, selector, parallel          -> children (>= 1)
    decorator   one_shot, retry, timeout, inverter... -> exactly one child
    leaf        a registered plugin name              -> params, references
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from enum import Enum
from typing import Any

from sar_framework.engine.diagnostics import SourceLocation
from sar_framework.engine.ports import NO_DEFAULT, PortBinding


@dataclass(frozen=True)
class Declared:
    """A declared entry: a ``blackboard:`` entry, or a subtree's port.

    Attributes:
        name: The entry's name in its scope.
        type: Its type name.
        initial: Its initial value (converted), or :data:`.ports.NO_DEFAULT`.
        description: Free text.
        where: Where it is declared.
        caller_sets: Whether the caller may set it (a ``blackboard:`` entry): a read
            needs no writer in the tree.
    """

    name: str
    type: str
    initial: Any = NO_DEFAULT
    description: str = ""
    where: SourceLocation | None = None
    caller_sets: bool = True


@dataclass
class Entry:
    """One entry of a loaded tree.

    Attributes:
        key: The absolute py_trees key (``/goal``, ``/Follow@0_2/path``).
        type: Its type name (declared, else as first used), ``any`` when unknown.
        initial: Written before the first tick; :data:`.ports.NO_DEFAULT` when none.
        description: Free text from its declaration.
    """

    key: str
    type: str = "any"
    initial: Any = NO_DEFAULT
    description: str = ""

    @property
    def name(self) -> str:
        """The name shown to people: the key without its leading ``/``."""
        return self.key[1:]


class Category(str, Enum):
    """What kind of node a spec describes."""

    COMPOSITE = "composite"
    DECORATOR = "decorator"
    LEAF = "leaf"


@dataclass
class NodeSpec:
    """One node of a validated tree.

    Attributes:
        kind: ``sequence``, ``selector``, ``parallel``, a decorator key such as
            ``one_shot``, or a plugin name such as ``NavigateToPose``.
        category: Composite, decorator or leaf.
        name: The behaviour's name (defaults filled in: a leaf defaults to its plugin name).
        uid: Unique within the tree, stable for one file: the path of child indices from
            the root, e.g. ``"0.1.3"`` (root is ``"0"``). Used to map behaviours and
            statuses back to spec nodes.
        location: Where the node's key stands in its file.
        attrs: Composite/decorator settings (``memory``, ``policy``, ``num_failures``...)
            or, for a leaf, its params with defaults filled in. A reference param's value
            is the referenced ``id`` (string), see ``refs`` for the resolved node.
        children: Child specs (composites: one or more; decorators: exactly one).
        id: The leaf's ``id`` as written, or None.
        refs: For a leaf: reference param name -> the referenced leaf's spec.
        subtree: Name of the subtree this node was inserted from, on the subtree's top node.
        insertion: On the subtree's top node: the insertion's ``ports`` (inner port -> the
            value as written) and ``autoremap``, as the tree file gives them.
        written: The names of the ``attrs`` the tree file sets (the rest are defaults).
        ports: For a leaf (or a BT.CPP node's blackboard ports): its port bindings as
            written (``"{goal}"`` or a converted literal), by port name.
        bindings: For a leaf (or a BT.CPP node's blackboard ports): every declared port's
            resolved binding (absolute key or literal), by port name.
        scripts: The node's compiled scripts (``code``, ``if``, ``_skipIf``...), by attribute.
        script_keys: Every variable its scripts use (``@name`` for the root's) -> the
            absolute key it resolves to in the node's scope.
        use: On the subtree's top node: the insertion (``subtree: {tree: X, _skipIf:
            ...}``) when it has pre/post-conditions; its ``scripts`` and ``script_keys``,
            resolved in the parent's scope, wrap the inserted subtree (BT.CPP's SubTree
            node).
        symbol: A composite's text symbol in diagrams, as its kind declares it ("": worked
            out from the node).
    """

    kind: str
    category: Category
    name: str
    uid: str
    location: SourceLocation
    attrs: dict[str, Any] = field(default_factory=dict)
    children: list[NodeSpec] = field(default_factory=list)
    id: str | None = None
    refs: dict[str, NodeSpec] = field(default_factory=dict)
    subtree: str | None = None
    written: frozenset[str] = frozenset()
    ports: dict[str, Any] = field(default_factory=dict)
    bindings: dict[str, PortBinding] = field(default_factory=dict)
    scripts: dict[str, Any] = field(default_factory=dict)
    script_keys: dict[str, str] = field(default_factory=dict)
    insertion: dict[str, Any] = field(default_factory=dict)
    use: NodeSpec | None = None
    symbol: str = ""

    def walk(self) -> Iterator[NodeSpec]:
        """Yield this node and every descendant, depth first, parents before children."""
        stack = [self]
        while stack:
            node = stack.pop()
            yield node
            stack.extend(reversed(node.children))


@dataclass
class TreeSpec:
    """A validated tree file.

    Attributes:
        name: The tree's ``name``.
        description: The tree's ``description`` (may be empty).
        root: The root node.
        source: The file it came from, as given by the user.
        format: The format version (1).
        plugin_paths: Extra plugin modules/dirs the file named, resolved to absolute paths.
        entries: Every blackboard entry the tree uses, by absolute key (type, initial value).
        declarations: Each scope's ``blackboard:`` section as written (``""``: the main
            tree; else a subtree definition's name): name -> declaration, in file order.
        completion: The file's top-level ``completion`` key ("" when not set).
    """

    name: str
    description: str
    root: NodeSpec
    source: str
    format: int = 1
    plugin_paths: list[str] = field(default_factory=list)
    entries: dict[str, Entry] = field(default_factory=dict)
    declarations: dict[str, dict[str, Declared]] = field(default_factory=dict)
    completion: str = ""

    def nodes(self) -> Iterator[NodeSpec]:
        """Yield every node of the tree, depth first."""
        return self.root.walk()

    def __len__(self) -> int:
        return sum(1 for _ in self.nodes())
