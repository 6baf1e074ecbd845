"""Parameters from a ROS node: the reading node, defaults, and errors worded with file and key.

The reading node is created with ``automatically_declare_parameters_from_overrides=True``
and ``allow_undeclared_parameters=True`` (see :func:`create_params_node`), so every key of
the file is declared by rclpy; a default is declared only where the file did not set the
key (:func:`declare_default`), which avoids ``ParameterAlreadyDeclaredException``.

Every problem is one :class:`ParamsError` naming the file and key (an app's readers derive
from :class:`ParamReader`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from sar_framework.mission.params_file import KeyLocation, ParamsError
from sar_framework.mission.runner_params import TICK_RATE_HZ

if TYPE_CHECKING:
    from rclpy.node import Node

__all__ = [
    "DEFAULT_TICK_RATE_HZ",
    "ParamReader",
    "ParamsError",
    "create_params_node",
    "declare_default",
]

#: Tick rate when the parameter file does not set ``tick_rate_hz`` (from the runner's table).
DEFAULT_TICK_RATE_HZ: float = TICK_RATE_HZ.default


def create_params_node(name: str, **kwargs: Any) -> Node:
    """Create a node that declares every parameter given in its parameter files.

    Args:
        name: The node name.
        **kwargs: Further ``rclpy.node.Node`` arguments (``context``, ``namespace``...).

    Returns:
        The node.
    """
    from rclpy.node import Node

    return Node(name, automatically_declare_parameters_from_overrides=True,
                allow_undeclared_parameters=True, **kwargs)


def declare_default(node: Node, name: str, value: Any) -> Any:
    """Declare ``name`` with ``value`` unless it is already declared; return its value.

    Args:
        node: The parameter-reading node.
        name: The parameter name.
        value: The default, used only when no parameter file or override set it.

    Returns:
        The parameter's current value.
    """
    if not node.has_parameter(name):
        node.declare_parameter(name, value)
    return node.get_parameter(name).value


class ParamReader:
    """Base of the parameter readers: a node, and errors worded with file, key and line.

    Args:
        node: The parameter-reading node.
        source: Names where parameters came from when a key's file is unknown.
        locations: Where each key is set in the parameter files (adds line numbers).
    """

    def __init__(self, node: Node, source: str, locations: Mapping[str, KeyLocation]) -> None:
        self._node = node
        self._source = source
        self._locations = locations

    def error(self, key: str, problem: str) -> ParamsError:
        """Return the error for ``key``, at its file and line when known.

        Args:
            key: The parameter name.
            problem: What is wrong with it.

        Returns:
            The error (to raise).
        """
        where = self._locations.get(key)
        if where is None:
            return ParamsError(self._source, key, problem)
        return ParamsError(where.file, key, problem, where.line)

    def finite_number(self, key: str, value: Any) -> float:
        """Return ``value`` as a float if it is a finite number (not a bool).

        Args:
            key: The parameter name, for the error.
            value: The parameter's value.

        Returns:
            The number.

        Raises:
            ParamsError: ``value`` is not a number, or not finite.
        """
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(key, f"must be a number, got {value!r}")
        if not math.isfinite(value):
            raise self.error(key, f"must be finite, got {value!r}")
        return float(value)
