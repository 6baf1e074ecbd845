"""``<TreeNodesModel>``: what a BehaviorTree.CPP file (or a palette) says about its nodes.

BT.CPP itself reads only the ``<SubTree>`` models of a file (their ports' defaults and
whether a remapping is mandatory); a node's real ports come from its C++
``providedPorts()``. Groot2 and palettes such as Nav2's ``nav2_tree_nodes.xml`` declare
the other nodes here too: category (``Action``, ``Condition``, ``Control``,
``Decorator``), ports with direction (``input_port``, ``output_port``, ``inout_port``),
C++ type, default and description. The importer reads them to type the ports of the
leaves it scaffolds and the blackboard entries it declares.

Port types are kept in our spelling (:mod:`sar_framework.engine.ports`): ``str int float
bool list any`` or a ROS message type ``pkg/msg/Type``; :func:`port_type` converts BT.CPP's
C++ names.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from sar_framework.engine.plugin import PluginSpec
from sar_framework.engine.ports import NO_DEFAULT
from sar_framework.interop.xml_source import Element, Problem

#: The elements of a ``<TreeNodesModel>`` that declare a node.
MODEL_CATEGORIES = frozenset({"Action", "Condition", "Control", "Decorator", "SubTree"})
#: Port element -> direction.
PORT_DIRECTIONS = {"input_port": "input", "output_port": "output", "inout_port": "inout"}

_CPP_SCALARS = {
    "str": ("std::string", "string", "std::basic_string<char>"),
    "float": ("double", "float"),
    "bool": ("bool",),
    "int": ("int", "unsigned", "unsigned int", "long", "unsigned long", "size_t",
            "std::size_t", "int8", "int16", "int32", "int64", "uint8", "uint16", "uint32",
            "uint64", "int8_t", "int16_t", "int32_t", "int64_t", "uint8_t", "uint16_t",
            "uint32_t", "uint64_t", "chrono::milliseconds", "std::chrono::milliseconds"),
}
#: C++ type name -> our port type name, for the scalar types.
CPP_TO_PORT: dict[str, str] = {cpp: ours for ours, names in _CPP_SCALARS.items()
                               for cpp in names}
#: Our port type name -> the C++ type BT.CPP writes in a model (messages: ``pkg::msg::T``).
PORT_TO_CPP: dict[str, str] = {"str": "std::string", "int": "int", "float": "double",
                               "bool": "bool"}
_MESSAGE = re.compile(r"^(?:::)?([A-Za-z][A-Za-z0-9_]*)::(msg)::([A-Z][A-Za-z0-9_]*)$")
_SEQUENCE = re.compile(r"^(?:std::)?(?:vector|deque)\s*<.*>$")


def port_type(cpp: str | None) -> str:
    """Our port type for a C++ type name.

    ``double`` -> ``float``, ``nav_msgs::msg::Path`` -> ``nav_msgs/msg/Path``,
    ``vector<...>`` -> ``list``; unknown or absent -> ``any``.
    """
    if not cpp:
        return "any"
    text = cpp.strip()
    if text in CPP_TO_PORT:
        return CPP_TO_PORT[text]
    message = _MESSAGE.match(text)
    if message:
        return "/".join(message.groups())
    if _SEQUENCE.match(text):
        return "list"
    return "any"


def cpp_type(ours: str) -> str | None:
    """The C++ type name of one of our port types, or None for ``any`` (any type)."""
    if ours in PORT_TO_CPP:
        return PORT_TO_CPP[ours]
    if ours.count("/") == 2:
        return ours.replace("/", "::")
    if ours == "list":
        return "std::vector<std::string>"
    return None


@dataclass(frozen=True)
class PortModel:
    """One declared port of a node model.

    Attributes:
        name: The port (the XML attribute).
        direction: ``input``, ``output`` or ``inout``.
        type: Our port type name (:func:`port_type`).
        cpp: The C++ type as written, or None.
        default: The default as written (a literal or ``{key}``), or None.
        description: The element's text or ``description`` attribute.
    """

    name: str
    direction: str
    type: str
    cpp: str | None = None
    default: str | None = None
    description: str = ""


@dataclass(frozen=True)
class NodeModel:
    """One ``<Action|Condition|Control|Decorator|SubTree ID="...">`` of a model.

    Attributes:
        id: The registration ID.
        category: The element name (``Action``...).
        ports: The declared ports, in file order.
        where: The element's position (``file:line:col`` of the declaration).
    """

    id: str
    category: str
    ports: tuple[PortModel, ...]
    where: Problem

    def port(self, name: str) -> PortModel | None:
        """The declared port called ``name``, or None."""
        return next((p for p in self.ports if p.name == name), None)

    @property
    def is_leaf(self) -> bool:
        """Whether the model is an action or a condition."""
        return self.category in ("Action", "Condition")


def _text(element: Element) -> str:
    return " ".join((element.text or element.attrs.get("description", "")).split())


def read_models(models: Element, file: str) -> tuple[dict[str, NodeModel], list[Problem]]:
    """Read one ``<TreeNodesModel>`` element.

    Args:
        models: The element.
        file: Its file, for problems and :attr:`NodeModel.where`.

    Returns:
        ID -> model, and the problems (a model without ``ID``, a port without ``name``:
        BT.CPP refuses both).
    """
    found: dict[str, NodeModel] = {}
    problems: list[Problem] = []
    for element in models.children:
        where = Problem(file, element.line, element.column, "")
        if element.tag not in MODEL_CATEGORIES:
            continue
        node_id = element.attrs.get("ID")
        if not node_id:
            problems.append(Problem(file, element.line, element.column,
                                    f"<{element.tag}> in <TreeNodesModel> needs an ID "
                                    "(BT.CPP: 'The attribute [ID] is mandatory')"))
            continue
        ports: list[PortModel] = []
        for port in element.children:
            direction = PORT_DIRECTIONS.get(port.tag)
            if direction is None:
                continue
            name = port.attrs.get("name")
            if not name:
                problems.append(Problem(file, port.line, port.column, f"<{port.tag}> of "
                                        f"'{node_id}' needs a name (BT.CPP: 'Missing "
                                        "attribute [name] in port')"))
                continue
            cpp = port.attrs.get("type")
            ports.append(PortModel(name, direction, port_type(cpp), cpp,
                                   port.attrs.get("default"), _text(port)))
        found[node_id] = NodeModel(node_id, element.tag, tuple(ports), where)
    return found, problems


def literal_default(port: PortModel) -> object:
    """The port's default as a Python value of its type (None when it has none).

    Palettes write a string default in double quotes (``"planner_selector"``, ``""``):
    they are taken off; a ``{key}`` default stays a string.
    """
    text = port.default
    if text is None:
        return None
    if len(text) >= 2 and text[0] == text[-1] == '"':
        return text[1:-1]
    if text.startswith("{") and text.endswith("}"):
        return text
    return convert_literal(text, port.type)


def convert_literal(text: str, ours: str) -> object:
    """``text`` converted to a port type as BT.CPP's ``convertFromString`` would.

    Left as text when the type is not a scalar or the text does not convert.
    """
    try:
        if ours == "bool":
            lowered = text.strip().lower()
            if lowered in ("true", "1"):
                return True
            if lowered in ("false", "0"):
                return False
            return text
        if ours == "int":
            return int(text)
        if ours == "float":
            return float(text)
    except ValueError:
        return text
    return text


def guess_type(text: str) -> str:
    """A port type guessed from a literal.

    ``true``/``false`` bool, integers int, numbers float, the rest str.
    """
    if text.strip().lower() in ("true", "false"):
        return "bool"
    try:
        int(text)
        return "int"
    except ValueError:
        pass
    try:
        float(text)
        return "float"
    except ValueError:
        return "str"


def widen(first: str, second: str) -> str:
    """The narrowest type of two guesses that holds both (int and float -> float)."""
    if first == second:
        return first
    if {first, second} == {"int", "float"}:
        return "float"
    return "str"


def plugin_ports(plugin: PluginSpec) -> dict[str, PortModel]:
    """A registered plugin's declared ports (``@leaf(ports=[...])``), as port models."""
    return {port.name: PortModel(port.name, port.direction.value, port.type, None,
                                 None if port.default is NO_DEFAULT else str(port.default),
                                 port.description) for port in plugin.ports}


def missing_ports(plugin: PluginSpec, model: NodeModel) -> list[str]:
    """The model's ports the plugin has neither as a param nor as a port (nor ``id``)."""
    names = {p.name for p in plugin.params} | {p.name for p in plugin.ports} | {"id", "name"}
    return [port.name for port in model.ports if port.name not in names]


def clashes(plugin: PluginSpec, model: NodeModel) -> bool:
    """Whether a model describes another node than the registered plugin of its name."""
    return model.is_leaf and bool(missing_ports(plugin, model))
