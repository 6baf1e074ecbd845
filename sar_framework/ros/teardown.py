"""Bound the destruction of a process's last nodes: Fast DDS's participant teardown can hang.

Fast DDS 2.14 (Jazzy's) deletes a participant through ``set_listener(nullptr)``, which waits
in a busy loop for discovery callbacks in flight (eProsima/Fast-DDS#6513); a callback for
another participant leaving at the same moment can block on a lock the waiting side holds,
and then neither ever moves. When launch stops every process at once, one of them now and
then hung in its last ``destroy_node`` until launch killed it (seen with gdb:
``rcl_node_fini`` → ``destroy_participant`` → ``set_listener``, a discovery thread blocked
in ``onWriterDiscovery``; lowering the waiting thread's priority did not free it).

The hung thread is the main thread and holds the GIL, so no Python thread and no Python
signal handler can act. :func:`bounded_teardown` therefore starts a small watchdog process
and installs a C-level handler (through ctypes) for :data:`STUCK_SIGNAL`. If the teardown
still runs after its bound, the watchdog sends that signal to the main thread; the handler
runs there at once (the thread already holds the GIL), prints every thread's stack and a
line saying what happened on stderr, and ends the process with exit code 0: the process's
own work is done, only the middleware's goodbye is cut short. Other participants then drop
it when its lease runs out.
"""

from __future__ import annotations

import ctypes
import faulthandler
import os
import signal
import subprocess
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager

#: Wall seconds a teardown may take (it takes well under a second, even on a loaded machine).
TEARDOWN_BOUND_S = 8.0
#: The signal the watchdog sends to the tearing-down thread.
STUCK_SIGNAL = signal.SIGUSR2

_WATCHDOG = """
import ctypes, sys, time
pid, tid, bound, signum = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
time.sleep(bound)
ctypes.CDLL(None).tgkill(pid, tid, signum)  # that thread, not any thread of the process
"""
_HANDLER_TYPE = ctypes.CFUNCTYPE(None, ctypes.c_int)
_handlers: list[object] = []  # the installed C callbacks, kept alive


def _install_exit_handler(bound_s: float) -> None:
    """Make :data:`STUCK_SIGNAL` report the stacks and end the process with code 0."""
    message = (f"teardown still running after {bound_s:g} s (Fast DDS's participant "
               "teardown can hang): the process ends without it\n").encode()

    def on_stuck(_signum: int) -> None:
        faulthandler.dump_traceback(file=sys.stderr, all_threads=True)
        os.write(2, message)
        os._exit(0)

    handler = _HANDLER_TYPE(on_stuck)
    _handlers.append(handler)
    libc = ctypes.CDLL(None)
    libc.signal.restype = ctypes.c_void_p
    libc.signal.argtypes = (ctypes.c_int, _HANDLER_TYPE)
    libc.signal(int(STUCK_SIGNAL), handler)


@contextmanager
def bounded_teardown(bound_s: float = TEARDOWN_BOUND_S) -> Iterator[None]:
    """End the process (code 0, stacks on stderr) if the body runs longer than ``bound_s``.

    Use it in the main thread around the destruction of a process's last nodes (Linux;
    elsewhere it only runs the body). The watchdog is stopped when the body ends.

    Args:
        bound_s: Wall seconds before the process is ended.
    """
    if not hasattr(ctypes.CDLL(None), "tgkill"):
        yield
        return
    _install_exit_handler(bound_s)
    watchdog = subprocess.Popen(
        [sys.executable, "-I", "-S", "-c", _WATCHDOG, str(os.getpid()),
         str(threading.get_native_id()), str(bound_s), str(int(STUCK_SIGNAL))],
        stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
        start_new_session=True)  # a Ctrl-C to the process group is not for it
    try:
        yield
    finally:
        watchdog.kill()
        watchdog.wait()
