"""BT.CPP 4's queue loops: LoopInt, LoopBool, LoopDouble and LoopString.

Each tick pops the next value of a queue, writes it to the ``value`` variable and ticks
the child with it; RUNNING while values remain, FAILURE as soon as the child fails, and
``if_empty`` (SUCCESS, FAILURE or SKIPPED) once the queue is empty. A literal queue
(``"1;2;3"``) is refilled each time the node starts afresh (from IDLE); a queue held in
a variable (``"{items}"``, a list) is shared: popping removes the value from it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from py_trees.common import Status

from sar_framework.engine.nodes.controls.base import Behaviour, BtDecorator, Outcome, Steps
from sar_framework.engine.variables import Variables

_TRUE = ("true", "True", "TRUE", "1")
_FALSE = ("false", "False", "FALSE", "0")


def _boolean(text: str) -> bool:
    if text in _TRUE or text in _FALSE:
        return text in _TRUE
    raise ValueError(f"'{text}' is not a boolean")


#: LoopInt .. LoopString: how one literal item is read.
ITEM_TYPES: dict[str, Callable[[str], Any]] = {
    "LoopInt": int, "LoopBool": _boolean, "LoopDouble": float, "LoopString": str,
}


class Loop(BtDecorator):
    """BT.CPP ``LoopInt``/``LoopBool``/``LoopDouble``/``LoopString``: the child once per value.

    Args:
        name: The behaviour's name.
        child: The decorated behaviour.
        queue: The values: a literal list (``"1;2;3"``, read with ``item``) or, when
            ``queue_variable`` is given, None.
        variables: Where ``value`` is written and ``queue_variable`` read.
        item: Reads one literal item (``int``, ``float``...).
        queue_variable: The variable holding a shared list, instead of a literal.
        value: The variable each popped value is written to (None: not written).
        if_empty: What to return once the queue is empty.

    Raises:
        ValueError: A literal item does not read as the loop's type.
    """

    marks_running = False

    def __init__(self, name: str, child: Behaviour, queue: str | None, variables: Variables,
                 *, item: Callable[[str], Any] = str, queue_variable: str | None = None,
                 value: str | None = None, if_empty: str = "SUCCESS") -> None:
        super().__init__(name, child)
        self.static = ([item(part) for part in queue.split(";") if part]
                       if queue is not None else None)
        self.variables = variables
        self.queue_variable = queue_variable
        self.value = value
        self.if_empty = Outcome(if_empty)
        self.current: list[Any] = []
        self.child_running = False

    def decorate(self) -> Steps:
        """Pop a value and tick the child with it, or return ``if_empty``."""
        popped = False
        if self.was_idle:
            self.child_running = False
            if self.static is not None:
                self.current = list(self.static)
        if not self.child_running:
            if self.queue_variable is not None:
                shared = (self.variables.get(self.queue_variable)
                          if self.queue_variable in self.variables else None)
                self.current = shared if shared is not None else []
            if self.current:
                popped = True
                item = self.current.pop(0)
                if self.value is not None:
                    self.variables.set(self.value, item)
        if not popped and not self.child_running:
            return self.if_empty
        self.bt_status = Status.RUNNING
        result = yield from self.tick_child()
        self.child_running = result is Outcome.RUNNING
        if result.completed:
            self.reset_child()
        return Outcome.FAILURE if result is Outcome.FAILURE else Outcome.RUNNING
