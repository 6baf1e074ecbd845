"""``sar-tree run``'s entry: check every input, then run the mission (one robot or more)."""

from __future__ import annotations

import argparse
import sys

from sar_framework.orchestrate.config import check_config
from sar_framework.orchestrate.options import RunUsageError, config_from_args
from sar_framework.orchestrate.orchestrator import Orchestrator, run_mission
from sar_framework.orchestrate.outcome import EXIT_USAGE


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
