"""Benchmark: the studio's live update latency (tick to browser) and replay scrub time.

    .venv/bin/python benchmarks/bench_studio.py [--speeds 1 20] [--scrubs 60]
                                                [--recording FILE.mcap] [--parts live replay]

Needs chromium and chromedriver (``apt-get install chromium chromium-driver``).

- **live**: ``sar-tree studio live`` is started, a headless chromium opens its page, then
  the reference mission (trees/search_and_rescue.yaml) runs at each ``--speeds``. An
  rclpy subscriber in this process notes the wall time each ``/sar_tree/status`` tick
  arrives; the page notes when the frame of that tick was drawn (``Date.now()``, the same
  clock). The latency is the difference, per tick the page drew (its first frame: the
  robot's moves redraw the same tick); ``shown`` is the share of ticks drawn (the server
  sends the newest frame at most every 10 ms and once the page drew the last, so at high
  speeds ticks closer than that are drawn together).
- **replay**: a long recording (by default the reference mission with a robot at a
  quarter of its speed, several minutes of simulated time, recorded at speed 20) is
  opened with ``sar-tree studio replay``; the page seeks to ``--scrubs`` random instants
  one after another and each is timed from the seek to the frame drawn. ``frame(t)`` is
  the server's part alone (:meth:`sar_framework.studio.timeline.Timeline.frame`).
  Then the page's event list is filled with 10,000 made-up events and shown at 2,000
  instants, timed per 100 (the suite checks what keeps it fast by counting: a bisection
  per instant, two rows' classes changed, one scroll per drawn frame).

Uses ``ROS_DOMAIN_ID`` from the environment (default 44) and loopback-only discovery.
"""

from __future__ import annotations

import argparse
import os
import random
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
TREE = REPO / "trees" / "search_and_rescue.yaml"

from sar_framework.testing.browser import (  # noqa: E402 - after the path is set
    browser_missing,
    headless_chromium,
    record_mission,
    start_studio,
)

DRAWN_HOOK = """
window.drawn = [];
const original = onFrame;
onFrame = (frame) => { original(frame); window.drawn.push([frame.tick, Date.now()]); };
"""
SCRUB = """
const [times, done] = [arguments[0], arguments[arguments.length - 1]];
const original = onFrame, took = [];
let i = 0, started = 0;
onFrame = (frame) => {
  original(frame);
  if (i > 0) took.push(performance.now() - started);
  if (i === times.length) { onFrame = original; done(took); return; }
  started = performance.now(); seek(times[i]); i += 1;
};
started = performance.now(); seek(times[0]); i = 1;
"""

EVENT_LIST = """
const [n, batches, per] = arguments;
const start = studio.hello.timeline.start;
const rows = Array.from({length: n}, (_, i) => ({
  i, t: start + i * 0.01, sim_s: start + i * 0.01, seq: i + 1, kind: i % 7 ? "status" : "note",
  node: "N", uid: "0", status: "", fields: [], mark: "", message: `event ${i}`}));
let began = performance.now();
fillEvents(rows, start);
const filled = performance.now() - began;
const shown = [];
for (let b = 0; b < batches; b++) {
  began = performance.now();
  for (let k = 0; k < per; k++) showEventAt(start + (((b * per + k) * 7919) % n) * 0.01);
  shown.push(performance.now() - began);
}
fillEvents(studio.hello.timeline.events, start);
return {filled, shown};
"""


def _env() -> None:
    os.environ.setdefault("ROS_DOMAIN_ID", "44")
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"


def _stats(values: list[float]) -> tuple[float, float, float]:
    ordered = sorted(values)
    p95 = ordered[min(len(ordered) - 1, round(0.95 * (len(ordered) - 1)))]
    return statistics.median(ordered), p95, ordered[-1]


def _tick_arrivals(stop: threading.Event, arrivals: dict[int, float]) -> None:
    """Note the wall time (ms) each status tick arrives at an rclpy subscriber of ours."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from std_msgs.msg import String

    from sar_framework.ros.qos import latched_qos
    from sar_framework.runner.tree_status import STATUS_TOPIC, decode_status

    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node("bench_studio_ticks", context=context)

    def on_status(message: String) -> None:
        now = time.time() * 1000
        arrivals.setdefault(decode_status(message.data)["tick"], now)

    node.create_subscription(String, STATUS_TOPIC, on_status, latched_qos(50))
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    while not stop.is_set():
        executor.spin_once(timeout_sec=0.05)
    executor.shutdown()
    node.destroy_node()
    rclpy.try_shutdown(context=context)


def live_row(speed: float, folder: Path) -> tuple[str, int, float, list[float]]:
    """One mission at ``speed`` watched live; the row's label, ticks, share shown, latencies."""
    studio, url = start_studio(["live"], folder, label=f"studio_live_{speed:g}")
    arrivals: dict[int, float] = {}
    stop = threading.Event()
    listener = threading.Thread(target=_tick_arrivals, args=(stop, arrivals), daemon=True)
    listener.start()
    try:
        with headless_chromium() as driver:
            driver.get(url)
            time.sleep(2.0)
            driver.execute_script(DRAWN_HOOK)
            subprocess.run([sys.executable, "-m", "sar_framework", "run", str(TREE),
                            "--speed", f"{speed:g}", "--report-dir",
                            str(folder / f"live_{speed:g}")],
                           capture_output=True, check=False, timeout=900, cwd=REPO)
            time.sleep(1.0)
            drawn = driver.execute_script("return window.drawn")
    finally:
        stop.set()
        listener.join(timeout=5)
        studio.stop()
    first_drawn: dict[int, float] = {}
    for tick, at in drawn:  # later frames of the same tick (the robot moved) do not count
        first_drawn.setdefault(tick, at)
    latencies = [at - arrivals[tick] for tick, at in first_drawn.items() if tick in arrivals]
    ticks = len(arrivals)
    shown = len([tick for tick in first_drawn if tick in arrivals]) / ticks if ticks else 0.0
    return f"live, speed {speed:g}: tick -> drawn", ticks, shown, latencies


def replay_rows(record: Path, scrubs: int, folder: Path) -> list[tuple[str, int, float,
                                                                       list[float]]]:
    """Scrub the recording in the page, and time the server's frame(t) alone."""
    from sar_framework.studio.session import replay_session

    session = replay_session(record, folder / "sources")
    timeline = session.timeline
    rng = random.Random(7)
    instants = [rng.uniform(timeline.start_s, timeline.end_s) for _ in range(scrubs)]
    server = []
    for t in instants:
        started = time.perf_counter()
        session.frame(t)
        server.append((time.perf_counter() - started) * 1000)
    studio, url = start_studio(["replay", str(record)], folder, label="studio_replay")
    try:
        with headless_chromium() as driver:
            driver.get(url)
            time.sleep(2.0)
            driver.set_script_timeout(300)
            browser = driver.execute_async_script(SCRUB, instants)
            events = driver.execute_script(EVENT_LIST, 10000, 20, 100)
    finally:
        studio.stop()
    minutes = (timeline.end_s - timeline.start_s) / 60
    label = f"{minutes:.1f} min, {len(timeline.statuses)} ticks, {len(timeline.poses)} poses"
    return [(f"replay ({label}): frame(t) on the server", scrubs, 1.0, server),
            ("replay: seek -> drawn in the page", scrubs, 1.0, browser),
            ("event list: fill with 10,000 events", 1, 1.0, [events["filled"]]),
            ("event list: 100 instants shown (of 10,000 events)", 20, 1.0, events["shown"])]


def main(argv: list[str] | None = None) -> int:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--speeds", type=float, nargs="+", default=[1.0, 20.0])
    parser.add_argument("--scrubs", type=int, default=60)
    parser.add_argument("--parts", nargs="+", choices=("live", "replay"),
                        default=["live", "replay"])
    parser.add_argument("--recording", type=Path, help="a long recording to scrub "
                        "(default: one is made)")
    args = parser.parse_args(argv)
    missing = browser_missing()
    if missing:
        print(f"bench_studio: {missing}")
        return 1
    _env()
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_studio_") as tmp:
        folder = Path(tmp)
        if "live" in args.parts:
            rows.extend(live_row(speed, folder) for speed in args.speeds)
        if "replay" in args.parts:
            recording = args.recording or record_mission(folder / "long.mcap",
                                                         "speed_scale:=0.25")
            rows.extend(replay_rows(recording, args.scrubs, folder))
    width = max(len(r[0]) for r in rows)
    print(f"{'what':<{width}} {'n':>5} {'shown':>6} {'median ms':>10} {'p95 ms':>8} "
          f"{'max ms':>8}")
    for label, n, shown, values in rows:
        median, p95, worst = _stats(values) if values else (float("nan"),) * 3
        print(f"{label:<{width}} {n:>5} {shown:>6.0%} {median:>10.1f} {p95:>8.1f} "
              f"{worst:>8.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
