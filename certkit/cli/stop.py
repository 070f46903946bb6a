"""Stop signals (Ctrl-C, SIGTERM, SIGHUP) as an exception, installed before anything else
of the command line is imported, so a signal at any moment ends the run with 128 + its
number, through the clean-up of whatever was being written, and never with a traceback."""

from __future__ import annotations

import signal
import threading

STOP_SIGNALS = (signal.SIGTERM, signal.SIGHUP, signal.SIGINT)


class Stopped(SystemExit):
    """The run was stopped by ``signal_name``; exit code 128 + the signal's number."""

    def __init__(self, number: int):
        super().__init__(128 + number)
        self.signal_name = signal.Signals(number).name


def _stop(number, _frame):
    # The first stop signal becomes an exception, so staged outputs are removed; further
    # signals are ignored so they cannot interrupt that clean-up.
    for other in STOP_SIGNALS:
        signal.signal(other, signal.SIG_IGN)
    raise Stopped(number)


def install() -> None:
    """Turn the stop signals into :class:`Stopped`.  Python lets only the main thread set
    signal handlers: imported from another thread (a notebook's worker, a GUI), the
    command line is used as a library and the process's handlers are left as they are."""
    if threading.current_thread() is not threading.main_thread():
        return
    for number in STOP_SIGNALS:
        signal.signal(number, _stop)
