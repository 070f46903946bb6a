"""Errors a user can act on: each names the file, the line, the key and what was wrong."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class Problem:
    """One thing wrong with an input: where it is and what was expected."""

    file: str
    line: int | None
    key: str
    message: str

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}" if self.line else self.file
        return f"{where} {self.key}: {self.message}" if self.key else f"{where}: {self.message}"


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
