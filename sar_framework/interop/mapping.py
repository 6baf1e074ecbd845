"""The one table between our composites/decorators and BehaviorTree.CPP 4 nodes.

Each of our kinds maps either to a built-in BT.CPP node that ticks its children the same
way (:data:`BUILTIN`), or, when BT.CPP has no such node, to a *custom* node
``Sar<ClassName>`` whose ports are our attributes (declared in ``<TreeNodesModel>``, so
Groot2 can show and edit it; a BT.CPP program must register it to run the tree).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from sar_framework.engine.node_kinds import KINDS, AttrType, NodeKind

#: Prefix of the custom BT.CPP node a kind without a built-in equivalent becomes.
CUSTOM_PREFIX = "Sar"


@dataclass(frozen=True)
class Builtin:
    """A BT.CPP built-in node equivalent to one of our kinds with some attribute values.

    Attributes:
        btcpp_id: The BT.CPP registration ID (the XML tag).
        kind: Our node kind.
        fixed: Our attributes this mapping requires (e.g. ``memory: true``).
        to_ports: Our attributes -> the BT.CPP ports to write.
        from_ports: BT.CPP ports (strings) -> our attributes; raises ValueError on a
            value it cannot express.
    """

    btcpp_id: str
    kind: str
    fixed: tuple[tuple[str, Any], ...] = ()
    to_ports: Callable[[dict[str, Any]], dict[str, str]] = lambda attrs: {}
    from_ports: Callable[[dict[str, str]], dict[str, Any]] = lambda ports: {}


def _integer(ports: dict[str, str], name: str, minimum: int) -> int:
    text = ports.get(name)
    if text is None:
        raise ValueError(f"needs the port '{name}'")
    try:
        value = int(text)
    except ValueError:
        raise ValueError(f"'{name}' must be an integer, got '{text}'") from None
    if value < minimum:
        raise ValueError(f"'{name}' must be >= {minimum} here, got {value}")
    return value


def _repeat_cycles(ports: dict[str, str]) -> dict[str, Any]:
    cycles = _integer(ports, "num_cycles", -1)
    if cycles == 0:
        raise ValueError("'num_cycles' 0 never ticks the child; our repeat needs >= 1 or -1")
    return {"num_success": cycles}


def _timeout_msec(ports: dict[str, str]) -> dict[str, Any]:
    return {"duration": _integer(ports, "msec", 1) / 1000.0}


def _run_once(ports: dict[str, str]) -> dict[str, Any]:
    if ports.get("then_skip", "true").strip().lower() != "false":
        raise ValueError("RunOnce with then_skip=true returns SKIPPED, which py_trees does "
                         "not have; only then_skip=\"false\" maps (to one_shot on_completion)")
    return {"policy": "on_completion"}


def _no_ports(ports: dict[str, str]) -> dict[str, Any]:
    return {}


BUILTIN: tuple[Builtin, ...] = (
    Builtin("Sequence", "sequence", (("memory", True),), from_ports=_no_ports),
    Builtin("ReactiveSequence", "sequence", (("memory", False),), from_ports=_no_ports),
    Builtin("Fallback", "selector", (("memory", True),), from_ports=_no_ports),
    Builtin("ReactiveFallback", "selector", (("memory", False),), from_ports=_no_ports),
    Builtin("RunOnce", "one_shot", (("policy", "on_completion"),),
            to_ports=lambda a: {"then_skip": "false"}, from_ports=_run_once),
    Builtin("Inverter", "inverter", from_ports=_no_ports),
    Builtin("RetryUntilSuccessful", "retry",
            to_ports=lambda a: {"num_attempts": str(a["num_failures"])},
            from_ports=lambda p: {"num_failures": _integer(p, "num_attempts", 1)}),
    Builtin("Repeat", "repeat", to_ports=lambda a: {"num_cycles": str(a["num_success"])},
            from_ports=_repeat_cycles),
    Builtin("Timeout", "timeout", to_ports=lambda a: {"msec": str(round(a["duration"] * 1000))},
            from_ports=_timeout_msec),
    Builtin("ForceSuccess", "failure_is_success", from_ports=_no_ports),
    Builtin("ForceFailure", "success_is_failure", from_ports=_no_ports),
    Builtin("KeepRunningUntilFailure", "success_is_running", from_ports=_no_ports),
)

#: BT.CPP ID -> its mapping.
BUILTIN_BY_ID: dict[str, Builtin] = {b.btcpp_id: b for b in BUILTIN}

#: BT.CPP (and Nav2) nodes that are refused on import, with the reason and a way out.
REFUSED: dict[str, str] = {
    "SequenceWithMemory": "it retries the failed child on the next tick; py_trees has no such "
    "sequence (use Sequence: memory true, or ReactiveSequence: memory false)",
    "SequenceStar": "an old name of SequenceWithMemory, which py_trees does not have",
    "AsyncSequence": "it yields RUNNING between children; use Sequence",
    "AsyncFallback": "it yields RUNNING between children; use Fallback",
    "Parallel": "it stops at the first threshold reached, before ticking later children, "
    "where py_trees ticks every child, then fails if any failed; use SarParallel",
    "ParallelAll": "it waits for every child to finish before failing, where py_trees fails "
    "on the tick a child fails; use SarParallel",
    "IfThenElse": "no py_trees equivalent; use a selector of sequences",
    "WhileDoElse": "no py_trees equivalent; use a reactive selector of sequences",
    "Delay": "no py_trees decorator delays a child; write a leaf plugin that waits",
    "Precondition": "its condition is a script on the blackboard; use a condition leaf",
    "Script": "scripts use the blackboard; this framework shares state by references",
    "ScriptCondition": "scripts use the blackboard; use a condition leaf plugin",
    "SetBlackboard": "this framework has no blackboard; leaves share state by references",
    "UnsetBlackboard": "this framework has no blackboard; leaves share state by references",
    "RecoveryNode": "Nav2's RecoveryNode (re-run the first child after the second one "
    "recovers) has no py_trees equivalent; the nearest is retry (num_failures: "
    "number_of_retries + 1) over a selector of the first child and success_is_failure over "
    "the recovery (which also retries after a failed recovery)",
    "PipelineSequence": "Nav2's PipelineSequence re-ticks finished children; the nearest is "
    "ReactiveSequence (sequence, memory: false), which restarts from the first child",
    "RoundRobin": "Nav2's RoundRobin has no py_trees equivalent",
    "RateController": "Nav2's RateController needs a clock-rate decorator py_trees lacks",
    "DistanceController": "a Nav2 decorator reading the robot pose; no equivalent",
    "SpeedController": "a Nav2 decorator reading the robot speed; no equivalent",
    "GoalUpdater": "a Nav2 decorator writing the blackboard; no equivalent",
    "SingleTrigger": "a Nav2 decorator (like one_shot, but SKIPPED/FAILURE after); "
    "use RunOnce then_skip=\"false\" if on_completion semantics fit",
}


def builtin_for(kind: str, attrs: dict[str, Any]) -> Builtin | None:
    """Return the built-in BT.CPP node for one of our nodes, or None when there is none."""
    for entry in BUILTIN:
        if entry.kind == kind and all(attrs.get(k) == v for k, v in entry.fixed):
            return entry
    return None


def custom_id(kind: NodeKind) -> str:
    """The BT.CPP ID of the custom node a kind becomes (``SarOneShot``)."""
    return CUSTOM_PREFIX + kind.class_name


#: Custom BT.CPP ID -> our kind.
CUSTOM_KINDS: dict[str, NodeKind] = {custom_id(k): k for k in KINDS.values()}


def custom_ports(kind: NodeKind) -> list[tuple[str, str, Any, str]]:
    """The ports of a kind's custom node: ``(name, C++ type, default, description)``."""
    types = {AttrType.STRING: "std::string", AttrType.INTEGER: "int",
             AttrType.NUMBER: "double", AttrType.BOOLEAN: "bool",
             AttrType.STRINGS: "std::string"}
    return [(a.name, types[a.type], None if a.required else a.default, a.description)
            for a in kind.attrs if a.type in types and a.name != "name"]
