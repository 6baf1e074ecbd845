"""A fleet mission over real DDS for the coordinator's tests: processes and their events.

One simulator with three robots, the base's report server, the zone coordinator, and per
robot a detect server and a runner of trees/fleet_search.yaml in its namespace. Each robot's
home is its spawn pose (``base_station`` per runner), so three robots never queue for one
base. :func:`run_fleet` returns the coordinator's events (its JSON Lines file) and each
runner's exit code.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from sar_testing.netns import NetworkLab
from sar_testing.processes import NodeProcess

REPO = Path(__file__).resolve().parents[2]
SPEED = 30.0
# Room corners away from the doorways near the origin and from the paths to the zones: a
# robot parked at home must not stand where the others pass.
SPAWNS = {"robot1": (4.5, 1.0, 0.0), "robot2": (-4.5, 1.0, 0.0), "robot3": (-4.5, -1.0, 0.0)}
ZONES = ("zone_a", "zone_b", "zone_c", "zone_d")
ROBOT_TIMEOUT_WALL_S = 2.0

#: Fast DDS over UDP only: a process SIGKILLed while it creates a shared-memory port leaves
#: a half-made /dev/shm/fastrtps_port* on which the next process of the domain hangs.
UDP_ONLY = {"FASTDDS_BUILTIN_TRANSPORTS": "UDPv4"}

Killer = Callable[[list[dict[str, Any]], dict[str, str]], "str | None"]
"""``(events so far, runner outputs) -> the robot to kill now, or None``."""


@dataclass
class FleetRun:
    """What a fleet mission left: the coordinator's events and the runners' exit codes."""

    events: list[dict[str, Any]]
    codes: dict[str, int | None]
    outputs: str
    victims: list[str | None] = field(default_factory=list)
    reports: list[dict[str, Any]] | None = None

    @property
    def victim(self) -> str | None:
        """The robot the first killer named (None if it never did)."""
        return self.victims[0] if self.victims else None

    def kinds(self, kind: str) -> list[dict[str, Any]]:
        """The events of one kind, in order."""
        return [e for e in self.events if e["kind"] == kind]

    def searched(self) -> dict[str, list[str]]:
        """Zone -> the robots that searched it."""
        out: dict[str, list[str]] = {}
        for event in self.kinds("searched"):
            out.setdefault(event["zone_id"], []).append(event["robot"])
        return out


def read_events(path: Path) -> list[dict[str, Any]]:
    """A JSON Lines file (the coordinator's events, the base's reports), one object per line.

    Empty before the file exists.
    """
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines()
            if line.strip()]


def run_fleet(tmp: Path, *, sim_params: Sequence[str] = (), detect_params: Sequence[str] = (),
              kill: Killer | Sequence[Killer] = (), timeout_s: float = 90.0,
              lab: NetworkLab | None = None, robots: Sequence[str] = tuple(SPAWNS)
              ) -> FleetRun:
    """Run the fleet mission to its end; each killer may name a runner to SIGKILL.

    Args:
        tmp: Folder for logs and files.
        sim_params: Extra ``-p`` settings of the simulator (its faults).
        detect_params: Extra ``-p`` settings of every detect server.
        kill: One killer or several. Each is called with the events so far and each live
            runner's output while the mission runs, until it names a robot; that runner is
            killed with SIGKILL. Each kills at most once, and never a robot already killed.
        timeout_s: Outer safety bound of the mission, wall seconds.
        lab: Run the root namespace's processes on its host ``world`` and each robot's on
            the host of its name (hosts of their own), instead of on this machine.
        robots: The robots to run, of :data:`SPAWNS` (all three unless a test needs fewer).
    """
    import signal

    fleet = tmp / "fleet.yaml"
    fleet.write_text("robots:\n" + "".join(
        f"  - name: {n}\n    pose: {{x: {x}, y: {y}, yaw: {w}}}\n"
        for n, (x, y, w) in SPAWNS.items() if n in robots), encoding="utf-8")
    events_file = tmp / "events.jsonl"
    params = str(REPO / "config" / "mission_params.yaml")
    tree = str(REPO / "trees" / "fleet_search.yaml")
    procs: list[NodeProcess] = []
    runners: dict[str, NodeProcess] = {}

    def start(args: list[str], label: str, host: str = "world") -> NodeProcess:
        where = {"prefix": lab.enter(host), "env": {**UDP_ONLY, **lab.ros_env(host)}} \
            if lab is not None else {"env": UDP_ONLY}
        proc = NodeProcess(["-m", *args], label, log_dir=tmp, **where).start()
        procs.append(proc)
        return proc

    try:
        sim = start(["sar_framework.sim", "--ros-args", "-p", f"speed:={SPEED}",
                     "-p", f"fleet_file:={fleet}", *sim_params], "sim")
        start(["sar_plugins.sar.servers.report_survivor_server", "--ros-args",
               "-p", f"report_file:={tmp / 'reports.jsonl'}"], "report")
        coordinator = start(["sar_plugins.sar.fleet.coordinator_node", "--ros-args",
                             "--params-file", params, "-p", f"events_file:={events_file}",
                             "-p", f"robot_timeout_wall_s:={ROBOT_TIMEOUT_WALL_S}"], "coordinator")
        sim.wait_for_output("ready", timeout=30)
        coordinator.wait_for_output("ready", timeout=30)
        for name in robots:
            x, y, yaw = SPAWNS[name]
            start(["sar_plugins.sar.servers.detect_survivor_server", "--ros-args",
                   "-r", f"__ns:=/{name}", *detect_params], f"detect_{name}", name)
            runners[name] = start([
                "sar_framework.runner.node", "--ros-args", "-r", f"__ns:=/{name}",
                "--params-file", params, "-p", f"tree:={tree}",
                "-p", f"initial_pose.x:={x}", "-p", f"initial_pose.y:={y}",
                "-p", f"initial_pose.yaw:={yaw}", "-p", f"base_station.x:={x}",
                "-p", f"base_station.y:={y}", "-p", f"base_station.yaw:={yaw}",
                "-p", "exit_on_completion:=true", "-p", "tick_rate_hz:=10.0"], f"runner_{name}",
                name)
        killers = [kill] if callable(kill) else list(kill)
        victims: list[str | None] = [None] * len(killers)
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:  # outer safety bound
            if None in victims:  # the events file read once a turn, for every killer
                events = read_events(events_file)
            for index, killer in enumerate(killers):
                if victims[index] is None:
                    live = {n: r.output for n, r in runners.items() if n not in victims}
                    victims[index] = killer(events, live)
                    if victims[index] is not None:
                        runners[victims[index]].signal(signal.SIGKILL)
            if all(r.poll() is not None for r in runners.values()):
                break
            time.sleep(0.05)
        codes = {name: r.poll() for name, r in runners.items()}
    finally:
        for proc in reversed(procs):
            proc.stop()
    outputs = "\n".join(f"--- {p.label}\n{p.output[-4000:]}" for p in procs)
    return FleetRun(read_events(events_file), codes, outputs, victims,
                    read_events(tmp / "reports.jsonl"))


TWO_ZONES = """\
/**:
  ros__parameters:
    zone_order: ["zone_a", "zone_b"]
    zones:
      zone_a: {x: -3.0, y: 3.0, yaw: 0.0}
      zone_b: {x: 3.5, y: 3.0, yaw: 1.57}
"""
"""A mission parameter file of two zones, for the coordinator's own tests."""


def two_zone_coordinator(tmp: Path, *extra: str) -> NodeProcess:
    """The coordinator over :data:`TWO_ZONES` (not started), with extra ``--ros-args``."""
    params = tmp / "mission.yaml"
    params.write_text(TWO_ZONES, encoding="utf-8")
    return NodeProcess(["-m", "sar_plugins.sar.fleet.coordinator_node", "--ros-args",
                        "--params-file", str(params), *extra], "coordinator", log_dir=tmp)
