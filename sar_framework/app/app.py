"""The :class:`App` contract: one mission's additions to the core, as plain callables.

Every hook is optional; an app that leaves one out adds nothing there. No ROS is imported
here: the runner-side hook receives the runner's node, the others plain data.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from rclpy.node import Node

    from sar_framework.engine.param import Param
    from sar_framework.events.emitter import EventEmitter
    from sar_framework.events.event import MissionEvent
    from sar_framework.mission.params_file import KeyLocation, ParamsError
    from sar_framework.mission.processes import MissionSettings, ParamValue, Process, Robot


@dataclass(frozen=True)
class ServiceCall:
    """One call of a service, as a recording holds it (its request and its answer).

    Attributes:
        request: The request message.
        response: The answer message.
        stamp_s: When the server answered (its clock, seconds).
    """

    request: Any
    response: Any
    stamp_s: float


@dataclass
class AppRun:
    """What an app gives the runner once its parameters are read.

    Attributes:
        context: Context objects by the names leaves declare (``load_tree(context=...)``).
        observe: Wires the app's own events to the runner's emitter (called once).
        status: The app's fields of the tree status, as they are now (JSON-ready).
    """

    context: dict[str, Any] = field(default_factory=dict)
    observe: Callable[[EventEmitter], None] | None = None
    status: Callable[[], Mapping[str, Any]] | None = None


@dataclass(frozen=True)
class AppProcess:
    """A process an app starts, as the core's command line and docs name it.

    Attributes:
        label: Its label (``detect``): ``sar-tree run --detect-param NAME:=VALUE`` sets its
            parameters, its log file is ``detect.log``.
        title: What it is, in help texts and docs (``the detect server``).
        parameters: Its node's parameter table (checks of ``--LABEL-param``, the docs).
        declared_in: The module declaring that table (the parameter docs).
        off_flag: ``sar-tree run``'s flag that leaves it out (``--no-detect-server``), or "".
        off_help: That flag's help.
        per_robot: A fleet starts one per robot (in the robot's namespace), else one in all.
        executable: Its installed program, for the docs of a process that only some runs
            start (the others' come from the process description); "" when it has none.
    """

    label: str
    title: str
    parameters: tuple[Param, ...] = ()
    declared_in: str = ""
    off_flag: str = ""
    off_help: str = ""
    per_robot: bool = False
    executable: str = ""


@dataclass(frozen=True)
class AppOption:
    """A file option of ``sar-tree run`` that sets one parameter of an app's process.

    Attributes:
        flag: The option (``--table``).
        process: The process's label (``detect``).
        parameter: The parameter it sets (``table_file``).
        what: The file in messages (``item table``): "item table not found: ...".
        help: Its help.
        check: ``check(path) -> problem or None``: the file's contents checked before the run.
    """

    flag: str
    process: str
    parameter: str
    what: str
    help: str = ""
    check: Callable[[str], str | None] | None = None


@dataclass(frozen=True)
class App:
    """One mission's additions to the core, registered like plugins.

    Attributes:
        name: Short name (``sar``), used in messages.
        provides: The context objects it provides; a tree uses the app when one of its
            leaves needs one of them.
        parameters: The runner parameters it reads (checked with the runner's own).
        params_file: The mission parameter file to use when ``sar-tree run`` names none
            (a callable: it may depend on the working folder).
        check: Whole-file checks of the runner's parameter values (beyond each value's
            type): ``check(values, locations, file) -> errors``.
        start: Runner side: reads its parameters from the runner's node and returns its
            context objects: ``start(node, source, locations) -> AppRun``.
        processes: The processes it needs beside the runner, in start order.
        process_kinds: What the core's command line, checks and docs know of those processes
            (their labels, parameter tables, flags).
        options: ``sar-tree run`` options that set a parameter of one of them to a file.
        places: Its named places in the run's parameters, name -> ``(x, y)`` in the map
            frame (the simulator's area faults may name them).
        recorded_topics: ``(topic, type)`` pairs a recording keeps beside the core's (its
            services' ``_service_event`` topics).
        run_files: The files its processes write in the run's folder (``reports.jsonl``):
            removed before a run, rebuilt by a replay.
        replayed: Rebuilds those files from a recording: ``replayed(calls, folder)``, with
            ``calls`` each recorded service's :class:`ServiceCall` list by its
            ``_service_event`` topic.
        event_kinds: Its event kinds, each with what it means.
        progress: One progress line for one of its events, or None (``sar-tree run``).
        summary: Its words in ``sar-tree run``'s summary line, from ``mission.json``
            (an app's words replace the core's list of goals).
        report: Its keys of ``mission.json``: ``report(inputs, events, document) -> dict``
            ({} when the run has nothing of the app).
        layout: Its places and base in a parameter file, as the studio draws them:
            ``layout(params_file) -> {"places": [{"id", "x", "y"}...], "base": {"x", "y"}}``
            (places in the order the mission takes them).
        marks: Its event kinds that mark the studio's timeline, and the mark: ``reached``
            (a place), ``found`` (something found) or ``failure``.
        frame: Its keys of a studio frame, from the events so far: ``reached`` (the ids of
            the places reached) and ``found`` (``[{"id", "position"}]``).
        status_text: Its words in a status line (``sar-tree watch``, the studio's header),
            from a tree status document ("" when it has none).
        figure: Draws its part of ``mission.png``: ``figure(canvas, document)`` returns a
            :class:`~sar_framework.report_map.MapLayer` (its title, legend and lines), or
            None when ``mission.json`` has nothing of it.
        robot_parameters: A robot's own runner parameters beside its spawn pose:
            ``robot_parameters(settings, robot, index) -> {name: value}`` (named robots).
        spawn_around: Where ``--robots N`` spawns its robots, from the runner's parameter
            values: ``spawn_around(values) -> (centre, places)``, near ``centre`` and off
            the ways from it to ``places`` (default: ``initial_pose``, no places).
        fleet_report: Its part of a run of named robots' ``fleet.json``:
            ``fleet_report(settings, summaries) -> (keys, problems)`` from each robot's
            ``mission.json``; ``keys["robots"][name]`` joins that robot's entry, each
            problem fails the run.
        fleet_figure: Draws its part of ``fleet.png``: ``fleet_figure(canvas, document,
            run_folder, colours)`` (robot name -> colour) returns a
            :class:`~sar_framework.report_map.MapLayer`, or None.
    """

    name: str
    provides: tuple[str, ...] = ()
    parameters: tuple[Param, ...] = ()
    params_file: Callable[[], str] | None = None
    check: Callable[[Mapping[str, Any], Mapping[str, KeyLocation], str],
                    list[ParamsError]] | None = None
    start: Callable[[Node, str, Mapping[str, KeyLocation]], AppRun] | None = None
    processes: Callable[[MissionSettings], list[Process]] | None = None
    process_kinds: tuple[AppProcess, ...] = ()
    options: tuple[AppOption, ...] = ()
    places: Callable[[Mapping[str, Any]], dict[str, tuple[float, float]]] | None = None
    recorded_topics: tuple[tuple[str, str], ...] = ()
    run_files: tuple[str, ...] = ()
    replayed: Callable[[Mapping[str, Sequence[ServiceCall]], Path], None] | None = None
    event_kinds: Mapping[str, str] = field(default_factory=dict)
    progress: Callable[[MissionEvent], str | None] | None = None
    summary: Callable[[Mapping[str, Any]], list[str]] | None = None
    report: Callable[[Any, Sequence[MissionEvent], dict[str, Any]],
                     dict[str, Any]] | None = None
    layout: Callable[[str], dict[str, Any]] | None = None
    marks: Mapping[str, str] = field(default_factory=dict)
    frame: Callable[[Sequence[MissionEvent]], dict[str, Any]] | None = None
    status_text: Callable[[Mapping[str, Any]], str] | None = None
    figure: Callable[[Any, dict[str, Any]], Any] | None = None
    robot_parameters: Callable[[MissionSettings, Robot, int],
                               Mapping[str, ParamValue]] | None = None
    spawn_around: Callable[[Mapping[str, Any]], tuple[tuple[float, float],
                                                      list[tuple[float, float]]]] | None = None
    fleet_report: Callable[[MissionSettings, Mapping[str, dict[str, Any]]],
                           tuple[dict[str, Any], list[str]]] | None = None
    fleet_figure: Callable[[Any, dict[str, Any], Path, Mapping[str, Any]], Any] | None = None

    def default_params_file(self) -> str:
        """Its parameter file when none is named, or "" (it then needs none)."""
        return self.params_file() if self.params_file is not None else ""


def checkout_file(relative: str, anchor: Path) -> str:
    """``relative`` as given when the working folder has it, else the checkout's copy.

    Args:
        relative: A path relative to the checkout (``config/mission_params.yaml``).
        anchor: The checkout's root.

    Returns:
        The path to use (``relative`` itself when neither exists).
    """
    if not Path(relative).exists() and (anchor / relative).exists():
        return str(anchor / relative)
    return relative
