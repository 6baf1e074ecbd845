"""``sar-sim`` / ``python -m sar_framework.sim``: run the embedded Nav2 simulator.

Parameters are ROS parameters::

    sar-sim --ros-args -p speed:=20.0 -p trace_file:=reports/latest/trace.jsonl

``sar-sim --help`` lists them. The simulator logs ``ready: ...`` once it serves, and
exits within a second on SIGINT/SIGTERM, aborting a goal in flight first.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Sequence

RESULT_FLUSH_S = 0.15
"""Wall seconds the executor keeps spinning after a goal was aborted at shutdown."""


def usage() -> str:
    """Return the ``--help`` text: the command line and the parameter table."""
    from sar_framework.engine.param import type_name
    from sar_framework.sim.params import SIM_PARAMETERS

    lines = [
        "usage: sar-sim [--ros-args -p NAME:=VALUE ...]",
        "",
        "Embedded Nav2 stand-in (docs/reference/nav2-surface.md): Nav2's lifecycle nodes and",
        "actions,",
        "/clock, /tf, /odometry/filtered, /map, /amcl_pose, on simulated time. Parameters:",
        "",
    ]
    for p in SIM_PARAMETERS:
        default = "(unset)" if p.default is None else p.default
        unit = f" [{p.unit}]" if p.unit else ""
        bounds = f" ({p.bounds()})" if p.bounds() else ""
        lines.append(f"  {p.name:<20} {type_name(p.type):<9} {default!s}\n"
                     f"      {p.description}{unit}{bounds}")
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    """Run the simulator until SIGINT/SIGTERM.

    Args:
        argv: Command line including the program name (default: ``sys.argv``).

    Returns:
        0 after a clean stop, 1 if the physics loop or the executor died, 2 on invalid
        parameters, map, world or trace file.
    """
    args = list(sys.argv if argv is None else argv)
    ros_start = args.index("--ros-args") if "--ros-args" in args else len(args)
    if any(a in ("-h", "--help") for a in args[1:ros_start]):
        sys.stdout.write(usage())
        return 0

    import rclpy
    from rclpy.executors import MultiThreadedExecutor
    from rclpy.logging import get_logger
    from rclpy.signals import SignalHandlerOptions

    from sar_framework.ros.teardown import bounded_teardown
    from sar_framework.sim.sim_node import SimConfigError, Simulator
    from sar_framework.stop_signals import stop_on_signals

    # Our own handlers: rclpy's would shut the context down before a goal in flight
    # could be aborted and its result sent.
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    stop = stop_on_signals()
    try:
        sim = Simulator()
    except SimConfigError as exc:
        get_logger("sar_sim").error(f"cannot start: {exc}")
        rclpy.try_shutdown()
        return 2

    executor = MultiThreadedExecutor(num_threads=6)
    for node in sim.nodes:
        executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, name="sim-executor", daemon=True)
    spinner.start()
    sim.start()
    sim.node.get_logger().info(sim.ready_message())
    crashed = False
    try:
        while not stop.event.wait(0.1):
            if not (spinner.is_alive() and sim.alive):
                crashed = True
                break
    finally:
        if sim.stop():
            time.sleep(RESULT_FLUSH_S)
        executor.shutdown(timeout_sec=0.5)
        spinner.join(timeout=0.5)
        with bounded_teardown():  # Fast DDS's participant teardown can hang
            sim.destroy()
        rclpy.try_shutdown()
    return 1 if crashed else 0


if __name__ == "__main__":
    sys.exit(main())
