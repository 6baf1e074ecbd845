"""Destroy a process's last nodes without Fast DDS's participant teardown spinning for good.

Fast DDS 2.14 (Jazzy's) deletes a participant through ``set_listener(nullptr)``: it
busy-waits, taking and releasing the participant's mutex in a tight loop, until no discovery
callback is in flight, while such a callback needs that same mutex to finish
(eProsima/Fast-DDS#6513). Another participant leaving at the same moment starts such
callbacks, so when launch stops every process at once, one of them now and then spun inside
its last ``destroy_node`` until it was killed (seen with gdb: ``rcl_node_fini`` →
``destroy_participant`` → ``set_listener``).

The spinning thread holds the GIL, so no Python thread of the process can act. Within
:func:`unstuck_teardown`, a small watchdog process waits; if the teardown still runs after
:data:`STUCK_AFTER_S`, it puts every thread of the process on one CPU and the tearing-down
thread at idle priority (``SCHED_IDLE``). The callback's thread, woken each time the mutex is
released, then preempts the spinning thread at once, takes the mutex and finishes, and the
participant goes as usual (its departure announced, its shared memory removed).
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager, suppress

#: Wall seconds a teardown may run before the watchdog lets discovery callbacks through
#: (a teardown takes well under a second, even on a loaded machine).
STUCK_AFTER_S = 2.0

_WATCHDOG = """
import os, sys, time
pid, tid, after = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
time.sleep(after)
try:
    cpu = min(os.sched_getaffinity(tid))
    for task in os.listdir(f"/proc/{pid}/task"):
        try:
            os.sched_setaffinity(int(task), {cpu})
        except OSError:
            pass
    os.sched_setscheduler(tid, os.SCHED_IDLE, os.sched_param(0))
except OSError:
    sys.exit(0)  # the process ended meanwhile
sys.stderr.write(f"teardown of process {pid} still running after {after} s: "
                 "its threads now share one CPU, the teardown at idle priority\\n")
"""


@contextmanager
def unstuck_teardown(stuck_after_s: float = STUCK_AFTER_S) -> Iterator[None]:
    """Watch the calling thread's teardown; past the bound, let its DDS callbacks through.

    Use it around the destruction of a process's last nodes (Linux; elsewhere it only runs
    the body). When the body ends, the watchdog is stopped and, if it acted, the thread's
    priority and the process's CPUs are as before.

    Args:
        stuck_after_s: Wall seconds before the watchdog acts.
    """
    if not hasattr(os, "sched_setscheduler"):
        yield
        return
    cpus = os.sched_getaffinity(0)
    watchdog = subprocess.Popen(
        [sys.executable, "-I", "-S", "-c", _WATCHDOG, str(os.getpid()),
         str(threading.get_native_id()), str(stuck_after_s)],
        stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
        start_new_session=True)  # a Ctrl-C to the process group is not for it
    try:
        yield
    finally:
        watchdog.kill()
        watchdog.wait()
        if os.sched_getscheduler(0) == os.SCHED_IDLE:  # the rest of the exit at full speed
            with suppress(OSError):
                os.sched_setscheduler(0, os.SCHED_OTHER, os.sched_param(0))
            for task in os.listdir("/proc/self/task"):
                with suppress(OSError):
                    os.sched_setaffinity(int(task), cpus)
