"""What the evidence falls short of, in words: why the outcome is not COMPLIANT (page 1,
one line per reason) and which values rest on an input the spec leaves out (marked, with
the assumption printed once)."""

from __future__ import annotations

from certkit.compliance.assessment import Assessment
from certkit.results import FAIL, PASS, Value


def cover_reasons(assessment: Assessment) -> list[str]:
    """Why the outcome is not COMPLIANT, one line per reason, for page 1: every shortfall
    that holds a criterion at FAIL or NOT SHOWN with the criteria it holds back and what
    would show them, then every data-quality error."""
    groups: dict[tuple, dict] = {}
    for verdict in assessment.verdicts:
        if verdict.verdict == PASS:
            continue
        group = groups.setdefault((verdict.verdict, verdict.shortfall or verdict.reason,
                                   verdict.remedy), {})
        scopes = group.setdefault((verdict.clause, verdict.title), [])
        scope = " / ".join(p for p in (verdict.run, verdict.gear) if p)
        if scope:
            scopes.append(scope)
    lines = []
    for (state, shortfall, remedy), criteria in groups.items():
        held = "; ".join(f"{clause}, {title[:1].lower() + title[1:]}"
                         + (f" ({', '.join(scopes)})" if scopes else "")
                         for (clause, title), scopes in criteria.items())
        lines.append(f"{state} because {shortfall}: {held}."
                     + (f" To show it: {remedy}." if remedy and state != FAIL
                        else f" To resolve: {remedy}." if remedy else ""))
    lines += [f"Data-quality error {f.id}: {f.message}" for f in assessment.findings
              if f.severity == "error"]
    return lines


#: The mark of a value computed with an input the spec leaves out (its assumption is
#: printed under the table, and beside the value in the run details).
ASSUMED = "‡"


def assumed_mark(value: Value | None, gear) -> str:
    """:data:`ASSUMED` when ``value`` was computed with one of ``gear``'s assumptions."""
    if value is None or value.value is None:
        return ""
    return ASSUMED if any(symbol in value.inputs for symbol in gear.assumptions) else ""


def results_assumptions(assessment: Assessment) -> list[str]:
    """Each assumption a value of the results table rests on, once, with its gear units."""
    found: dict[str, list[str]] = {}
    for run in assessment.runs:
        for gear in run.gears:
            for words in gear.assumptions.values():
                units = found.setdefault(words, [])
                if gear.gear_id not in units:
                    units.append(gear.gear_id)
    return [f"{words} ({', '.join(units)})" for words, units in found.items()]
