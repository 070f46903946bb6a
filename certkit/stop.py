"""Stop signals (Ctrl-C, SIGTERM, SIGHUP) as an exception, installed by the command line
before anything else of it is imported, so a signal at any moment ends the run with
128 + its number, through the clean-up of whatever was being written, and never with a
traceback.

Python runs a signal handler in the main thread between two bytecodes, wherever it is:
also inside a finaliser (``__del__``, a weak-reference callback), where an exception is
printed as "Exception ignored" with a traceback and dropped.  So the handler also records
the stop, and the places that make a run's work final ask for it again:
:func:`raise_if_stopped` before outputs are moved into place (:mod:`certkit.outputs`),
:func:`finish` when the command has ended; and :func:`install` keeps Python from printing
a dropped stop (:func:`_quiet_stop`, as ``sys.unraisablehook``), so the user sees the
one message of the stop and no traceback.  Without :func:`install` (certkit used as a
library) none of this happens.
"""

from __future__ import annotations

import signal
import sys
import threading

STOP_SIGNALS = (signal.SIGTERM, signal.SIGHUP, signal.SIGINT)

_requested: list[int] = []   # the stop signal received, once one has been


class Stopped(SystemExit):
    """The run was stopped by ``signal_name``; exit code 128 + the signal's number."""

    def __init__(self, number: int):
        super().__init__(128 + number)
        self.signal_name = signal.Signals(number).name


def _ignore_stop_signals() -> None:
    for number in STOP_SIGNALS:
        signal.signal(number, signal.SIG_IGN)


def _stop(number, _frame):
    # The first stop signal becomes an exception, so staged outputs are removed; further
    # signals are ignored so they cannot interrupt that clean-up.
    _ignore_stop_signals()
    _requested.append(number)
    raise Stopped(number)


_other_hook: list = []       # the unraisable hook install() found (a test runner's, say)


def _quiet_stop(unraisable) -> None:
    """``sys.unraisablehook``: a :class:`Stopped` a finaliser dropped is not printed (it was
    recorded, and :func:`raise_if_stopped` raises it again); anything else goes to the hook
    that was in place before :func:`install` (Python's own, unless another was set)."""
    if isinstance(unraisable.exc_value, Stopped):
        return
    (_other_hook[0] if _other_hook else sys.__unraisablehook__)(unraisable)


def install() -> None:
    """Turn the stop signals into :class:`Stopped`.  Python lets only the main thread set
    signal handlers: imported from another thread (a notebook's worker, a GUI), the
    command line is used as a library and the process's handlers are left as they are."""
    if threading.current_thread() is not threading.main_thread():
        return
    for number in STOP_SIGNALS:
        signal.signal(number, _stop)
    if sys.unraisablehook is not _quiet_stop:      # installed twice: keep the first one found
        _other_hook[:] = [sys.unraisablehook]
        sys.unraisablehook = _quiet_stop


def raise_if_stopped() -> None:
    """Raise :class:`Stopped` again if a stop signal came and its exception was dropped
    (by a finaliser it interrupted): called before a run's outputs are made final."""
    if _requested:
        raise Stopped(_requested[0])


def finish() -> None:
    """The command has ended: a stop signal from now on has nothing left to stop and is
    ignored (the outputs are in place); one that came and was dropped still stops."""
    if threading.current_thread() is threading.main_thread() and \
            signal.getsignal(signal.SIGINT) is _stop:
        _ignore_stop_signals()
    raise_if_stopped()
