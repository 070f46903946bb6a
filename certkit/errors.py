"""Errors a user can act on: each names the file, the line, the key and what was wrong."""

from __future__ import annotations

import errno
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

#: The longest a user's value is quoted in a message; longer ones are cut with their length.
ECHO_LIMIT = 60
#: Control characters (C0, DEL, C1) and the Unicode line and paragraph separators.
_CONTROL = re.compile(r"[\x00-\x1f\x7f-\x9f\u2028\u2029]")


def escaped(text: str) -> str:
    """``text`` with every control character written as an escape (``\\x00``, ``\\x1b``,
    ``\\n``), so a message never carries a raw one to the terminal or a log."""
    return _CONTROL.sub(lambda found: repr(found.group())[1:-1], text)


def shown(value: object) -> str:
    """A user's value as a message quotes it: text in double quotes, anything else as
    Python writes it, control characters escaped, at most :data:`ECHO_LIMIT` characters
    (a longer one is cut with an ellipsis and its length, so a 100 kB value costs nothing).
    """
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 200:
        digits = int(value.bit_length() * math.log10(2)) + 1   # str() of it may be refused
        return f"a number of about {digits} digits"
    text = value if isinstance(value, str) else repr(value)
    cut = f"{text[:ECHO_LIMIT - 1]}…" if len(text) > ECHO_LIMIT else text
    quoted = f'"{escaped(cut)}"' if isinstance(value, str) else escaped(cut)
    return f"{quoted} ({len(text)} characters)" if len(text) > ECHO_LIMIT else quoted


@dataclass(frozen=True)
class Problem:
    """One thing wrong with an input: where it is and what was expected."""

    file: str
    line: int | None
    key: str
    message: str

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}" if self.line else self.file
        text = f"{where} {self.key}: {self.message}" if self.key else f"{where}: {self.message}"
        return escaped(text)


class CertkitInputError(Exception):
    """Bad input (campaign spec, data file, CLI argument). The CLI exits with code 2."""

    def __init__(self, problems: list[Problem]):
        self.problems = list(problems)
        super().__init__("\n".join(str(p) for p in self.problems))

    @classmethod
    def single(cls, file: str | Path, line: int | None, key: str, message: str):
        return cls([Problem(str(file), line, key, message)])

    def __reduce__(self):
        # made again from its problems (raised in a worker process, reported by the parent;
        # the default passes the joined message to __init__, which reads it as one-letter
        # problems, so str() came out a letter a line)
        return type(self), (self.problems,)


class DataInputError(CertkitInputError, ValueError):
    """Bad data or settings given to a library function from code (a notebook's arrays, an
    estimator's hyper-parameters), not read from a file: names the argument, says what was
    expected and what was found.  A ValueError too, as scikit-learn's conventions expect."""

    def __init__(self, name: str, message: str):
        super().__init__([Problem("argument", None, name, message)])

    def __reduce__(self):
        # made again from its argument's name and message (a worker process raises it and
        # the search's process reports it)
        return type(self), (self.problems[0].key, self.problems[0].message)


class KeywordArgumentError(DataInputError, TypeError):
    """A parameter given by position where certkit takes it by keyword only (an estimator's
    hyper-parameters): a TypeError, as Python raises for a call its signature refuses, that
    names the parameter and shows the call written with keywords."""


class CertkitWarning(UserWarning):
    """Something a user can act on though nothing failed (a tuned value at the edge of its
    search range): the base of certkit's warnings, so that they can be filtered as one."""


class CampaignError(Exception):
    """What a valid campaign can still cause and its user can act on, though no key is wrong:
    a drop model that cannot be simulated, residuals that cannot be evaluated, a blind check
    with nowhere to run.  The CLI exits with code 2 and names the campaign (or bag)."""


class EnvironmentFailure(Exception):
    """The machine refused what certkit needed: no space left, no permission, a read-only
    file system, another run writing the same folder.  Nothing is wrong with the campaign
    or with certkit; the CLI prints the message (it names the path) and exits with code 4.
    """

    def __init__(self, path: str | Path, message: str):
        self.path = str(path)
        super().__init__(f"{path}: {message}")

    @classmethod
    def from_os_error(cls, error: OSError, path: str | Path | None = None,
                      doing: str = "cannot write the outputs", remedy: str | None = None):
        """The failure ``error`` as one line: ``path`` (the folder or file the user named;
        the error's own file name when not given), what failed, why and what to do (the
        errno's usual remedy unless ``remedy`` is given)."""
        path = path if path is not None else os.fsdecode(error.filename or "certkit")
        why, usual = _ENVIRONMENT.get(error.errno, (None, "check the folder and try again"))
        remedy = usual if remedy is None else remedy
        why = why or error.strerror or str(error)
        return cls(path, f"{doing}: {why}{named_file(error, path)}; {remedy}")


def named_file(error: OSError, path: str | Path) -> str:
    """' (the file the error names)' when it is not ``path`` itself, else ''."""
    if error.filename is None or os.fsdecode(error.filename) == str(path):
        return ""
    return f" ({os.fsdecode(error.filename)})"


# errno -> (what happened, what to do): the failures that come from the machine, not from
# the campaign or from certkit.  Any OSError met while writing outputs is reported as an
# EnvironmentFailure; elsewhere only these are (see certkit.cli.app).
_ANOTHER_DISK = "free some space, or choose a folder on another disk"
_PERMISSION = "check the permissions, or choose a folder you may write to"
_ENVIRONMENT = {
    errno.ENOSPC: ("no space left on the device", _ANOTHER_DISK),
    getattr(errno, "EDQUOT", errno.ENOSPC): ("the disk quota is exceeded", _ANOTHER_DISK),
    errno.EFBIG: ("a file is too large for this file system", "choose a folder on another "
                                                              "disk"),
    errno.EACCES: ("permission denied", _PERMISSION),
    errno.EPERM: ("operation not permitted", _PERMISSION),
    errno.EROFS: ("the file system is read-only", "choose a folder on a writable disk"),
    errno.EIO: ("input/output error (a failing disk or a lost network share)",
                "check the disk or share and try again"),
    errno.EMFILE: ("too many open files", "close other programs or raise the limit "
                                          "(ulimit -n) and try again"),
    errno.ENFILE: ("too many open files on the system", "try again later"),
}


def is_environmental(error: BaseException) -> bool:
    """An OSError that comes from the machine (full, forbidden, read-only, failing)."""
    return isinstance(error, OSError) and error.errno in _ENVIRONMENT


def key_path(location: tuple) -> str:
    """('runs', 2, 'drop_height') -> 'runs[2].drop_height'."""
    text = ""
    for part in location:
        if isinstance(part, int):
            text += f"[{part}]"
        else:
            text += f".{part}" if text else str(part)
    return text
