"""``sar-tree watch``: attach to a running mission and show its tree live in the terminal.

Listens on the ROS domain of the environment (``ROS_DOMAIN_ID``) to the tree status the
runner publishes each tick (:mod:`sar_framework.runner.tree_status`) and redraws the
frame of :mod:`.view` with rich's ``Live`` display, at most :data:`MAX_FPS` times a
second. It ends by itself when the mission is over (the runner's verdict) or when the
runner goes away, and on Ctrl-C; when no mission shows up within ``--wait`` seconds it
says so and exits 1.
"""

from __future__ import annotations

import argparse
import functools
import os
import sys
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from sar_framework.events.event import in_namespace
from sar_framework.runner.entry_values import apply_entries
from sar_framework.runner.tree_status import STATUS_TOPIC_NAME, StatusFormatError, decode_status
from sar_framework.watch.snapshot_source import SnapshotFeed

EXIT_OK = 0
EXIT_NO_MISSION = 1
EXIT_INTERRUPTED = 130
MAX_FPS = 20.0
DEFAULT_WAIT_S = 30.0
RATE_WINDOW_S = 2.0
SPIN_S = 0.02
#: Seconds to keep reading after the runner's publisher is gone (messages still in flight).
GONE_GRACE_S = 0.5
#: Callbacks taken at most, once the snapshot stream ended, for what it had sent.
DRAIN_MAX = 100


def configure(parser: argparse.ArgumentParser) -> None:
    """Add ``sar-tree watch``'s arguments to ``parser``."""
    parser.add_argument("--wait", type=float, default=DEFAULT_WAIT_S, metavar="S",
                        help="give up when no mission ticks within S seconds "
                        f"(default: {DEFAULT_WAIT_S:g})")
    parser.add_argument("--fps", type=float, default=MAX_FPS, metavar="N",
                        help=f"redraw at most N times a second (default: {MAX_FPS:g})")
    parser.add_argument("--namespace", default="", metavar="NS",
                        help="watch the runner in this namespace (a fleet's robot1: "
                        "/robot1/sar_tree/status; default: the root namespace)")


@dataclass
class WatchState:
    """What the watcher has seen so far.

    Attributes:
        document: The latest status document, or None before the first.
        arrivals: ``(wall time, tick)`` of recent documents, for the tick rate.
        received: Documents received.
        drawn: Frames drawn.
        rejected: Messages that were not status documents.
        fresh: A document came since the last frame was drawn.
        first_s: ``time.monotonic()`` of the first document.
        entries: The tree's blackboard entries as known so far (the status documents carry
            only the ones that changed), ``name -> {"key", "value", "type", "writer"}``.
    """

    document: dict[str, Any] | None = None
    arrivals: deque[tuple[float, int]] = field(default_factory=deque)
    received: int = 0
    drawn: int = 0
    rejected: int = 0
    fresh: bool = False
    first_s: float = 0.0
    entries: dict[str, dict[str, str]] = field(default_factory=dict)

    def take(self, text: str, now: float) -> None:
        """Decode one message and keep it (a bad one is counted and dropped)."""
        try:
            document = decode_status(text)
        except StatusFormatError:
            self.rejected += 1
            return
        if self.document is None:
            self.first_s = now
        if "entries" in document:
            changed = {row[0] for row in document["entries"]}
            self.entries = apply_entries(self.entries, document["entries"],
                                         full=bool(document.get("entries_full")))
            document["entries"] = self.entries
            document["entries_changed"] = changed
        self.document, self.fresh = document, True
        self.received += 1
        self.arrivals.append((now, int(document.get("tick", 0))))
        while self.arrivals and now - self.arrivals[0][0] > RATE_WINDOW_S:
            self.arrivals.popleft()

    def ticks_per_s(self) -> float | None:
        """Ticks per wall second over the last :data:`RATE_WINDOW_S` seconds."""
        if len(self.arrivals) < 2:
            return None
        (t0, k0), (t1, k1) = self.arrivals[0], self.arrivals[-1]
        return (k1 - k0) / (t1 - t0) if t1 > t0 else None


def watch(wait_s: float = DEFAULT_WAIT_S, fps: float = MAX_FPS, console: Any = None,
          namespace: str = "") -> int:
    """Show the running mission's tree until it ends; return the exit code.

    Args:
        wait_s: Seconds to wait for the first status.
        fps: Highest redraw rate.
        console: A ``rich.console.Console`` (stdout's by default).
        namespace: The runner's namespace (a fleet's ``robot1``); "" for the root.
    """
    status_topic = in_namespace(STATUS_TOPIC_NAME, namespace)
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.signals import SignalHandlerOptions
    from rich.console import Console
    from rich.live import Live
    from std_msgs.msg import String

    from sar_framework.stop_signals import stop_on_signals
    from sar_framework.watch.snapshot_source import snapshots_available
    from sar_framework.watch.view import frame

    console = console or Console()
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    stop = stop_on_signals()
    node = Node("sar_tree_watch")
    state = WatchState()
    node.create_subscription(String, status_topic,
                             lambda m: state.take(m.data, time.monotonic()), 100)
    feed = SnapshotFeed(node, status_topic) if snapshots_available() else None
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    started = time.monotonic()
    ending = ""
    gone_since: float | None = None
    try:
        with Live(console=console, auto_refresh=False, transient=False) as live:
            live.update(f"waiting for a mission on {status_topic} "
                        f"(ROS_DOMAIN_ID={_domain()})...", refresh=True)
            last_draw = 0.0
            while not stop:
                executor.spin_once(timeout_sec=SPIN_S)
                now = time.monotonic()
                if feed is not None and state.document is not None:
                    feed.poll(now)
                done = state.document is not None and bool(state.document.get("complete"))
                if done and feed is not None and feed.topic:
                    # draw the last tick with its own snapshot, which follows the status:
                    # wait for it, or for the end of the stream (then take what it sent)
                    tick = int(state.document.get("tick", 0))
                    done = feed.settled(tick)
                    if done and not feed.has(tick):
                        _drain(executor, functools.partial(feed.has, tick))
                fresh = state.fresh or (feed is not None and feed.fresh)
                if fresh and (done or now - last_draw >= 1.0 / fps):
                    document = feed.merged(state.document) if feed else state.document
                    live.update(frame(document, state.ticks_per_s(),
                                      source=_source(status_topic, state.received, feed)),
                                refresh=True)
                    state.fresh, last_draw = False, now
                    state.drawn += 1
                if done:
                    ending = "the mission is over"
                    break
                if state.document is None and now - started > wait_s:
                    break
                if state.document is not None and node.count_publishers(status_topic) == 0:
                    gone_since = gone_since or now
                    if now - gone_since > GONE_GRACE_S:
                        ending = "the runner has gone"
                        break
                else:
                    gone_since = None
    finally:
        if feed is not None:
            feed.close(executor)
        executor.shutdown(timeout_sec=0.0)
        node.destroy_node()
        rclpy.try_shutdown()
        stop.restore()
    if stop:
        return EXIT_INTERRUPTED
    if state.document is None:
        console.print(f"sar-tree watch: no mission ticked on {status_topic} within "
                      f"{wait_s:g} s (ROS_DOMAIN_ID={_domain()}); start one with sar-tree run "
                      "or ros2 launch on the same domain", highlight=False)
        return EXIT_NO_MISSION
    elapsed = max(time.monotonic() - state.first_s, 1e-9)
    console.print(f"sar-tree watch: {ending}; {state.received} ticks seen, {state.drawn} "
                  f"frames drawn ({state.drawn / elapsed:.1f} frames/s)", highlight=False)
    return EXIT_OK


def _drain(executor: Any, enough: Callable[[], bool]) -> None:
    """Run the callbacks already waiting (messages received), until ``enough()``."""
    for _ in range(DRAIN_MAX):
        if enough():
            return
        executor.spin_once(timeout_sec=0.0)


def _source(status_topic: str, received: int, feed: SnapshotFeed | None) -> str:
    if feed is None or not feed.topic:
        return f"{status_topic}, {received} ticks seen"
    return f"{status_topic} + py_trees_ros snapshots on {feed.topic}, {received} ticks seen"


def _domain() -> str:
    return os.environ.get("ROS_DOMAIN_ID", "0") or "0"


def watch_command(args: argparse.Namespace) -> int:
    """``sar-tree watch``: return the exit code."""
    if not args.wait > 0 or not args.fps > 0:
        sys.stderr.write("sar-tree watch: error: --wait and --fps must be positive\n")
        return 2
    return watch(args.wait, args.fps, namespace=args.namespace)
