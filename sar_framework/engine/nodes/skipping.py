"""BehaviorTree.CPP's SKIPPED status, carried on py_trees' three statuses.

py_trees has no SKIPPED. A node that BT.CPP would report SKIPPED (a ``_skipIf`` that
holds, a ``_while`` that is false before the node starts, ``RunOnce then_skip``, a
``Precondition``... ) returns ``Status.SUCCESS`` *and* marks itself skipped for that tick.
Composites that follow BT.CPP's rules read the mark and treat the child as BT.CPP treats
SKIPPED (a sequence or fallback moves on to the next child; a parallel does not count it;
a composite whose children were all skipped is skipped itself). A plain py_trees
composite sees SUCCESS. The mark is an attribute on the behaviour, cleared whenever the
behaviour returns a status of its own.

Only code that makes or reads the mark imports this module; the mark lives on the
behaviour, so no registry or tree-wide state is needed.
"""

from __future__ import annotations

from typing import Any

#: The behaviour attribute that holds the mark.
SKIPPED_ATTRIBUTE = "sar_skipped"


def mark_skipped(behaviour: Any, skipped: bool = True) -> None:
    """Record whether ``behaviour``'s latest status means SKIPPED.

    Args:
        behaviour: The py_trees behaviour that just returned a status.
        skipped: True when that status (always SUCCESS) stands for SKIPPED.
    """
    setattr(behaviour, SKIPPED_ATTRIBUTE, skipped)


def was_skipped(behaviour: Any) -> bool:
    """Return whether ``behaviour``'s latest status stands for SKIPPED."""
    return bool(getattr(behaviour, SKIPPED_ATTRIBUTE, False))
