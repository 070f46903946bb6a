"""The certkit command line: a thin shell over the library.

Exit codes: 0 success; 1 a check did not pass (``report --strict``, ``audit``,
``verify``); 2 bad input; 3 internal error (a certkit bug; no traceback unless CERTKIT_DEBUG
is set); 4 the machine refused (no space, no permission, a read-only disk, another run
writing the same output).

:mod:`certkit.cli.app` holds the application and the one home of its error handling; the
commands live by what they work on: :mod:`~certkit.cli.campaign` (validate, report, audit,
schema, sets), :mod:`~certkit.cli.model` (simulate, calibrate, identify, gap) and
:mod:`~certkit.cli.archive` (archive, verify, catalog).
"""

from certkit import stop

stop.install()   # first: a stop signal while the rest is imported ends the run quietly

from certkit.cli import archive, campaign, model  # noqa: E402, F401 - registers the commands
from certkit.cli.app import app, run  # noqa: E402

__all__ = ["app", "run"]
