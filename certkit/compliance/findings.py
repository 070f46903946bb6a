"""How a data-quality check records what it found, and what it could not check.

Every check of :mod:`certkit.compliance.quality` and its companions appends through these
helpers, so a finding's id, its wording of values (the campaign's display units) and a
"not checked" entry look the same whichever check made them.
"""

from __future__ import annotations

from certkit.compliance.assessment import Assessment
from certkit.display import with_unit
from certkit.results import Finding, Unchecked


def shown(assessment: Assessment, value: float, kind: str) -> str:
    """A value in the campaign's display units, as every finding states it."""
    return with_unit(value, kind, assessment.campaign.spec.report.units)


def add(assessment: Assessment, check: str, severity: str, run: str | None, gear: str | None,
        message: str, **values) -> None:
    """Append a finding with a stable id ``QA/check[/run][/gear]``."""
    parts = ["QA", check] + [part for part in (run, gear) if part]
    identifier, taken = "/".join(parts), {f.id for f in assessment.findings}
    # the same check can find twice in one place (two channels of a run): number the
    # repeats in the order found, so every id stays unique and stable
    repeat = 2
    while identifier in taken:
        identifier = "/".join(parts) + f"#{repeat}"
        repeat += 1
    assessment.findings.append(Finding(identifier, check, severity, run, gear, message, values))


def not_checked(assessment: Assessment, check: str, where: str | None, reason: str) -> None:
    """Record that ``check`` could not run (for ``where``, or anywhere) and why."""
    item = Unchecked(check, where, reason)
    if item not in assessment.unchecked:
        assessment.unchecked.append(item)


def gear_items(assessment: Assessment):
    """(run result, gear result) of every gear unit of every run."""
    for run in assessment.runs:
        for gear in run.gears:
            yield run, gear


def rises(values: list[tuple[float, float, str]]):
    """Pairs of consecutive (height, value, run) items, sorted by height, where the height
    rises and the value does not."""
    ordered = sorted(values)
    return [(low, high) for low, high in zip(ordered, ordered[1:])
            if high[0] > low[0] and high[1] <= low[1]]
