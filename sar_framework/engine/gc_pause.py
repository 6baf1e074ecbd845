"""Pause the cyclic garbage collector while a tree loads; promote what the load made.

A load allocates tens of thousands of objects that all stay alive; the collector would
scan them again and again for nothing (a third of the time of a big load). At the end of
a successful load, what it made is moved straight to the oldest generation (the
documented effect of ``gc.freeze()`` then ``gc.unfreeze()``), which is where the
collector would put it after scanning it all once at the first allocation after the
pause (about 25 ms at 10,000 nodes). Skipped when the program keeps objects frozen
itself, so as not to unfreeze them.

Objects promoted this way do not count towards the collector's own trigger for a full
collection (which is what finds a discarded tree: py_trees behaviours point at their
parents, so old trees are cycles). A program that reloads trees and does little else
would then never run one, and old trees would pile up. So the promotion has a budget,
:data:`PROMOTION_BUDGET` objects between two full collections; past it, loads leave their
objects to the collector, which counts them as usual and soon runs a full collection.
"""

from __future__ import annotations

import contextlib
import gc
import threading
from collections.abc import Iterator

#: Most objects promoted between two full collections: about two 10,000-node loads (one
#: promotes some 127,000 objects), or thousands of small ones; also the most garbage the
#: promotion can keep out of the collector's sight.
PROMOTION_BUDGET = 250_000


class _Budget:
    """Objects promoted since the last full collection the budget has seen."""

    __slots__ = ("full_collections", "lock", "promoted")

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.promoted = 0
        self.full_collections = -1


_budget = _Budget()


@contextlib.contextmanager
def paused() -> Iterator[None]:
    """Pause the collector for a load; on success, promote what the load made."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
        if was_enabled:
            _promote()
    finally:
        if was_enabled:
            gc.enable()


def _promote() -> None:
    """Move the young objects to the oldest generation, within the budget."""
    if gc.get_freeze_count():
        return  # the program's own frozen objects: leave them frozen
    budget = _budget
    with budget.lock:
        full = gc.get_stats()[-1]["collections"]
        if full != budget.full_collections:
            budget.full_collections, budget.promoted = full, 0
        young = gc.get_count()[0]  # container objects allocated (net) since the pause
        if budget.promoted + young > PROMOTION_BUDGET:
            return
        budget.promoted += young
        gc.freeze()
        gc.unfreeze()
