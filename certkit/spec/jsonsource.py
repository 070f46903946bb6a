"""Reading a JSON input (a blind-check record, a baseline results file) the way the YAML
spec is read: whatever the file holds, the reader raises :class:`JsonSourceError` with a
message and, where known, the line, never Python's own errors.

Beyond malformed JSON, a file can hold what the standard reader fails on with other
errors: bytes that are not UTF-8, nesting deeper than the interpreter's recursion limit,
and integers longer than Python converts from text (4300 digits).  Integers are bounded
to :data:`MAX_INTEGER_DIGITS` here, as numbers are in the spec.
"""

from __future__ import annotations

import json
from pathlib import Path

from certkit.spec.yamlsource import MAX_NUMBER

#: The longest integer a JSON input may hold (its digits and sign).
MAX_INTEGER_DIGITS = MAX_NUMBER


class JsonSourceError(Exception):
    """A JSON input that cannot be read: ``message`` and the ``line`` (or None)."""

    def __init__(self, message: str, line: int | None = None):
        super().__init__(message)
        self.message, self.line = message, line


def _integer(text: str) -> int:
    if len(text) > MAX_INTEGER_DIGITS:
        raise JsonSourceError(f"an integer of {len(text)} digits (at most "
                              f"{MAX_INTEGER_DIGITS})")
    return int(text)


def load_json(path: str | Path) -> object:
    """The JSON document in ``path``.

    Raises
    ------
    JsonSourceError
        The file cannot be read, is not UTF-8, is not JSON, nests too deeply or holds an
        integer too long.
    """
    try:
        data = Path(path).read_bytes()
    except OSError as error:
        raise JsonSourceError(f"cannot be read: {error.strerror or error}") from None
    return parse_json(data)


def parse_json(data: bytes) -> object:
    """The JSON document in ``data`` (a file's bytes); raises :class:`JsonSourceError` as
    :func:`load_json` does."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise JsonSourceError(f"not UTF-8 text ({error.reason})") from None
    try:
        return json.loads(text, parse_int=_integer)
    except json.JSONDecodeError as error:
        raise JsonSourceError(f"not JSON: {error.msg} at line {error.lineno}, column "
                              f"{error.colno}", error.lineno) from None
    except RecursionError:
        raise JsonSourceError("not JSON certkit reads: nested too deeply") from None
