"""Scripted leaves: the same tree ticked by py_trees (our loader) and by BehaviorTree.CPP.

A *script* maps a leaf's name to the statuses its successive visits return (the last one
repeats; a leaf without an entry returns SUCCESS), exactly as the C++ checker
(``btcpp_checker/main.cpp``) reads it. Both sides print one transcript format::

    visit NAME STATUS      (every leaf tick)
    halt NAME              (a running leaf halted; only when asked for)
    tick N STATUS          (the root, after each tick)
"""

from __future__ import annotations

import subprocess
from collections.abc import Collection, Iterable
from pathlib import Path

import py_trees
from py_trees.common import Status
from sar_plugins.nav2.robot_context import ROBOT_POSE_KEY, ROBOT_SPEED_KEY

from sar_framework.engine.api import LoadedTree, load_spec, load_tree
from sar_framework.engine.building.control_build import CLOCK_KEY
from sar_framework.engine.nodes.skipping import was_skipped
from sar_framework.engine.plugin import PluginSpec, leaf
from sar_framework.engine.registry import Registry
from sar_framework.interop.btcpp_export import export_btcpp

Script = dict[str, list[str]]


class ScriptState:
    """The script plus the visits made so far and the transcript."""

    def __init__(self, script: Script, *, halts: bool = False) -> None:
        self.script = script
        self.halts = halts
        self.visits: dict[str, int] = {}
        self.lines: list[str] = []

    def next(self, name: str) -> Status:
        results = self.script.get(name) or ["SUCCESS"]
        index = self.visits.get(name, 0)
        self.visits[name] = index + 1
        status = Status[results[min(index, len(results) - 1)]]
        self.lines.append(f"visit {name} {status.name}")
        return status


class ScriptedLeaf(py_trees.behaviour.Behaviour):
    """A leaf whose every update returns the script's next status for its name."""

    state: ScriptState | None = None

    def __init__(self, name: str, **_params: object) -> None:
        super().__init__(name)

    def update(self) -> Status:
        assert ScriptedLeaf.state is not None, "no script set"
        return ScriptedLeaf.state.next(self.name)

    def terminate(self, new_status: Status) -> None:
        state = ScriptedLeaf.state
        if (new_status == Status.INVALID and self.status == Status.RUNNING
                and state is not None and state.halts):
            state.lines.append(f"halt {self.name}")


def scripted_registry(plugins: Iterable[PluginSpec]) -> Registry:
    """A registry with a scripted leaf for each plugin: same name, params, context, ports.

    A registry's controls and decorators (Nav2's...) are kept as they are.
    """
    registry = Registry()
    for kind in plugins.kind_plugins() if isinstance(plugins, Registry) else ():
        registry.add(kind.cls, kind.source)
    for plugin in plugins:
        cls = type(plugin.name, (ScriptedLeaf,), {"__module__": __name__})
        leaf(plugin.name, params=plugin.params, context=plugin.context,
             description=plugin.description, ports=plugin.ports)(cls)
        registry.add(cls, "scripted")
    assert registry.diagnostics == [], registry.diagnostics
    return registry


class StepClock:
    """A clock that moves ``step`` seconds each time :meth:`advance` is called."""

    def __init__(self, step: float) -> None:
        self.step = step
        self.now = 0.0

    def __call__(self) -> float:
        return self.now

    def advance(self) -> None:
        self.now += self.step


def load_scripted(tree: Path, registry: Registry, *, tick_seconds: float = 0.0,
                  speed: float | None = None) -> tuple[LoadedTree, StepClock]:
    """Load ``tree`` with ``registry`` on a cleared blackboard; return it and its clock.

    With ``tick_seconds`` the tree's clock is the returned one; with ``speed`` (m/s) the
    robot context has a robot moving along x at that speed on it (see :func:`run_py_trees`).
    """
    context: dict[str, object] = {key: None for plugin in registry for key in plugin.context}
    clock = StepClock(tick_seconds)
    if tick_seconds:
        context[CLOCK_KEY] = clock
    if speed is not None:
        context[ROBOT_POSE_KEY] = lambda _frame, _base: (speed * clock.now, 0.0)
        context[ROBOT_SPEED_KEY] = lambda: speed
    py_trees.blackboard.Blackboard.clear()
    return load_tree(tree, context, registry=registry), clock


def run_py_trees(tree: Path, registry: Registry, script: Script, max_ticks: int,
                 *, all_ticks: bool = False, tick_seconds: float = 0.0,
                 halts: bool = False, speed: float | None = None,
                 goal_ticks: Collection[int] = ()) -> list[str]:
    """Load ``tree`` with ``registry`` (our loader) and tick it; return the transcript.

    Ticking stops when the root finishes, or, with ``all_ticks``, after ``max_ticks``.
    With ``tick_seconds``, the tree's clock advances that much after each tick; with
    ``halts``, halting a running leaf adds ``halt NAME``. The
    blackboard is cleared first; a root that returns SKIPPED is reported SKIPPED. With
    ``speed`` (m/s), the robot context has a robot moving along x at that speed on the
    tree's clock (pose ``(speed * now, 0)``), as the checker's ``speed=`` option does.
    Before each tick in ``goal_ticks``, the root entry ``goal`` is set to ``"goal N"``
    (the checker's ``goals=`` option).
    """
    loaded, clock = load_scripted(tree, registry, tick_seconds=tick_seconds, speed=speed)
    state = ScriptedLeaf.state = ScriptState(script, halts=halts)
    try:
        for tick in range(1, max_ticks + 1):
            if tick in goal_ticks:
                py_trees.blackboard.Blackboard.set("/goal", f"goal {tick}")
            loaded.root.tick_once()
            shown = "SKIPPED" if was_skipped(loaded.root) else loaded.root.status.name
            state.lines.append(f"tick {tick} {shown}")
            clock.advance()
            if loaded.root.status != Status.RUNNING and not all_ticks:
                break
    finally:
        ScriptedLeaf.state = None
    return state.lines


def run_checker(checker: Path, xml: Path, script: Script, max_ticks: int,
                *, all_ticks: bool = False, tick_seconds: float = 0.0, sleeps: bool = True,
                halts: bool = False, speed: float | None = None,
                goal_ticks: Collection[int] = ()) -> list[str]:
    """Run the BT.CPP checker on ``xml``; return its transcript (after the models line).

    ``tick_seconds`` is the time between ticks on the Nav2 stand-ins' clock; with ``sleeps``
    the checker also sleeps it after each tick (BT.CPP's own Delay, Timeout and Sleep read
    the wall clock).
    """
    clock = "sleep" if sleeps else "clock"
    script_file = xml.with_suffix(".script")
    script_file.write_text("".join(f"{name} {' '.join(s)}\n" for name, s in script.items()))
    done = subprocess.run([str(checker), str(xml), str(script_file), str(max_ticks),
                           *(["all"] if all_ticks else []), *(["halts"] if halts else []),
                           *([f"{clock}={round(tick_seconds * 1000)}"] if tick_seconds else []),
                           *([f"speed={speed!r}"] if speed is not None else []),
                           *([f"goals={','.join(map(str, goal_ticks))}"] if goal_ticks else [])],
                          capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 0, f"BT.CPP refused {xml}:\n{done.stderr}\n{xml.read_text()}"
    lines = done.stdout.splitlines()
    assert lines[0].startswith("models "), lines
    return lines[1:]


def visits_and_result(lines: list[str]) -> list[str]:
    """The leaf visits and the last root status (tick counts left out)."""
    return [line for line in lines if line.startswith("visit ")] + [lines[-1].split()[-1]]


def compare(tree: Path, registry: Registry, checker: Path, script: Script,
            *, max_ticks: int = 40, exact_ticks: bool = True, all_ticks: bool = False,
            export_from: Path | None = None, tick_seconds: float = 0.0, sleeps: bool = True,
            halts: bool = False, speed: float | None = None,
                 goal_ticks: Collection[int] = ()) -> list[str]:
    """Export ``tree``, tick it on both sides, assert the transcripts match; return ours.

    ``export_from`` is the file to export when ``tree`` is a copy without local plugins;
    ``tick_seconds`` is the time between ticks (simulated here; slept by the checker when
    ``sleeps``, see :func:`run_checker`);
    ``speed`` gives both sides a robot moving at that speed, ``goal_ticks`` the ticks
    before which a new goal is set (see :func:`run_py_trees`).
    """
    spec = load_spec(export_from or tree, registry=registry)
    xml = tree.with_suffix(".xml")
    xml.write_text(export_btcpp(spec, registry))
    scripted = scripted_registry(registry)
    ours = run_py_trees(tree, scripted, script, max_ticks, all_ticks=all_ticks,
                        tick_seconds=tick_seconds, halts=halts, speed=speed,
                        goal_ticks=goal_ticks)
    theirs = run_checker(checker, xml, script, max_ticks, all_ticks=all_ticks,
                         tick_seconds=tick_seconds, sleeps=sleeps, halts=halts, speed=speed,
                         goal_ticks=goal_ticks)
    if exact_ticks:
        assert theirs == ours
    else:
        assert visits_and_result(theirs) == visits_and_result(ours)
    return ours
