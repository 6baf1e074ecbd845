"""The tutorials (docs/tutorials/) show real commands with their real output.

Convention (docs/tutorials/README.md, "How the tutorials stay true"): a fenced block
tagged ``console`` is checked. In it, ``$ CMD`` starts a command and the lines up to the
next ``$`` are its expected output (stdout and stderr together); a line ``...`` stands
for any number of lines. ``$ echo $?`` shows the previous command's exit code. Only
commands that need no ROS may appear in a console block (``sar-tree validate``,
``render``, ``plugins``, ``schema`` and ``python trees/tutorials/tick.py``); output of
commands that start ROS (``sar-tree run``) is shown in ``text`` blocks and is not
checked. ``render -o`` writes into a temporary directory instead of docs/tutorials/img/.
Each command runs in a process of its own, forked from one that has imported the libraries
the commands share (see :data:`FORK_SERVER`).
"""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import py_trees
import pytest
from py_trees.common import Status

REPO = Path(__file__).resolve().parents[2]
TUTORIALS = REPO / "docs" / "tutorials"
TREES = REPO / "trees" / "tutorials"
BROKEN = sorted((TUTORIALS / "broken").glob("*.yaml"))
DOCS = sorted(TUTORIALS.glob("[0-9][0-9]_*.md"))
FENCE = re.compile(r"^```console\n(.*?)^```", re.MULTILINE | re.DOTALL)
NO_ROS = {"validate", "render", "plugins", "schema"}


@dataclass(frozen=True)
class Shown:
    """One command shown in a tutorial and the output shown under it."""

    doc: str
    line: int
    command: str
    expected: tuple[str, ...]

    @property
    def label(self) -> str:
        return f"{self.doc}:{self.line}"


def shown_commands(doc: Path) -> list[Shown]:
    """Every ``$ ...`` command of every console block in ``doc``, in order."""
    text = doc.read_text()
    found: list[Shown] = []
    for block in FENCE.finditer(text):
        first_line = text.count("\n", 0, block.start(1)) + 1
        current: list[str] | None = None
        for offset, line in enumerate(block.group(1).splitlines()):
            if line.startswith("$ "):
                current = []
                found.append(Shown(doc.name, first_line + offset, line[2:], ()))
            elif current is not None:
                last = found[-1]
                found[-1] = Shown(last.doc, last.line, last.command, (*last.expected, line))
            else:
                raise AssertionError(f"{doc.name}:{first_line + offset}: output before any $")
    return found


ALL = [shown for doc in DOCS for shown in shown_commands(doc)]
RUN = [shown for shown in ALL if shown.command != "echo $?"]


def matches(expected: tuple[str, ...], actual: list[str]) -> bool:
    """Whether ``actual`` matches ``expected``, where a ``...`` line matches any lines."""
    if not expected:
        return not actual
    head, *rest = expected
    if head == "...":
        return any(matches(tuple(rest), actual[i:]) for i in range(len(actual) + 1))
    return bool(actual) and actual[0] == head and matches(tuple(rest), actual[1:])


def sar_tree() -> Path:
    """The ``sar-tree`` script of this interpreter's environment."""
    script = Path(sys.executable).parent / "sar-tree"
    assert script.exists(), f"no sar-tree script beside {sys.executable}"
    return script


#: A process that has imported what the shown commands import, then runs each command in a
#: fork of itself: a fresh process per command (its own state, its own exit code, stdout and
#: stderr into files), without paying the imports again for each. Protocol: one JSON line
#: ``[script, argv, out, err]`` in (``err`` may be ``out``), one line with the exit code out.
FORK_SERVER = """
import atexit, json, os, runpy, sys, traceback
import py_trees, jsonschema, yaml
import sar_framework.cli, sar_framework.engine.api
sys.stdout.flush()
for line in sys.stdin:
    script, argv, out, err = json.loads(line)
    pid = os.fork()
    if pid == 0:
        fd = os.open(out, os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
        os.dup2(fd, 1)
        os.dup2(fd if err == out else os.open(err, os.O_WRONLY | os.O_CREAT | os.O_TRUNC), 2)
        sys.argv = [script, *argv]
        sys.path[0] = os.path.dirname(os.path.abspath(script))
        try:
            runpy.run_path(script, run_name="__main__")
            code = 0
        except SystemExit as end:
            code = end.code if isinstance(end.code, int) else (end.code is not None)
            if end.code is not None and not isinstance(end.code, int):
                print(end.code, file=sys.stderr)
        except BaseException:
            traceback.print_exc()
            code = 1
        atexit._run_exitfuncs()
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(int(code))
    _, status = os.waitpid(pid, 0)
    print(os.waitstatus_to_exitcode(status), flush=True)
"""


@pytest.fixture(scope="module")
def fork_server() -> Iterator[subprocess.Popen[str]]:
    """The :data:`FORK_SERVER`, started from the repository root as the shell would run."""
    env = {**os.environ, "COLUMNS": "80", "PYTHONDONTWRITEBYTECODE": "1"}
    with subprocess.Popen([sys.executable, "-c", FORK_SERVER], cwd=REPO, env=env, text=True,
                          stdin=subprocess.PIPE, stdout=subprocess.PIPE) as server:
        yield server
        server.stdin.close()


def run_shown(shown: Shown, tmp_path: Path,
              server: subprocess.Popen[str]) -> tuple[int, list[str]]:
    """Run one shown command from the repository root; return its code and output lines."""
    argv = shlex.split(shown.command)
    rewrites: dict[str, str] = {}
    if argv[0] == "sar-tree":
        assert len(argv) > 1 and argv[1] in NO_ROS, (
            f"{shown.label}: only {sorted(NO_ROS)} may be shown in a checked console block "
            f"(use a text block for commands that start ROS): {shown.command}")
        if "-o" in argv:
            index = argv.index("-o") + 1
            target = tmp_path / Path(argv[index]).name
            rewrites[str(target)] = argv[index]
            argv[index] = str(target)
        script, args = str(sar_tree()), argv[1:]
    elif argv[:2] == ["python", "trees/tutorials/tick.py"]:
        script, args = argv[1], argv[2:]
    else:
        pytest.fail(f"{shown.label}: not a checked command: {shown.command}")
    out = tmp_path / "output.txt"
    code = fork_run(server, script, args, out)
    text = out.read_text()
    for real, shown_path in rewrites.items():
        text = text.replace(real, shown_path)
    return code, text.splitlines()


def fork_run(server: subprocess.Popen[str], script: str, args: list[str], out: Path,
             err: Path | None = None) -> int:
    """Run ``script ARGS`` in a fork of the :data:`FORK_SERVER`; its exit code.

    Its stdout goes to ``out``, its stderr to ``err`` (or to ``out`` too).
    """
    assert server.stdin is not None and server.stdout is not None
    server.stdin.write(json.dumps([script, args, str(out), str(err or out)]) + "\n")
    server.stdin.flush()
    answer = server.stdout.readline()
    assert answer, f"{script} {args}: the fork server ended (exit {server.wait(timeout=60)})"
    return int(answer)


def test_there_are_six_to_ten_tutorials_each_with_its_trees() -> None:
    assert 6 <= len(DOCS) <= 10, [d.name for d in DOCS]
    index = (TUTORIALS / "README.md").read_text()
    for doc in DOCS:
        number = doc.name[:2]
        assert f"({doc.name})" in index, f"docs/tutorials/README.md does not link {doc.name}"
        if number in ("08", "10"):
            continue  # the simulator runs use the repository's examples
        trees = sorted(TREES.glob(f"{number}_*.yaml"))
        assert trees, f"no trees/tutorials/{number}_*.yaml for {doc.name}"
        text = doc.read_text()
        for tree in trees:
            assert f"trees/tutorials/{tree.name}" in text, f"{doc.name} never shows {tree.name}"


@pytest.mark.parametrize("path", sorted(TREES.rglob("*.yaml")),
                         ids=lambda p: str(p.relative_to(REPO)))
def test_every_tutorial_tree_validates(path: Path) -> None:
    from sar_framework.engine.api import validate

    result = validate(path)
    assert [str(d) for d in result.diagnostics] == []


def test_every_checked_block_has_commands() -> None:
    assert len(ALL) >= 20
    for doc in DOCS:
        if doc.name.startswith("08"):
            continue
        assert shown_commands(doc), f"{doc.name} shows no checked command"


@pytest.mark.parametrize("shown", RUN, ids=[s.label for s in RUN])
def test_shown_command_prints_the_shown_output(shown: Shown, tmp_path: Path,
                                               fork_server: subprocess.Popen[str]) -> None:
    code, actual = run_shown(shown, tmp_path, fork_server)
    expected = shown.expected
    position = ALL.index(shown)
    if position + 1 < len(ALL) and ALL[position + 1].command == "echo $?" \
            and ALL[position + 1].doc == shown.doc:  # `$ echo $?` shows this exit code
        assert list(ALL[position + 1].expected) == [str(code)], shown.label
    else:
        assert code == 0, f"{shown.label}: exit {code}\n" + "\n".join(actual)
    assert matches(expected, actual), (
        f"{shown.label}: `{shown.command}` printed\n" + "\n".join(actual)
        + "\n--- but the tutorial shows ---\n" + "\n".join(expected))
    if "-o" in shown.command:
        written = tmp_path / Path(shlex.split(shown.command)[-1]).name
        assert written.stat().st_size > 0
        assert (REPO / shlex.split(shown.command)[-1]).exists(), "the image is not committed"


@pytest.mark.parametrize("broken", BROKEN, ids=lambda p: p.name)
def test_broken_tree_diagnostics_equal_the_tutorial(broken: Path) -> None:
    from sar_framework.engine.api import validate

    result = validate(broken)
    assert not result.ok
    shown = next(s for s in ALL if s.command == f"sar-tree validate {broken.relative_to(REPO)}")
    diagnostics = [str(d).replace(f"{REPO}/", "") for d in result.diagnostics]
    assert len(diagnostics) >= 4
    assert list(shown.expected) == [*diagnostics, f"{len(diagnostics)} errors"]


def test_images_in_the_tutorials_exist_and_are_small() -> None:
    for doc in [*DOCS, TUTORIALS / "README.md"]:
        for target in re.findall(r"!\[[^\]]*\]\(([^)]+)\)", doc.read_text()):
            image = (doc.parent / target).resolve()
            assert image.is_file(), f"{doc.name}: missing image {target}"
            assert image.stat().st_size < 200_000, f"{target} is larger than 200 kB"


def load_tutorial_leaves() -> dict[str, type]:
    """The tutorial plugin's classes, imported the way the engine imports local files."""
    from sar_framework.engine.registry import discover

    registry = discover(entry_points=False,
                        plugin_paths=[TREES / "plugins" / "tutorial_leaves.py"])
    return {name: registry.get(name).cls for name in ("Countdown", "TakeId", "ReportId")}


def test_tutorial_plugin_ticks_to_the_shown_statuses() -> None:
    from sar_plugins.sar.zone_manager import ZoneManager

    leaves = load_tutorial_leaves()
    countdown = leaves["Countdown"]("Wait", ticks=2, result="failure")
    statuses = []
    for _ in range(3):
        countdown.tick_once()
        statuses.append(countdown.status)
    assert statuses == [Status.RUNNING, Status.RUNNING, Status.FAILURE]

    zones = ZoneManager([{"id": "a", "x": 0, "y": 0, "yaw": 0}], {"x": 0, "y": 0, "yaw": 0})
    for memory, ids in ((True, ["survivor_1"]),
                        (False, ["survivor_2", "survivor_3", "survivor_4"])):
        take = leaves["TakeId"]("TakeId", zone_manager=zones)
        report = leaves["ReportId"]("ReportId", taker=take, ticks=2)
        branch = py_trees.composites.Sequence("SurvivorFound", memory=memory,
                                              children=[take, report])
        taken = []
        for _ in range(3):
            branch.tick_once()
            if take.status == Status.SUCCESS and take.taken not in taken:
                taken.append(take.taken)
        assert branch.status == Status.SUCCESS
        assert taken == ids
        assert report.reported == [ids[-1]]


def test_port_leaves_read_and_write_their_entries() -> None:
    from py_trees.blackboard import Blackboard

    from sar_framework.engine.building.port_values import PortValues
    from sar_framework.engine.ports import PortBinding
    from sar_framework.engine.registry import discover

    registry = discover(entry_points=False, plugin_paths=[TREES / "plugins" / "port_leaves.py"])
    drive, scan = registry.get("Drive"), registry.get("Scan")
    ports = {p.name: p for p in (*drive.ports, *scan.ports)}
    Blackboard.clear()
    Blackboard.set("/battery", 30.0)
    leaf = drive.cls("Drive", ports=PortValues("Drive", {
        "zone": PortBinding(ports["zone"], value="zone_a"),
        "cost": PortBinding(ports["cost"], value=25.0),
        "battery": PortBinding(ports["battery"], key="/battery")}))
    statuses = []
    for _ in range(4):
        leaf.tick_once()
        statuses.append(leaf.status)
    assert statuses == [Status.RUNNING, Status.SUCCESS, Status.RUNNING, Status.FAILURE]
    assert Blackboard.get("/battery") == 5.0 and leaf.feedback_message == (
        "5% left, zone_a needs 25%")
    counter = scan.cls("Scan", ports=PortValues("Scan", {
        "zone": PortBinding(ports["zone"], value="b"),
        "sightings": PortBinding(ports["sightings"], value=["a", "b", "b"]),
        "found": PortBinding(ports["found"], key="/found")}))
    counter.tick_once()
    assert counter.status == Status.SUCCESS and Blackboard.get("/found") == 2
    Blackboard.clear()


@pytest.mark.parametrize(("assignment", "message"), [
    ("zome=zone_a", "--set zome=zone_a: the tree declares no entry 'zome'"),
    ("battery=full", "--set battery=full: expected a float, got 'full'"),
])
def test_tick_refuses_a_bad_set(assignment: str, message: str, tmp_path: Path,
                                fork_server: subprocess.Popen[str]) -> None:
    out, err = tmp_path / "stdout.txt", tmp_path / "stderr.txt"
    code = fork_run(fork_server, "trees/tutorials/tick.py",
                    ["trees/tutorials/09_ports_and_blackboard.yaml", "--set", assignment],
                    out, err)
    assert (code, out.read_text(), err.read_text()) == (2, "", f"{message}\n")


def test_tutorial_plugin_imports_without_ros() -> None:
    code = ("import sys, runpy; runpy.run_path('trees/tutorials/plugins/tutorial_leaves.py');"
            "runpy.run_path('trees/tutorials/plugins/port_leaves.py');"
            "runpy.run_path('trees/tutorials/tick.py');"
            "assert 'rclpy' not in sys.modules, 'rclpy imported'")
    subprocess.run([sys.executable, "-c", code], cwd=REPO, check=True, timeout=60)
