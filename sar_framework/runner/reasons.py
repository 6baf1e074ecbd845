"""Why things happen in a ticking tree: one record per failure, timeout, cancel, retry, skip.

:class:`ReasonLog` is fed by the status file writer (:mod:`.status_file`) with what each tick
did and keeps one record per event worth telling a user::

    {"what": "timeout", "uid": "0.0.1.0", "name": "VisitWithin180s", "kind": "timeout",
     "message": "timed out after 180 s; GoShelf: navigate_to_pose cancelled",
     "sim_s": 201.5, "wall_s": 11.2}

``what`` is ``failure`` (a leaf that had been RUNNING failed), ``timeout`` (a ``timeout``
decorator failed its child), ``cancel`` (a RUNNING leaf was halted by its parent, e.g. a
reactive selector), ``retry`` (a ``retry`` decorator starts its child again, or gives up)
or ``skip`` (a ``failure_is_success`` decorator turned a failure into success). A recovery
control (a kind whose declaration ``reports`` ``"recovery"``: an action, then its
recovery) whose recovery branch succeeded and which tries its action again is a ``retry``
too (``DeliverRecovery [0.1] retry: recovery 1/3 done (ClearWay) after Drive: ...;
trying Drive again``), and one that fails
after recoveries says it gives up. Each
record's :func:`reason_line` is what the runner logs: ``GoShelf [0.0.1]: navigate_to_pose
aborted (error code 206): goal (0.00, 3.00) is inside an obstacle``.
"""

from __future__ import annotations

from typing import Any

from py_trees.behaviour import Behaviour
from py_trees.common import Status

from sar_framework.engine.kind_plugin import declared_kind
from sar_framework.engine.nodes.script_nodes import PrePostConditions

#: The decorator kinds that explain something when their child fails.
EXPLAINING_DECORATORS = ("timeout", "retry", "failure_is_success")


def node_itself(behaviour: Behaviour) -> Behaviour:
    """``behaviour``, or the node inside when it is the wrapper of a node's conditions."""
    return behaviour.decorated if isinstance(behaviour, PrePostConditions) else behaviour


def recovers(behaviour: Behaviour | None) -> bool:
    """Whether ``behaviour``'s declared kind is a recovery control (it explains too)."""
    if behaviour is None:
        return False
    kind = declared_kind(node_itself(behaviour))
    return kind is not None and kind.reports == "recovery"


def reason_line(record: dict[str, Any]) -> str:
    """One console line for a record: ``Name [uid] what: message``."""
    what = "" if record["what"] == "failure" else f" {record['what']}"
    return f"{record['name']} [{record['uid']}]{what}: {record['message']}"


class ReasonLog:
    """Collects the records of one tick, then hands them over.

    Args:
        kinds: ``uid -> node kind`` of every node of the tree.
        behaviours: ``uid -> behaviour``.
    """

    def __init__(self, kinds: dict[str, str], behaviours: dict[str, Behaviour]) -> None:
        self._kinds = kinds
        self._behaviours = behaviours
        self._tick: list[dict[str, Any]] = []
        self._quoted: set[str] = set()
        self._said: dict[str, str] = {}
        # recovery control uid -> (retries when its recovery started, why the action failed)
        self._recovering: dict[str, tuple[int, str]] = {}
        # leaves that succeeded inside a recovery branch, until its recovery control tells
        self._recovered: dict[str, str] = {}
        self._recoveries: dict[str, int] = {}  # recovery control uid -> recoveries done
        self._recovery_controls = {uid for uid in kinds if recovers(behaviours.get(uid))}
        self._recovery_branches = tuple(f"{uid}.1." for uid in sorted(self._recovery_controls))

    def _add(self, what: str, uid: str, message: str, stamp: dict[str, float]) -> None:
        behaviour = self._behaviours[uid]
        self._tick.append({"what": what, "uid": uid, "name": behaviour.name,
                           "kind": self._kinds[uid], "message": message, **stamp})

    def _last_failure_under(self, uid: str, *, named: bool = False) -> str:
        for record in reversed(self._tick):
            if record["what"] in ("failure", "timeout") and record["uid"].startswith(uid + "."):
                return f"{record['name']}: {record['message']}" if named else record["message"]
        for leaf, message in reversed(list(self._said.items())):
            if leaf.startswith(uid + "."):
                return f"{self._behaviours[leaf].name}: {message}"
        return "no reason given"

    def leaf_failed(self, uid: str, message: str, stamp: dict[str, float]) -> None:
        """A leaf that had been RUNNING returned FAILURE."""
        self._add("failure", uid, message or "no reason given", stamp)

    def leaf_said_no(self, uid: str, message: str) -> None:
        """A leaf that was not RUNNING (a condition) returned FAILURE with ``message``.

        Not a record of its own (a condition saying "no" is a decision), but the reason a
        ``timeout``, ``retry`` or ``failure_is_success`` above it quotes.
        """
        if message:
            self._said[uid] = message

    def leaf_succeeded(self, uid: str) -> None:
        """A leaf that had been RUNNING succeeded: kept when part of a recovery branch."""
        if uid.startswith(self._recovery_branches):
            self._recovered[uid] = f"{self._kinds[uid]} {self._behaviours[uid].name}" \
                if self._kinds[uid] != self._behaviours[uid].name else self._kinds[uid]

    def decorator_ticked(self, uid: str, running: set[str], stamp: dict[str, float]) -> None:
        """Explain what a ``timeout``, ``retry``, ``failure_is_success`` or recovery did.

        Args:
            uid: The decorator's uid.
            running: Uids of the leaves that were RUNNING before this tick.
            stamp: ``sim_s`` and ``wall_s`` of the tick.
        """
        kind = self._kinds[uid]
        behaviour = self._behaviours[uid]
        if uid in self._recovery_controls:
            self._recovery_ticked(uid, behaviour, stamp)
            return
        child = behaviour.children[0] if behaviour.children else None
        status = behaviour.status
        if kind == "timeout" and status == Status.FAILURE \
                and (child is None or child.status == Status.INVALID):
            halted = [u for u in sorted(running) if u.startswith(uid + ".")
                      and self._behaviours[u].status == Status.INVALID]
            self._quoted.update(halted)
            parts = [f"timed out after {getattr(behaviour, 'duration', 0.0):g} s"]
            parts += [f"{self._behaviours[u].name}: {self._behaviours[u].feedback_message}"
                      for u in halted]
            self._add("timeout", uid, "; ".join(parts), stamp)
        elif kind == "retry" and child is not None and child.status == Status.FAILURE:
            failures = getattr(behaviour, "failures", 0)
            limit = getattr(behaviour, "num_failures", 0)
            why = self._last_failure_under(uid)
            message = (f"attempt {failures}/{limit} failed ({why}); trying again"
                       if status == Status.RUNNING else
                       f"giving up after {failures} failed attempts ({why})")
            self._add("retry", uid, message, stamp)
        elif kind == "failure_is_success" and status == Status.SUCCESS \
                and child is not None and child.status == Status.FAILURE:
            self._add("skip", uid, f"{child.name} failed ({self._last_failure_under(uid)}); "
                      "skipped", stamp)

    def _recovery_ticked(self, uid: str, behaviour: Behaviour, stamp: dict[str, float]) -> None:
        """A recovery control: its recovery started, succeeded (a retry), or it gave up."""
        behaviour = node_itself(behaviour)
        retries = int(getattr(behaviour, "retries", 0))
        index = int(getattr(behaviour, "index", 0))
        limit = int(getattr(behaviour, "number_of_retries", 0))
        action = behaviour.children[0].name
        if behaviour.status == Status.RUNNING:
            if index == 1 and uid not in self._recovering:
                self._recovering[uid] = (retries, self._last_failure_under(uid, named=True))
            elif index == 0 and uid in self._recovering:
                before, why = self._recovering.pop(uid)
                done = [name for leaf, name in sorted(self._recovered.items())
                        if leaf.startswith(f"{uid}.1.")]
                for leaf in [u for u in self._recovered if u.startswith(f"{uid}.1.")]:
                    del self._recovered[leaf]
                if retries == before + 1:
                    self._recoveries[uid] = retries
                    what = f" ({', '.join(done)})" if done else ""
                    self._add("retry", uid, f"recovery {retries}/{limit} done{what} after "
                              f"{why}; trying {action} again", stamp)
            return
        started = self._recovering.pop(uid, None)
        count = self._recoveries.pop(uid, 0)
        if behaviour.status != Status.FAILURE:
            return
        if started is not None:
            self._add("retry", uid, f"giving up: the recovery of {action} failed "
                      f"({self._last_failure_under(uid, named=True)}) after {started[1]}", stamp)
        elif count:
            self._add("retry", uid, f"giving up after {count}/{limit} recoveries "
                      f"({self._last_failure_under(uid, named=True)})", stamp)

    def leaves_halted(self, halted: list[str], stamp: dict[str, float]) -> None:
        """RUNNING leaves their parent stopped this tick (not already quoted by a timeout)."""
        for uid in halted:
            if uid not in self._quoted:
                feedback = str(self._behaviours[uid].feedback_message or "")
                self._add("cancel", uid, f"halted ({feedback})" if feedback else "halted",
                          stamp)

    def take(self) -> list[dict[str, Any]]:
        """The records of the tick just finished (and forget them)."""
        records, self._tick = self._tick, []
        self._quoted = set()
        self._said = {}
        return records
