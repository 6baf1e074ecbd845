"""The faults ``sar-tree run`` can inject (``sar-tree faults``), read from the node tables.

A fault is a parameter of the simulator or of a server (its unit, default and meaning come
from that node's table, :data:`~sar_framework.orchestrate.inputs.NODE_PARAMETERS`), or a flag that
leaves a server out. This module only says which, with an example each.
"""

from __future__ import annotations

from dataclasses import dataclass

from sar_framework.engine.param import type_name
from sar_framework.mission.params_check import find_param
from sar_framework.orchestrate.inputs import child_parameters


@dataclass(frozen=True)
class Fault:
    """One fault ``sar-tree run`` can inject.

    Attributes:
        option: How to set it: ``--sim-param``, ``--detect-param``, a flag...
        name: The parameter name ("" for a flag).
        example: A command-line example ("" for a flag).
        meaning: What a flag does (a parameter's meaning is its table's).
    """

    option: str
    name: str = ""
    example: str = ""
    meaning: str = ""

    @property
    def child(self) -> str:
        """The process whose parameter it is (``sim``, ``detect``, ``report``)."""
        return self.option.removeprefix("--").removesuffix("-param")


FAULTS: tuple[Fault, ...] = (
    Fault("--sim-param", "reject_goals", "reject_goals:=true"),
    Fault("--sim-param", "abort_goal_numbers", "abort_goal_numbers:=[2]"),
    Fault("--sim-param", "abort_delay_s", "abort_delay_s:=3.0"),
    Fault("--sim-param", "accept_delay_wall_s", "accept_delay_wall_s:=2.0"),
    Fault("--sim-param", "blocked_areas", "blocked_areas:=['2.0:1.5:0.5']"),
    Fault("--sim-param", "speed_scale", "speed_scale:=0.5"),
    Fault("--sim-param", "phantom_obstacles", "phantom_obstacles:=['1.0:-0.5:0.3']"),
    Fault("--sim-param", "stuck_recoveries", "stuck_recoveries:=2"),
    Fault("--sim-param", "movement_time_allowance", "movement_time_allowance:=5.0"),
    Fault("--detect-param", "answer_delay_wall_s", "answer_delay_wall_s:=5.0"),
    Fault("--report-param", "answer_delay_wall_s", "answer_delay_wall_s:=5.0"),
    Fault("--report-param", "refuse_all", "refuse_all:=true"),
    Fault("--no-detect-server", meaning="the detect service is never available"),
    Fault("--no-report-server", meaning="the report service is never available"),
)
"""Every fault ``sar-tree run`` can inject."""


def faults_table() -> str:
    """The faults as plain text: the setting, then name, unit or type, default, meaning.

    Raises:
        LookupError: A fault names a parameter its node's table does not have.
    """
    lines = []
    for fault in FAULTS:
        if not fault.name:
            lines.append(f"{fault.option}\n    {fault.option} [flag]: {fault.meaning}")
            continue
        param = find_param(fault.name, child_parameters(fault.child))
        if param is None:
            raise LookupError(f"{fault.option} {fault.name}: not in the {fault.child}'s table")
        unit = ", ".join(u for u in (type_name(param.type), param.unit) if u)
        default = "" if param.default is None else f" (default {param.default!r})"
        meaning = param.description.removeprefix("fault: ")
        lines.append(f"{fault.option} {fault.example}\n    {fault.name} [{unit}]: "
                     f"{meaning}{default}")
    return "\n".join(lines) + "\n"
