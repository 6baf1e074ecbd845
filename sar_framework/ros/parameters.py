"""A node's parameter table declared on its rclpy node: descriptors, ranges, one check.

Each entry of the table (:class:`~sar_framework.engine.param.Param`) becomes a declared
ROS parameter whose descriptor carries the description (with the unit), the range
(``floating_point_range``/``integer_range``) and the choices, so ``ros2 param describe``
shows what the table says. Every value is checked with :meth:`Param.problem
<sar_framework.engine.param.Param.problem>` first, the rule ``sar-tree run`` applies before
the node starts, so the node rejects what the check rejects, in the same words.

A parameter already declared (from the parameter files, on a node made with
``automatically_declare_parameters_from_overrides``) keeps its value and gets the
descriptor. Entries whose names hold ``*`` (``goals.*.x``) are left to the node.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.parameter import Parameter

from sar_framework.engine.param import REQUIRED, Param
from sar_framework.mission.params_file import KeyLocation, ParamsError

if TYPE_CHECKING:
    from rclpy.node import Node

_STATIC = {bool: Parameter.Type.BOOL, str: Parameter.Type.STRING, int: Parameter.Type.INTEGER,
           list[str]: Parameter.Type.STRING_ARRAY, list[int]: Parameter.Type.INTEGER_ARRAY}
_OWN = frozenset({"use_sim_time"})
"""Parameters rclpy declares itself: checked, never re-described."""


def descriptor(param: Param, *, ranged: bool = True) -> ParameterDescriptor:
    """The ROS descriptor of ``param``.

    A ``float`` parameter is dynamically typed, so ``speed:=20`` (an integer) is accepted
    as rclpy's command line gives it; :meth:`Param.problem` still requires a number.

    Args:
        param: The declaration.
        ranged: Include the numeric range (rclpy enforces it on every later set).
    """
    text = param.description + (f" [{param.unit}]" if param.unit else "")
    constraints = []
    if param.bounds():
        constraints.append(param.bounds())
    if param.enum is not None:
        constraints.append("one of " + ", ".join(str(c) for c in param.enum))
    out = ParameterDescriptor(description=text, additional_constraints="; ".join(constraints),
                              dynamic_typing=param.type not in _STATIC)
    if not out.dynamic_typing:
        out.type = _STATIC[param.type].value
    low = param.minimum if param.minimum is not None else param.exclusive_minimum
    if ranged and (low is not None or param.maximum is not None):
        if param.type is float:
            out.floating_point_range = [FloatingPointRange(
                from_value=float(low if low is not None else -math.inf),
                to_value=float(param.maximum if param.maximum is not None else math.inf))]
        elif param.type is int:
            out.integer_range = [IntegerRange(
                from_value=int(low if low is not None else -2**63),
                to_value=int(param.maximum if param.maximum is not None else 2**63 - 1))]
    return out


def declare_table(node: Node, table: Iterable[Param], *,
                  defaults: Mapping[str, Any] | None = None, source: str = "parameters",
                  locations: Mapping[str, KeyLocation] | None = None) -> dict[str, Any]:
    """Declare every parameter of ``table`` on ``node``, check each value, return them.

    Args:
        node: The node.
        table: Its parameters.
        defaults: Defaults known only at run time (the world's spawn), over the table's.
        source: Names where a value came from when its file is unknown.
        locations: Where each key is set in the parameter files.

    Returns:
        Name -> value (None for a parameter without a default that nobody set).

    Raises:
        ParamsError: The first value the table's rule rejects, with its file and line when
            known.
    """
    defaults = defaults or {}
    values: dict[str, Any] = {}
    for param in table:
        if "*" in param.name:
            continue
        name = param.name
        if not node.has_parameter(name):
            default = defaults.get(name, param.default)
            if default is REQUIRED or default is None:
                node.declare_parameter(name, None, ParameterDescriptor(dynamic_typing=True))
            else:
                node.declare_parameter(name, default, descriptor(param, ranged=False))
        parameter = node.get_parameter(name)
        value = None if parameter.type_ == Parameter.Type.NOT_SET else parameter.value
        if isinstance(value, tuple):
            value = list(value)
        elif hasattr(value, "tolist"):  # array.array from an INTEGER_ARRAY
            value = value.tolist()
        problem = None if value is None else param.problem(value)
        if problem is not None:
            at = (locations or {}).get(name)
            raise ParamsError(at.file if at else source, name, problem,
                              at.line if at else None, at.col if at else None)
        if name not in _OWN and value is not None:
            node.set_descriptor(name, descriptor(param))
        values[name] = value
    return values
