"""Errors a user can act on: each names the file, the line, the key and what was wrong."""

from __future__ import annotations

import math
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


class CampaignError(Exception):
    """What a valid campaign can still cause and its user can act on, though no key is wrong:
    a drop model that cannot be simulated, residuals that cannot be evaluated, a blind check
    with nowhere to run.  The CLI exits with code 2 and names the campaign (or bag)."""


def key_path(location: tuple) -> str:
    """('runs', 2, 'drop_height') -> 'runs[2].drop_height'."""
    text = ""
    for part in location:
        if isinstance(part, int):
            text += f"[{part}]"
        else:
            text += f".{part}" if text else str(part)
    return text
