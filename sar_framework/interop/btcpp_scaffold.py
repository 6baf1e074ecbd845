"""Scaffold leaf plugins for the BT.CPP nodes an imported file uses and nobody registered.

``sar-tree import FILE --scaffold DIR`` writes one module, ``DIR/<file stem>_leaves.py``,
with one ``@leaf`` class per unknown leaf. A class's ports come from the node's model
(the file's ``<TreeNodesModel>`` or a ``--nodes-model`` palette) when there is one, else
from the attributes the file gives it: ``{key}`` is a port bound to an entry (direction
unknown: bidirectional, any type), a literal an input port of the type it looks like
(``true`` bool, ``12`` int, ``1.5`` float, else str). Every scaffolded leaf returns
FAILURE with a feedback message saying it is not written yet: the user writes
``update()``.
"""

from __future__ import annotations

import keyword
import re
from dataclasses import dataclass, field
from pathlib import Path

from sar_framework.engine.ports import convert, entry_ref, is_message
from sar_framework.interop.btcpp_entries import entry_key
from sar_framework.interop.btcpp_models import (
    NodeModel,
    PortModel,
    guess_type,
    literal_default,
    widen,
)
from sar_framework.interop.xml_source import Problem

#: Port direction -> the class the module declares it with (sar_framework.engine.ports).
PORT_CLASSES = {"input": "InputPort", "output": "OutputPort", "inout": "BidirectionalPort"}
_PYTHON_TYPES = frozenset({"str", "int", "float", "bool", "list"})


@dataclass
class LeafDraft:
    """What the file tells about one unknown leaf.

    Attributes:
        tag: The node's registration ID (the XML tag).
        where: Its first use.
        model: Its model, when one was given.
        guessed: Port name -> (direction, type) inferred from attributes, for the
            attributes the model does not declare (all of them without a model).
        bound: Attribute -> on how many uses of the node the file sets it.
        uses: How many times the file uses the node.
        plugin: The plugin name to scaffold (the tag, unless a registered plugin has it).
    """

    tag: str
    where: Problem
    model: NodeModel | None = None
    guessed: dict[str, tuple[str, str]] = field(default_factory=dict)
    bound: dict[str, int] = field(default_factory=dict)
    uses: int = 0
    plugin: str = ""

    def __post_init__(self) -> None:
        self.plugin = self.plugin or self.tag

    def use(self, key: str, text: str) -> None:
        """Record that the file sets attribute ``key`` to ``text`` on this node."""
        self.bound[key] = self.bound.get(key, 0) + 1
        if self.model is not None and self.model.port(key) is not None:
            return
        if entry_key(text) is not None:
            direction, kind = "inout", "any"
        else:
            direction, kind = "input", guess_type(text)
        if key in self.guessed:
            old_direction, old_kind = self.guessed[key]
            direction = old_direction if old_direction == direction else "inout"
            kind = old_kind if kind == "any" else (kind if old_kind == "any"
                                                      else widen(old_kind, kind))
        self.guessed[key] = (direction, kind)

    def ports(self) -> list[PortModel]:
        """The ports the scaffold declares: the model's, then the guessed ones.

        A modelled input without a default that the file never sets is left out (see
        :meth:`optional`): BT.CPP lets a node run without it, our ports would require it.
        One the file sets on some uses only gets the default ``"{=}"`` (the entry named
        like the port): unset, reading it fails, as BT.CPP's ``getInput`` does.
        """
        declared = [p for p in self.model.ports if p not in self.optional()] \
            if self.model is not None else []
        for name, (direction, kind) in self.guessed.items():
            text = ("Guessed from the attributes the file gives it"
                    + (": bound to a blackboard entry, direction unknown"
                       if direction == "inout" else "") + ".")
            declared.append(PortModel(name, direction, kind, None, None, text))
        return [self._sometimes(p) for p in declared]

    def _sometimes(self, port: PortModel) -> PortModel:
        if port.direction == "output" or port.default is not None \
                or self.bound.get(port.name, 0) >= self.uses:
            return port
        text = (port.description + " " if port.description else "") + (
            "(Optional in BT.CPP: where the file leaves it out, it reads the entry named "
            "like the port.)")
        return PortModel(port.name, port.direction, port.type, port.cpp, "{=}", text)

    def optional(self) -> list[PortModel]:
        """The modelled inputs without a default that the file never sets."""
        if self.model is None:
            return []
        return [p for p in self.model.ports if p.direction != "output" and p.default is None
                and p.name not in self.bound]

    def port_type(self, key: str) -> str:
        """The type of port ``key`` (``any`` when unknown)."""
        if self.model is not None and self.model.port(key) is not None:
            return self.model.port(key).type  # type: ignore[union-attr]
        return self.guessed.get(key, ("input", "any"))[1]


def class_name(tag: str) -> str:
    """A Python class name for a node ID (``Is-Path Valid`` -> ``Is_Path_Valid``)."""
    name = re.sub(r"\W", "_", tag)
    if not name or name[0].isdigit() or keyword.iskeyword(name):
        name = "Node_" + name
    return name


def _type_source(kind: str) -> str:
    return kind if kind in _PYTHON_TYPES else repr(kind)


def _port_source(port: PortModel) -> str:
    parts = [repr(port.name), _type_source(port.type)]
    default = literal_default(port)
    if default is not None and port.direction != "output":
        try:
            if entry_ref(default) is None:
                converted = convert(port.type, default)
                if not is_message(port.type):  # a message's text stays, read as a literal
                    default = converted
            parts.append(f"default={default!r}")
        except ValueError:
            pass  # a default the port type cannot hold: none
    if port.description:
        parts.append(f"description={port.description!r}")
    return f"    {PORT_CLASSES[port.direction]}({', '.join(parts)}),"


def _class_source(draft: LeafDraft) -> str:
    name = class_name(draft.plugin)
    ports = draft.ports()
    category = draft.model.category if draft.model is not None else "node"
    origin = ("its ports come from its <TreeNodesModel> entry in"
              f" {Path(draft.model.where.file).name}" if draft.model is not None
              else "its ports are guessed from the attributes the file gives it")
    first = f"{Path(draft.where.file).name}:{draft.where.line}:{draft.where.column}"
    args = [repr(draft.plugin)] if name != draft.plugin else []
    left_out = "".join(f"\n    # {_port_source(p).strip()}" for p in draft.optional())
    if left_out:
        left_out = ("\n    # Optional in BT.CPP (no default, never set by the file); an input "
                    "declared\n    # here must be bound, so give it a default before using "
                    "it:" + left_out)
    if ports or left_out:
        args.append("ports=[\n" + "\n".join(_port_source(p) for p in ports) + left_out
                    + "\n]")
    decorator = f"@leaf({', '.join(args)})"
    signature = ("self, name: str, *, ports: object = None" if ports else "self, name: str")
    keep = "        self.ports = ports\n" if ports else ""
    return f'''{decorator}
class {name}(py_trees.behaviour.Behaviour):
    """BT.CPP {category} {draft.tag}, scaffolded by 'sar-tree import': not written yet.

    First used at {first};
    {origin}.
    """

    def __init__({signature}) -> None:
        super().__init__(name)
{keep}
    def update(self) -> Status:
        self.feedback_message = "{draft.tag} is scaffolded: its behaviour is not written yet"
        return Status.FAILURE
'''


def scaffold_module(drafts: list[LeafDraft], source: str) -> str:
    """The text of a plugin module with one scaffolded leaf per draft.

    Args:
        drafts: The unknown leaves, in first-use order.
        source: The imported file's name, for the docstring.

    Returns:
        Python source that imports cleanly (the leaves declare ports with
        :mod:`sar_framework.engine.ports`).
    """
    uses_ports = any(draft.ports() for draft in drafts)
    used = sorted({PORT_CLASSES[p.direction] for d in drafts for p in d.ports()})
    header = f'''"""Leaves scaffolded by 'sar-tree import' from {source}.

One class per BehaviorTree.CPP node the file uses that no plugin provides. Each returns
FAILURE, saying it is not written yet: write its update() (and setup(), initialise(),
terminate() as it needs); the ports are declared already.
"""

from __future__ import annotations

import py_trees
from py_trees.common import Status

from sar_framework.engine.plugin import leaf
'''
    if uses_ports:
        header += f"from sar_framework.engine.ports import {', '.join(used)}\n"
    return header + "".join(f"\n\n{_class_source(d)}" for d in drafts)
