"""Versioned requirement sets shipped with certkit, as data files beside this module.

A set names its clauses, formulas and coefficients; the checks that evaluate them
live in :mod:`certkit.compliance.criteria`, looked up by each criterion's ``check`` name.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from pathlib import Path

import yaml

from certkit.units import parse_quantity

_HERE = Path(__file__).parent


@dataclass(frozen=True)
class Criterion:
    id: str
    clause: str
    title: str
    formula: str
    check: str
    applies_if: str | None = None


@dataclass(frozen=True)
class RequirementSet:
    id: str
    title: str
    edition: str
    status: str  # "verified" or "to_confirm"
    status_note: str
    parameters: dict
    criteria: tuple[Criterion, ...]
    source_file: str

    @property
    def to_confirm(self) -> bool:
        """True when the values must be confirmed against a licensed standard."""
        return self.status == "to_confirm"

    def length(self, name: str) -> float | None:
        """A length parameter in metres (``None`` when the set does not define it)."""
        value = self.parameters.get(name)
        return None if value is None else parse_quantity(value, "length").si

    def number(self, name: str) -> float:
        return float(self.parameters[name])


def available() -> list[str]:
    """Ids of the shipped requirement sets."""
    return sorted(path.stem for path in _HERE.glob("*.yaml"))


@cache
def load(set_id: str) -> RequirementSet:
    """Load a shipped requirement set by id; a bad id lists the valid ones."""
    path = _HERE / f"{set_id}.yaml"
    if set_id not in available():
        raise KeyError(f"unknown requirement set {set_id!r}; available: {', '.join(available())}")
    raw = yaml.safe_load(path.read_text(encoding="utf-8"))
    criteria = tuple(Criterion(**item) for item in raw["criteria"])
    return RequirementSet(
        id=raw["id"], title=raw["title"], edition=raw["edition"], status=raw["status"],
        status_note=" ".join(raw["status_note"].split()), parameters=raw["parameters"],
        criteria=criteria, source_file=path.name)
