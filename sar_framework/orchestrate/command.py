"""``sar-tree run``'s entry: check every input, then run the mission (one robot or more)."""

from __future__ import annotations

import argparse
import sys

from sar_framework.orchestrate.config import check_config
from sar_framework.orchestrate.options import RunUsageError, config_from_args
from sar_framework.orchestrate.orchestrator import Orchestrator
from sar_framework.orchestrate.outcome import EXIT_USAGE, exited_children
from sar_framework.stop_signals import stop_on_signals


def run_command(args: argparse.Namespace) -> int:
    """``sar-tree run``: check the input, run the mission, return the exit code.

    Args:
        args: Parsed arguments (see :func:`~sar_framework.orchestrate.options.configure`).

    Returns:
        The exit code.
    """
    config = config_from_args(args)
    try:
        inputs = check_config(config)
    except RunUsageError as err:
        lines = str(err).splitlines()
        if len(lines) == 1:
            sys.stderr.write(f"sar-tree run: error: {lines[0]}\n")
        else:
            sys.stderr.write("\n".join(lines) + f"\nsar-tree run: error: {len(lines)} "
                             "problems in the inputs; nothing was started\n")
        return EXIT_USAGE
    return run_mission(Orchestrator(config, inputs))


def run_mission(mission: Orchestrator) -> int:
    """Run a checked mission; return the exit code.

    Args:
        mission: The mission (an :class:`Orchestrator` of checked inputs, one robot or more).

    Returns:
        0 SUCCESS, 1 FAILURE/timeout/start-up failure, 2 input rejected by a child,
        130 interrupted.
    """
    interrupt = stop_on_signals()
    try:
        mission.prepare()
        mission.start()
        outcome = mission.wait(interrupt.event)
        if outcome.status == "TIMEOUT":
            mission.say(f"sar-tree run: {outcome.reason}; stopping")
        if outcome.status == "INTERRUPTED":
            mission.say(f"sar-tree run: {interrupt.name or 'interrupted'}: stopping "
                        "(the goal in flight is cancelled)")
    finally:
        mission.stop()
        interrupt.restore()
    if mission.exited and outcome.status != "SUCCESS":
        outcome.reason = "; ".join([outcome.reason, *exited_children(mission.exited)]).strip("; ")
    mission.record_verdict(outcome)
    written = mission.write_report(outcome)
    return mission.conclude(outcome, written)
