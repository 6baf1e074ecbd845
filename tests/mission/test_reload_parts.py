"""The parts of a reload that need no ROS: --reload's parameter, the watched files, the
status writer following a swapped tree, the console and mission.json showing reloads."""

from __future__ import annotations

import argparse
import io
import json
import time
from pathlib import Path

import py_trees
from py_trees.common import Status

from sar_framework.engine.api import load_tree
from sar_framework.engine.registry import discover
from sar_framework.engine.reloading.hot_swap import HotSwap, hot_swap
from sar_framework.events.event import EventKind, MissionEvent
from sar_framework.events.jsonl import EVENTS_FILE, EventFileWriter
from sar_framework.mission.processes import mission_processes
from sar_framework.orchestrate.config import mission_settings
from sar_framework.orchestrate.options import config_from_args, configure
from sar_framework.orchestrate.outcome import Outcome, progress_line, summarise
from sar_framework.runner.reload import signature, tree_files
from sar_framework.runner.status_file import StatusFileWriter

REPO = Path(__file__).resolve().parents[2]
PLUGINS = Path(__file__).resolve().parent / "runner_plugins"


def test_run_reload_sets_the_runners_watch_tree(tmp_path: Path) -> None:
    parser = argparse.ArgumentParser()
    configure(parser)
    for argv, watched in ((["t.yaml"], False), (["t.yaml", "--reload"], True)):
        config = config_from_args(parser.parse_args(argv))
        assert config.reload is watched
        runner = mission_processes(mission_settings(config, tmp_path))[-1]
        assert runner.parameters.get("watch_tree", False) is watched


def test_the_watched_files_are_the_tree_and_its_includes(tmp_path: Path) -> None:
    library = tmp_path / "lib" / "common.yaml"
    library.parent.mkdir()
    library.write_text("format: 1\nsubtrees:\n  step:\n    Countdown: {ticks: 1}\n")
    tree = tmp_path / "tree.yaml"
    tree.write_text("format: 1\ninclude: [lib/common.yaml]\nroot:\n  subtree: step\n")
    files = tree_files(str(tree), (str(PLUGINS),))
    assert sorted(files) == sorted([tree.resolve(), library.resolve()])
    before = signature(files)
    time.sleep(0.01)
    library.write_text(library.read_text() + "# edited\n")
    assert signature(files) != before
    # A file that does not load is still watched (it is the file itself).
    broken = tmp_path / "broken.yaml"
    broken.write_text("format: 1\nroot: [\n")
    assert tree_files(str(broken)) == [broken.resolve()]
    assert signature([tmp_path / "gone.yaml"]) == ((str(tmp_path / "gone.yaml"), -1, -1),)


class Zones:
    """The one thing Countdown asks of the zone manager."""

    def total_zones(self) -> int:
        return 4


STEPS = ("format: 1\nroot:\n  sequence:\n    name: Steps\n    memory: true\n    children:\n"
         "      - Countdown: {name: Work, ticks: 3}\n")


class Ticked:
    """A tree file loaded with the runner's test leaves, a status writer and a ticking tree."""

    def __init__(self, tmp_path: Path, text: str) -> None:
        self.registry = discover([PLUGINS], builtins=False, entry_points=False)
        self.path = tmp_path / "tree.yaml"
        self.path.write_text(text)
        self.context = {"zone_manager": Zones()}
        self.loaded = load_tree(self.path, self.context, registry=self.registry)
        self.writer = StatusFileWriter(str(self.path), self.loaded.spec, self.loaded.behaviours,
                                       lambda: 0.0, completion="once")
        self.tree = py_trees.trees.BehaviourTree(self.loaded.root)

    def swap(self, text: str) -> HotSwap:
        self.path.write_text(text)
        return hot_swap(self.loaded, self.path, self.context, registry=self.registry)


def test_the_status_writer_follows_a_swapped_tree(tmp_path: Path) -> None:
    text = STEPS + "      - Countdown: {name: Last, ticks: 0}\n"
    run = Ticked(tmp_path, text)
    writer, ticking = run.writer, run.tree
    ticking.visitors.append(writer)
    ticking.add_post_tick_handler(writer.after_tick)
    ticking.tick()
    assert writer.running == ["0", "0.0"] and writer.nodes["0.0"] == "RUNNING"
    swap = run.swap(text.replace("      - Countdown: {name: Work",
                                 "      - Countdown: {name: First, ticks: 0}\n"
                                 "      - Countdown: {name: Work"))
    writer.retarget(swap.tree.spec, swap.tree.behaviours, None)
    # Work is 0.1 now: what was noted of it follows it.
    assert writer.running == ["0", "0.1"]
    assert writer.nodes == {"0": "RUNNING", "0.1": "RUNNING"}
    for _ in range(3):  # Work goes on: two more RUNNING ticks, then SUCCESS and Last
        ticking.tick()
    assert writer.complete and writer.status == Status.SUCCESS
    assert [(e["uid"], e["name"]) for e in writer.events] == [("0.1", "Work"), ("0.2", "Last")]
    assert "0.0" not in writer.nodes  # First was added behind the running Work: never ticked


def test_reloads_on_the_console_and_in_the_summary(tmp_path: Path) -> None:
    swapped = MissionEvent(EventKind.TREE_SWAPPED, message="Tree swapped from t.yaml: 2 kept")
    refused = MissionEvent(EventKind.RELOAD_REFUSED,
                           message="Reload of t.yaml refused, the tree goes on: t.yaml:3:1: x")
    assert progress_line(swapped) == swapped.message
    assert progress_line(refused) == refused.message
    from sar_framework.report import MissionInputs
    from sar_framework.report import summarise as mission_json

    writer = EventFileWriter(tmp_path / EVENTS_FILE)
    for seq, event in enumerate((refused, swapped), 1):
        writer(event.numbered(seq))
    writer.close()
    tree = REPO / "trees" / "search_and_rescue.yaml"
    document = mission_json(MissionInputs(tmp_path, str(tree), str(REPO / "config" /
                                                                    "mission_params.yaml"),
                                          None, "SUCCESS", wall_duration_s=1.0))
    assert [(r["what"], r["message"]) for r in document["reloads"]] == [
        ("reload_refused", refused.message), ("tree_swapped", swapped.message)]
    (tmp_path / "mission.json").write_text(json.dumps(document))
    out = io.StringIO()
    summarise(lambda line: out.write(line + "\n"), tmp_path, Outcome("SUCCESS", 0),
              [tmp_path / "mission.json"], None)
    assert "sar-tree run: tree reloads: 1 swapped, 1 refused (mission.json: reloads)" in \
        out.getvalue()


def test_a_rebuilt_root_becomes_the_ticking_trees_root(tmp_path: Path) -> None:
    from sar_framework.events.emitter import EventEmitter
    from sar_framework.runner.reload import follow_swap

    class Publisher:  # stands in for TreeStatusPublisher (a ROS publisher)
        def retarget(self, spec: object, behaviours: object, entries: object) -> None:
            self.followed = (spec, behaviours)

    run = Ticked(tmp_path, STEPS)
    ticking, writer, loaded = run.tree, run.writer, run.loaded
    ticking.tick()
    swap = run.swap(STEPS.replace("memory: true", "memory: false"))
    publisher, events = Publisher(), EventEmitter()
    follow_swap(ticking, swap, status_writer=writer, status_publisher=publisher,  # type: ignore[arg-type]
                events=events)
    assert ticking.root is swap.tree.root is not loaded.root
    assert publisher.followed == (swap.tree.spec, swap.tree.behaviours)
    work = swap.tree.behaviours["0.0"]
    emitted = events.emit(EventKind.STATUS, source=work)
    assert (emitted.node_uid, emitted.node_kind, emitted.node_name) == ("0.0", "Countdown", "Work")
    ticking.tick()
    assert work.status == Status.RUNNING and swap.summary.changed == ("Steps",)


def test_a_save_during_a_reload_is_reloaded_on_the_next_poll(tmp_path: Path) -> None:
    # Regression: the watcher took the files' signature after reloading, so a save made
    # while the refused tree was being read (an editor fixing the error at once) was
    # taken as already seen and never loaded.
    from sar_framework.runner.reload import TreeReloader

    tree = tmp_path / "tree.yaml"
    tree.write_text("format: 1\nroot:\n  Countdown: {ticks: 1}\n")
    reads: list[str] = []
    watcher = object.__new__(TreeReloader)  # the watch logic only: no node, no service
    watcher._tree_file, watcher._plugin_paths = str(tree), (str(PLUGINS),)
    watcher._files = tree_files(str(tree), (str(PLUGINS),))
    watcher._seen, watcher._pending = signature(watcher._files), None

    def reload() -> tuple[bool, str]:
        reads.append(tree.read_text())
        if len(reads) == 1:  # the fix is saved while the first reload runs
            time.sleep(0.01)
            tree.write_text("format: 1\nroot:\n  Countdown: {ticks: 2}\n")
        return False, "refused"

    watcher.reload = reload  # type: ignore[method-assign]
    time.sleep(0.01)
    tree.write_text("format: 1\nroot:\n  Countdown: {ticks: 3}\n")
    for _ in range(6):  # a poll sees the change, the next one (settled) reloads
        watcher._poll()
    assert [text.split()[-1] for text in reads] == ["3}", "2}"]
