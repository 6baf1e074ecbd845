"""``sar-tree run``: the whole mission from one command.

Starts, as child processes of this one, what :mod:`sar_framework.mission.processes`
describes (the launch file starts the same): the embedded simulator (unless ``--no-sim``),
the detect and report servers, and the tree runner; prints the mission's progress; stops
everything in order; writes the mission report (:mod:`sar_framework.report`) into the
report folder, beside every child's log.

One concern per module, each importing only those above it:

- :mod:`.options`: the command line, :class:`~.options.RunConfig`;
- :mod:`.inputs`: every input checked before anything starts, the nodes' tables;
- :mod:`.robots`: the robots of a run (one unnamed robot, or ``--robots N``/``--fleet FILE``);
- :mod:`.config`: what the mission starts, as the children's command lines;
- :mod:`.supervise`: the child processes, their output, signals and the stop order;
- :mod:`.outcome`: progress lines, the verdict and its reason, the summary, exit codes;
- :mod:`.run_report`: each robot's verdict event and report, named robots' run page;

and :mod:`.orchestrator` ties them together (:class:`~.orchestrator.Orchestrator`, for any
robot count; :func:`run_command`). The name says what the package does: it orchestrates the
processes of one run; the tree runner it starts is :mod:`sar_framework.runner`, and the mission's
own state and process list are :mod:`sar_framework.mission`.
"""

from sar_framework.orchestrate.command import run_command
from sar_framework.orchestrate.options import configure

__all__ = ["configure", "run_command"]
