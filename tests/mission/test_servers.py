"""The service servers, each in a child process, called over real DDS."""

from __future__ import annotations

import contextlib
import json
import math
import re
import signal
from dataclasses import dataclass
from pathlib import Path

import pytest
from sar_plugins.sar.servers.report_log import ReportLog
from sar_plugins.sar.servers.survivors import (
    DEFAULT_SURVIVORS,
    SurvivorsFileError,
    load_survivors,
)
from sar_testing.processes import NodeProcess
from sar_testing.spin import call_service, ros_node, spin_until

REPO = Path(__file__).resolve().parents[2]
DISCOVERY_S = 15.0
DETECT = ["-m", "sar_plugins.sar.servers.detect_survivor_server"]
REPORT = ["-m", "sar_plugins.sar.servers.report_survivor_server"]


# --- plain Python parts --------------------------------------------------------------------

def test_repo_survivor_table_is_the_spec_table():
    assert load_survivors(REPO / "config" / "survivors.yaml") == DEFAULT_SURVIVORS
    assert DEFAULT_SURVIVORS == {"zone_a": (-2.5, 3.2), "zone_c": (4.1, -2.5)}


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("survivors: {zone_a: {x: 1.0}}\n", "survivors.zone_a: expected a mapping with x and y"),
        ("survivors: {zone_a: {x: one, y: 2}}\n", "survivors.zone_a.x: must be a number"),
        ("survivors: {zone_a: {x: .inf, y: 2}}\n", "survivors.zone_a.x: must be finite"),
        ("zones: {}\n", "survivors: expected a mapping"),
        ("survivors: [\n", "YAML error"),
    ],
)
def test_bad_survivor_tables(tmp_path, text, message):
    path = tmp_path / "s.yaml"
    path.write_text(text)
    with pytest.raises(SurvivorsFileError, match=message):
        load_survivors(path)


def test_report_log_reloads_ids_and_heals_a_torn_line(tmp_path):
    path = tmp_path / "sub" / "reports.jsonl"
    log = ReportLog(path)
    assert log.open().loaded == 0
    assert log.append({"survivor_id": "survivor_1", "x": 1.0})
    assert not log.append({"survivor_id": "survivor_1", "x": 9.0})
    log.close()
    with path.open("a") as handle:
        handle.write('{"survivor_id": "surv')  # a crash mid-write
    again = ReportLog(path)
    opened = again.open()
    assert (opened.loaded, opened.unreadable_lines) == (1, (2,))
    assert "survivor_1" in again
    assert again.append({"survivor_id": "survivor_2", "x": 2.0})
    again.close()
    lines = path.read_text().splitlines()
    assert json.loads(lines[0])["survivor_id"] == "survivor_1"
    assert json.loads(lines[-1])["survivor_id"] == "survivor_2"
    assert len(lines) == 3


# --- over DDS ------------------------------------------------------------------------------

def call(node, executor, srv_type, name, request):
    return call_service(node, executor, srv_type, name, request, discovery_timeout=DISCOVERY_S)


def detect(ros, zone_id):
    from sar_interfaces.srv import DetectSurvivor

    node, executor = ros
    return call(node, executor, DetectSurvivor, "/detect_survivor",
                DetectSurvivor.Request(zone_id=zone_id))


def report(ros, survivor_id, x=-2.5, y=3.2, frame="map"):
    from sar_interfaces.srv import ReportSurvivor

    node, executor = ros
    request = ReportSurvivor.Request(survivor_id=survivor_id)
    request.location.header.frame_id = frame
    request.location.point.x, request.location.point.y = x, y
    return call(node, executor, ReportSurvivor, "/report_survivor", request).acknowledged


def records(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


@pytest.mark.ros
def test_detect_server_default_table(ros, tmp_path):
    with NodeProcess(DETECT, "detect", log_dir=tmp_path) as server:
        server.wait_for_output("ready")
        found = detect(ros, "zone_a")
        assert found.found is True
        assert (found.survivor_x, found.survivor_y) == (-2.5, 3.2)
        assert detect(ros, "zone_b").found is False
        assert detect(ros, "zone_c").found is True
        server.wait_for_output(r"Detection request for zone_a: FOUND at \(-2\.50, 3\.20\)")
        server.wait_for_output(r"Detection request for zone_b: no survivor")
    assert server.returncode() == 0
    assert "Traceback" not in server.output


@pytest.mark.ros
def test_detect_server_custom_table(ros, tmp_path):
    table = tmp_path / "table.yaml"
    table.write_text("survivors:\n  zone_b: {x: 1.0, y: -1.5}\n")
    args = [*DETECT, "--ros-args", "-p", f"survivors_file:={table}"]
    with NodeProcess(args, "detect", log_dir=tmp_path) as server:
        server.wait_for_output("ready")
        assert detect(ros, "zone_a").found is False
        found = detect(ros, "zone_b")
        assert (found.found, found.survivor_x, found.survivor_y) == (True, 1.0, -1.5)


@pytest.mark.ros
def test_detect_server_bad_table_exits_2_with_one_message(tmp_path):
    table = tmp_path / "table.yaml"
    table.write_text("survivors:\n  zone_b: {x: 1.0}\n")
    server = NodeProcess([*DETECT, "--ros-args", "-p", f"survivors_file:={table}"], "detect",
                         log_dir=tmp_path).start()
    assert server.wait(timeout=20) == 2
    assert f"{table}: survivors.zone_b: expected a mapping with x and y" in server.output
    assert "Traceback" not in server.output


REPEATED = "Repeated report: survivor_1 .* Acknowledged; already on record"


@dataclass(frozen=True)
class Killed:
    """A report server that was told survivor_1 twice, then killed (SIGKILL)."""

    file: Path
    acknowledged: tuple[bool, bool]
    output: str
    records: list[dict]  # the file's records right after the kill


@pytest.fixture(scope="module")
def killed(tmp_path_factory: pytest.TempPathFactory) -> Killed:
    """One report server run for the durability and the restart tests: survivor_1 reported
    twice (the repeat acknowledged and written once), then SIGKILL, with no chance to flush
    anything after answering. The restart test starts a second server on its file."""
    folder = tmp_path_factory.mktemp("killed")
    file = folder / "reports.jsonl"
    server = NodeProcess([*REPORT, "--ros-args", "-p", f"report_file:={file}"], "report",
                         log_dir=folder).start()
    try:
        server.wait_for_output("ready")
        with ros_node("report_client") as ros:
            acknowledged = (report(ros, "survivor_1"), report(ros, "survivor_1"))
        with contextlib.suppress(AssertionError):  # the restart test asserts it, by name
            server.wait_for_output(REPEATED)
        server.send_signal(signal.SIGKILL)
        server.wait(timeout=10)
    finally:
        server.stop()
    return Killed(file, acknowledged, server.output, records(file))


@pytest.mark.ros
def test_report_is_on_disk_when_acknowledged_even_after_sigkill(killed: Killed):
    assert killed.acknowledged[0] is True
    assert "Report received: survivor_1 at (-2.50, 3.20). Acknowledged." in killed.output
    (record,) = killed.records
    assert record["survivor_id"] == "survivor_1"
    assert (record["x"], record["y"], record["frame_id"]) == (-2.5, 3.2, "map")


@pytest.mark.ros
def test_bad_reports_are_refused_with_a_warning(ros, tmp_path):
    file = tmp_path / "reports.jsonl"
    with NodeProcess([*REPORT, "--ros-args", "-p", f"report_file:={file}"], "report",
                     log_dir=tmp_path) as server:
        server.wait_for_output("ready")
        assert report(ros, "survivor_1", frame="odom") is False
        server.wait_for_output(r"WARN.*location frame is 'odom', expected 'map'")
        assert report(ros, "survivor_1", x=math.nan) is False
        server.wait_for_output(r"WARN.*location is not finite")
        assert report(ros, "survivor_1", y=math.inf) is False
        assert report(ros, "") is False
        server.wait_for_output(r"WARN.*empty survivor id")
        assert report(ros, "s" * 65) is False
        server.wait_for_output(r"WARN.*65 characters long \(at most 64\)")
        assert report(ros, "s" * 64) is True  # the limit itself is fine
    assert [r["survivor_id"] for r in records(file)] == ["s" * 64]


@pytest.mark.ros
def test_repeated_id_is_acknowledged_but_written_once_across_restarts(ros, tmp_path,
                                                                      killed: Killed):
    assert killed.acknowledged == (True, True)  # the repeat too, in the first server
    assert re.search(REPEATED, killed.output), killed.output
    args = [*REPORT, "--ros-args", "-p", f"report_file:={killed.file}"]
    with NodeProcess(args, "report2", log_dir=tmp_path) as second:
        second.wait_for_output(r"ready: .*\(1 survivors already on record\)")
        assert report(ros, "survivor_1", x=0.5) is True
        second.wait_for_output("differs from the recorded")
        assert report(ros, "survivor_2", x=4.1, y=-2.5) is True
    assert [r["survivor_id"] for r in records(killed.file)] == ["survivor_1", "survivor_2"]
    assert records(killed.file)[0]["x"] == -2.5


@pytest.mark.ros
def test_refuse_all_fault_injection(ros, tmp_path):
    file = tmp_path / "reports.jsonl"
    args = [*REPORT, "--ros-args", "-p", f"report_file:={file}", "-p", "refuse_all:=true"]
    with NodeProcess(args, "report", log_dir=tmp_path) as server:
        server.wait_for_output("ready")
        assert report(ros, "survivor_1") is False
        server.wait_for_output("refuse_all is set")
    assert not file.exists() or records(file) == []


@pytest.mark.ros
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_mid_request_stops_the_server_cleanly(ros, tmp_path, sig):
    """A signal while requests keep arriving ends the server with 0 and no traceback.

    With rclpy's own handlers the signal raised KeyboardInterrupt wherever the main thread
    was and shut the context down under the executor: a take (or a half-made Task) then
    printed a traceback (seen under load at the end of a mission).
    """
    from sar_interfaces.srv import DetectSurvivor

    node, executor = ros
    for round_ in range(3):
        server = NodeProcess(DETECT, f"detect{round_}", log_dir=tmp_path).start()
        try:
            server.wait_for_output("ready")
            client = node.create_client(DetectSurvivor, "/detect_survivor")
            assert spin_until(executor, client.service_is_ready, DISCOVERY_S)
            pending = [client.call_async(DetectSurvivor.Request(zone_id="zone_a"))
                       for _ in range(50)]
            spin_until(executor, lambda p=pending: any(f.done() for f in p), 5.0)
            server.send_signal(sig)  # while the other requests are still being served
            for _ in range(50):
                client.call_async(DetectSurvivor.Request(zone_id="zone_b"))
            assert server.wait(timeout=10) == 0, server.output
        finally:
            server.stop()
            node.destroy_client(client)
        assert "Traceback" not in server.output, server.output
