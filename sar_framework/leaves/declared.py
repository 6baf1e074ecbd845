"""Declared values as attributes: what every toolkit leaf's constructor does with its kwargs.

The loader constructs a leaf as ``cls(name=..., <params>..., <context objects>..., ports=...)``
(:mod:`sar_framework.engine.plugin`). A toolkit leaf keeps each of them as an attribute of
the same name, so a leaf needs no ``__init__`` of its own unless it keeps state.
"""

from __future__ import annotations

from functools import cache
from typing import Any


def keep_declared(behaviour: Any, values: dict[str, Any]) -> None:
    """Set each declared value as an attribute of ``behaviour``.

    Args:
        behaviour: The leaf being constructed.
        values: The declared params, context objects and ``ports`` by name.

    Raises:
        TypeError: A name would hide an attribute the behaviour already has (``status``,
            ``feedback_message``, a method...).
    """
    for key, value in values.items():
        if key != "ports" and (key in _behaviour_attributes() or hasattr(type(behaviour), key)):
            raise TypeError(f"{type(behaviour).__name__}: the declared name {key!r} would "
                            "hide an attribute of the behaviour; choose another name")
        setattr(behaviour, key, value)


@cache
def _behaviour_attributes() -> frozenset[str]:
    """The attributes every py_trees behaviour sets on itself (``status``, ``parent``...)."""
    import py_trees

    class _Probe(py_trees.behaviour.Behaviour):
        def update(self) -> py_trees.common.Status:
            return py_trees.common.Status.SUCCESS

    return frozenset(vars(_Probe(name="probe")))


def interface_type(name: str) -> Any:
    """Import a ROS interface type from its name, as ``ros2 interface`` spells it.

    Args:
        name: ``package/kind/Type``, e.g. ``nav2_msgs/action/Spin`` or
            ``std_srvs/srv/Trigger``.

    Returns:
        The Python class (``nav2_msgs.action.Spin``).

    Raises:
        ValueError: The name is not ``package/kind/Type``.
        ImportError: The interface package is not installed.
    """
    import importlib

    parts = name.split("/")
    if len(parts) != 3 or not all(parts):
        raise ValueError(f"interface name {name!r}: expected package/kind/Type, "
                         "e.g. nav2_msgs/action/Spin")
    package, kind, type_name = parts
    return getattr(importlib.import_module(f"{package}.{kind}"), type_name)
