"""The command-line application and the one home of its error handling.

Every command is registered with :func:`command`, which turns what a user can cause into a
message and exit code 2: a bad spec, data file or argument
(:class:`~certkit.errors.CertkitInputError`, its problems one per line), a campaign the model
cannot follow (:class:`~certkit.errors.CampaignError`, named with the campaign or bag) and a
path that is not a bag (:class:`~certkit.archive.bag.BagError`); and what the machine
refuses into a message and exit code 4 (:class:`~certkit.errors.EnvironmentFailure`, or an
OSError such as no space left, permission denied, read-only).  :func:`run`, the console
entry point, reports anything else as a certkit bug (exit 3, no traceback unless
CERTKIT_DEBUG is set).
"""

from __future__ import annotations

import functools
import inspect
import os
import re
import sys
from pathlib import Path
from typing import Annotated, NoReturn

import typer
from rich.console import Console
from rich.text import Text

import certkit.stop as stop
from certkit.archive.bag import BagError
from certkit.errors import (CampaignError, CertkitInputError, EnvironmentFailure,
                            is_environmental)
from certkit.version import VERSION

EXIT_CODES = ("Exit codes: 0 success; 1 a check does not pass; 2 bad input; 3 an internal "
              "error (a certkit bug); 4 the machine refused (no space, no permission, a "
              "read-only disk, another run writing the same output).")
app = typer.Typer(add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False,
                  rich_markup_mode=None,
                  help="Turn a landing-gear drop-test campaign into airworthiness evidence.",
                  epilog=EXIT_CODES)
catalog_app = typer.Typer(no_args_is_help=True, help="An index of archived campaigns, in an "
                                                     "SQLite file or a PostgreSQL database: "
                                                     "add bags, list and search them.")
app.add_typer(catalog_app, name="catalog",
              short_help="An index of archived campaigns (SQLite or PostgreSQL)")
err = Console(stderr=True, highlight=False, soft_wrap=True, markup=False)
out = Console(highlight=False, soft_wrap=True, markup=False)

SpecArgument = Annotated[Path, typer.Argument(help="the campaign spec, a YAML file",
                                              metavar="SPEC", show_default=False)]


def error(message: str) -> None:
    """Print one error line on standard error."""
    err.print(Text.assemble(("error: ", "bold red"), message))


def warning(message: str, label: str = "warning") -> None:
    """Print one warning (or note) line on standard error."""
    err.print(Text.assemble((f"{label}: ", "bold yellow" if label == "warning" else "bold"),
                            message))


def fail(subject: Path, message: str) -> NoReturn:
    """A bad-input outcome that is not a spec problem (no data to work on): exit 2."""
    error(f"{subject}: {message}")
    raise typer.Exit(2)


def bad_option(option: str, expected: str, found) -> NoReturn:
    """A command-line option with a value it cannot take: say which, and exit 2."""
    error(f"--{option}: expected {expected}, found {found}")
    raise typer.Exit(2)


def _report_user_error(problem: Exception, subject: object, context: str) -> NoReturn:
    """What the user can act on, as a message; exit 2."""
    if isinstance(problem, CertkitInputError):
        for item in problem.problems:
            error(str(item))
    elif isinstance(problem, CampaignError):
        error(f"{subject}: {context}{problem}")
    else:
        error(str(problem))
    raise typer.Exit(2)


def _report_environment(problem: Exception) -> NoReturn:
    """What the machine refused (space, permission, ...), as one line naming the path; exit 4."""
    if not isinstance(problem, EnvironmentFailure):
        problem = EnvironmentFailure.from_os_error(problem, doing="the system refused")
    error(str(problem))
    raise typer.Exit(4)


class PlainCommand(typer.core.TyperCommand):
    """click's plain help, with each argument named as its metavar says (``SPEC``,
    ``BAG...``): no type column (``<path>``) and no braces in the usage line."""

    @staticmethod
    def _name(param) -> str:
        name = param.metavar or param.name.upper()
        return name if param.metavar or param.nargs == 1 else f"{name}..."

    def collect_usage_pieces(self, ctx) -> list[str]:
        pieces = [self.options_metavar] if self.options_metavar else []
        for param in self.get_params(ctx):
            if param.param_type_name == "argument":
                pieces.append(self._name(param) if param.required else f"[{self._name(param)}]")
        return pieces

    def format_options(self, ctx, formatter) -> None:
        arguments, options = [], []
        for param in self.get_params(ctx):
            record = param.get_help_record(ctx)
            if record is None:
                continue
            if param.param_type_name == "argument":
                arguments.append((self._name(param), record[1]))
            else:
                options.append(record)
        for title, rows in (("Arguments", arguments), ("Options", options)):
            if rows:
                with formatter.section(title):
                    formatter.write_dl(rows)


def summary(doc: str | None) -> str | None:
    """A command's line in the list of commands: its docstring's first clause (to the first
    full stop, colon or semicolon), whole, where click would cut it at the terminal's width."""
    if not doc:
        return None
    return re.split(r"[.:;](?:\s|$)", " ".join(doc.split()), maxsplit=1)[0]


def command(group: typer.Typer = app, name: str | None = None, context: str = ""):
    """Register a command whose user-caused errors exit 2 with a message.

    ``context`` prefixes the message of a :class:`~certkit.errors.CampaignError` (e.g. "the
    recomputation failed: "); its subject is the command's first argument (the spec or bag).
    """
    def register(function):
        signature = inspect.signature(function)

        @functools.wraps(function)
        def handled(*args, **kwargs):
            try:
                return function(*args, **kwargs)
            except (CertkitInputError, CampaignError, BagError) as problem:
                arguments = signature.bind_partial(*args, **kwargs).arguments
                subject = next(iter(arguments.values()), "certkit")
                _report_user_error(problem, subject, context)
            except EnvironmentFailure as problem:
                _report_environment(problem)
            except OSError as problem:
                if not is_environmental(problem):
                    raise
                _report_environment(problem)

        return group.command(name, cls=PlainCommand,
                             short_help=summary(function.__doc__))(handled)

    return register


def _version(value: bool) -> None:
    if value:
        out.print(f"certkit {VERSION}")
        raise typer.Exit()


@app.callback()
def main(version: Annotated[bool, typer.Option("--version", callback=_version, is_eager=True,
                                               help="print the version and exit")] = False):
    """certkit: drop-test campaign -> compliance report, audit tables and evidence."""
    stop.install()   # again: the application may be run without the package's import


def _usable_streams() -> None:
    """Standard output and error as certkit writes them: a closed one (``>&-``) discards
    what is written, as /dev/null would; one whose encoding lacks a character (a locale
    without UTF-8, PYTHONIOENCODING=ascii) gets it as an escape (``\\u2014``), not an
    error.  (A reader that stops early, ``| head -1``, ends a run still writing quietly,
    exit 1: click's handling of EPIPE.)"""
    for name in ("stdout", "stderr"):
        stream = getattr(sys, name)
        if stream is None:
            setattr(sys, name, open(os.devnull, "w", encoding="utf-8"))  # noqa: SIM115
        elif hasattr(stream, "reconfigure"):
            stream.reconfigure(errors="backslashreplace")
    sys.stdout = _NamedOutput(sys.stdout)


class _NamedOutput:
    """Standard output whose failures name it: a write or flush that the machine refuses
    (``> file`` on a full disk, a failing disk) raises an EnvironmentFailure naming
    "standard output" with what to do, so the exit-4 message says where certkit could not
    write.  Every other attribute, and every other error (a closed pipe), is the stream's
    own."""

    def __init__(self, stream):
        self._stream = stream

    def write(self, text):
        try:
            return self._stream.write(text)
        except OSError as problem:
            raise _named(problem) from None

    def flush(self):
        try:
            return self._stream.flush()
        except OSError as problem:
            raise _named(problem) from None

    def __getattr__(self, name):
        return getattr(self._stream, name)


def _named(problem: OSError) -> Exception:
    if not is_environmental(problem) or problem.filename is not None:
        return problem
    return EnvironmentFailure.from_os_error(
        problem, "standard output", doing="cannot write",
        remedy="redirect it to a file on another disk, or let it print to the terminal")


def run() -> None:
    """Console entry point: an unexpected error is reported as a bug (exit 3)."""
    _usable_streams()
    try:
        try:
            app()
        finally:
            stop.finish()   # a stop signal from here on finds the outputs in place
    except (CertkitInputError, CampaignError, BagError) as problem:  # outside any command
        try:
            _report_user_error(problem, "certkit", "")
        except typer.Exit as exit_:
            sys.exit(exit_.exit_code)
    except EnvironmentFailure as problem:   # outside any command
        error(str(problem))
        sys.exit(4)
    except stop.Stopped as stopped:
        names = {"SIGINT": "SIGINT, Ctrl-C", "SIGTERM": "SIGTERM", "SIGHUP": "SIGHUP"}
        error(f"stopped ({names[stopped.signal_name]}); what the run had not finished "
              f"writing was removed")
        sys.exit(stopped.code)
    except Exception as problem:  # noqa: BLE001 - last resort: no traceback for users
        if os.environ.get("CERTKIT_DEBUG"):
            raise
        err.print(Text.assemble(("internal error: ", "bold red"),
                                f"{type(problem).__name__}: {problem}. This is a certkit bug; "
                                f"please report it with the campaign (set CERTKIT_DEBUG=1 to "
                                f"see the traceback)."))
        sys.exit(3)
