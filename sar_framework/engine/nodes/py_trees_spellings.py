"""The one table of py_trees' spellings: which declared BT.CPP kind each py_trees kind is.

A py_trees kind (``sequence`` with ``memory``, ``one_shot``, ``retry``...) is spelt as the
BT.CPP node that ticks its children the same way, given some of its attribute values. The
BT.CPP import/export mapping (:mod:`sar_framework.interop.mapping`) reads this table; a
py_trees kind or attribute value absent here has no BT.CPP equivalent. Where a kind and
its spelling still tick differently (``retry``'s attempts, ``timeout``'s clock), the
kind's declaration says how (``NodeKind.differences``, :mod:`.node_kinds`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Spelling:
    """A py_trees kind, with some attribute values, spelt as one declared BT.CPP kind.

    Attributes:
        btcpp_id: The BT.CPP kind (its registration ID, the XML tag).
        kind: The py_trees kind.
        fixed: The py_trees attribute values this spelling requires (``memory: true``).
        to_ports: The py_trees attributes -> the BT.CPP kind's ports.
    """

    btcpp_id: str
    kind: str
    fixed: tuple[tuple[str, Any], ...] = ()
    to_ports: Callable[[dict[str, Any]], dict[str, str]] = lambda attrs: {}


PY_TREES_SPELLINGS: tuple[Spelling, ...] = (
    Spelling("Sequence", "sequence", (("memory", True),)),
    Spelling("ReactiveSequence", "sequence", (("memory", False),)),
    Spelling("Fallback", "selector", (("memory", True),)),
    Spelling("ReactiveFallback", "selector", (("memory", False),)),
    Spelling("RunOnce", "one_shot", (("policy", "on_completion"),),
             to_ports=lambda a: {"then_skip": "false"}),
    Spelling("Inverter", "inverter"),
    Spelling("RetryUntilSuccessful", "retry",
             to_ports=lambda a: {"num_attempts": str(a["num_failures"])}),
    Spelling("Repeat", "repeat", to_ports=lambda a: {"num_cycles": str(a["num_success"])}),
    Spelling("Timeout", "timeout",
             to_ports=lambda a: {"msec": str(round(a["duration"] * 1000))}),
    Spelling("ForceSuccess", "failure_is_success"),
    Spelling("ForceFailure", "success_is_failure"),
    Spelling("KeepRunningUntilFailure", "success_is_running"),
)
