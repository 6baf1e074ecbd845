"""Values checked against a node's parameter table in pure Python, before the node starts.

Each node declares its parameters once, as a table of
:class:`~sar_framework.engine.param.Param` (:data:`sar_framework.orchestrate.inputs.NODE_PARAMETERS`
names every table). With it ``sar-tree run`` checks the mission parameter file and each
``--X-param NAME:=VALUE`` before any process starts: unknown names (with a did-you-mean),
wrong types and impossible values are all reported at once, each with its file, line and
column when it has one. The rule for a value is :meth:`Param.problem
<sar_framework.engine.param.Param.problem>`, the one the nodes apply too.
"""

from __future__ import annotations

import fnmatch
from collections.abc import Iterable, Mapping
from typing import Any

from sar_framework.engine.diagnostics import did_you_mean
from sar_framework.engine.param import Param
from sar_framework.mission.params_file import KeyLocation, ParamsError

#: ROS's own parameter, which every node has (rclpy declares it).
USE_SIM_TIME = Param("use_sim_time", bool, default=False,
                     description="follow /clock (ROS time from the simulator or Gazebo)")


def find_param(name: str, table: Iterable[Param]) -> Param | None:
    """The entry of ``table`` that ``name`` matches (``*`` is one name segment), or None."""
    for param in table:
        if param.name == name or ("*" in param.name and fnmatch.fnmatchcase(name, param.name)
                                  and name.count(".") == param.name.count(".")):
            return param
    return None


def check_values(values: Mapping[str, Any], table: Iterable[Param],
                 where: Mapping[str, KeyLocation], source: str) -> list[ParamsError]:
    """Check names and types of ``values`` against ``table``.

    Args:
        values: Dotted name -> value.
        table: The node's parameters.
        where: Where each name is set, when known.
        source: Names the origin of a value without a location.

    Returns:
        One error per unknown name or bad value.
    """
    table = tuple(table)
    names = [p.name.replace("*", "<id>") for p in table]
    problems = []
    for name, value in values.items():
        param = find_param(name, table)
        problem = (param.problem(value) if param is not None
                   else "unknown parameter" + did_you_mean(name, names))
        if problem is not None:
            problems.append(located(name, problem, where, source))
    return problems


def located(name: str, problem: str, where: Mapping[str, KeyLocation],
            source: str) -> ParamsError:
    """An error about ``name``, at its file, line and column when known."""
    at = where.get(name)
    if at is None:
        return ParamsError(source, name, problem)
    return ParamsError(at.file, name, problem, at.line, at.col)
