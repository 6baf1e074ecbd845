"""``sar-tree run``: the whole mission from one command.

Starts, as child processes of this one, what :mod:`sar_framework.mission.processes`
describes (the launch file starts the same): the embedded simulator (unless ``--no-sim``),
the detect and report servers, and the tree runner; prints the mission's progress; stops
everything in order; writes the mission report (:mod:`sar_framework.report`) into the
report folder, beside every child's log.

Three modules, one concern each:

- :mod:`.config`: the options, the checks of every input, the children's command lines;
- :mod:`.supervise`: the child processes, their output, signals and the stop order;
- :mod:`.outcome`: progress lines, the verdict and its reason, the summary, exit codes;

and :mod:`.mission` ties them together (:func:`run_command`).
"""

from sar_framework.run.config import configure
from sar_framework.run.mission import run_command

__all__ = ["configure", "run_command"]
