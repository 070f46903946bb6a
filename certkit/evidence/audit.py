"""Audit tables for CI: one row per criterion verdict and per data-quality finding, with a
stable id, as JUnit XML, Markdown, CSV or JSON.

A row's id is the verdict's (requirement clause, run and gear: ``CFR23.725a-limit-drop-
height/D300``) or the finding's (``QA/<check>/<run>/<gear>``), so the same criterion keeps
its id from one run of the audit to the next.  Values are SI, as in results.json, in the
JSON and CSV tables; the Markdown summary and the JUnit messages, which people read, show
them in the campaign's display units (:mod:`certkit.display`).

With a baseline (an earlier results.json, :mod:`certkit.evidence.comparison`), every number that
drifted beyond the tolerance, every criterion added or removed and every verdict that
changed is a row too.

Exit status of an audit (:func:`passed`): every criterion PASS, no data-quality error and
no change since the baseline.
A criterion NOT SHOWN is not a pass: compliance that is not shown must not turn CI green.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
from dataclasses import asdict, dataclass
from xml.etree import ElementTree

from certkit.compliance.assessment import Assessment
from certkit.display import margin as margin_text
from certkit.display import with_unit
from certkit.spec.schema import DisplayUnits

PASS = "PASS"
#: The kind (and id) of the row a planning campaign's audit starts with: it always fails,
#: so no CI job can turn green on predictions made from synthetic histories.
PLANNING_ROW = "planning"
#: The kind of the row of a data-quality check that could not run (JUnit: skipped).
NOT_CHECKED = "not checked"


@dataclass(frozen=True)
class AuditRow:
    id: str
    kind: str                 # "criterion", "finding", "not checked" (a check that could
                              # not run: skipped, never a failure) or "baseline" (a change)
    clause: str               # criterion: the requirement clause; finding: the check
    title: str
    run: str | None
    gear: str | None
    value: float | None       # SI
    limit: float | None       # SI
    margin: float | None      # SI: value − limit in the passing direction
    unit: str
    outcome: str              # criterion: PASS / FAIL / NOT SHOWN; finding: its severity
    message: str
    quantity: str = "ratio"   # physical kind of value, limit and margin (selects display unit)
    comparison: str = ""      # criterion: ≥ or ≤
    uncertainty: float | None = None   # SI: the margin's expanded uncertainty U
    conformance: float | None = None   # P(margin ≥ 0), JCGM 106
    decision: str = ""        # the statement under the decision rule ("pass", "conditional
                              # pass", ..., "not stated", "exact")

    @property
    def failed(self) -> bool:
        if self.kind == "criterion":
            return self.outcome != PASS
        return self.kind == PLANNING_ROW or self.outcome in ("error", "changed")


def _number(value):
    return None if value is None or not math.isfinite(value) else float(value)


def audit_rows(assessment: Assessment) -> list[AuditRow]:
    """The criteria (in the report's order), then the findings; a planning campaign's start
    with a failing row that says so."""
    rows = [AuditRow(PLANNING_ROW, PLANNING_ROW, "campaign.purpose", "planning campaign", None,
                     None, None, None, None, "", "PLANNING",
                     "campaign.purpose is planning: the verdicts are predictions computed from "
                     "synthetic histories, not compliance evidence")] if assessment.planning else []
    rows += [AuditRow(v.id, "criterion", v.clause, v.title, v.run, v.gear, _number(v.value),
                     _number(v.limit), _number(v.margin), v.unit, v.verdict, v.reason, v.kind,
                     v.comparison, *_uncertainty(v))
            for v in assessment.verdicts]
    rows += [AuditRow(f.id, "finding", f.check, f.check.replace("-", " "), f.run, f.gear, None,
                      None, None, "", f.severity, f.message)
             for f in assessment.findings]
    rows += [AuditRow("/".join(["QA-not-run", u.check] + ([u.where] if u.where else [])),
                      NOT_CHECKED, u.check, u.check.replace("-", " "), None, None, None, None,
                      None, "", "not run", u.reason)
             for u in assessment.unchecked]
    return rows


def _uncertainty(verdict) -> tuple:
    """(U, p_c, statement) of a verdict's margin (None, None, "" without a margin)."""
    found = verdict.uncertainty
    if found is None:
        return None, None, ""
    return _number(found.expanded), _number(found.conformance), found.statement


def baseline_rows(changes) -> list[AuditRow]:
    """A row per :class:`certkit.evidence.comparison.Change`; every one of them fails the audit."""
    return [AuditRow(f"baseline/{c.path}", "baseline", c.kind, c.kind, None, None,
                     c.before if isinstance(c.before, float) else None,
                     None, None, "", "changed", f"{c.detail}: baseline {c.before!r}, now "
                                                f"{c.after!r}")
            for c in changes]


def passed(rows: list[AuditRow]) -> bool:
    """True when every criterion passes and no finding is an error."""
    return not any(row.failed for row in rows)


def _text(value) -> str:
    """A cell: floats in full (the shortest text that reads back as the same number), so
    no table rounds a value silently."""
    return "" if value is None else repr(value) if isinstance(value, float) else str(value)


def to_json(rows: list[AuditRow]) -> str:
    return json.dumps([asdict(row) for row in rows], indent=1, ensure_ascii=False,
                      sort_keys=True) + "\n"


#: The CSV's columns: the uncertainty's three come last, so a reader of the columns before
#: them by position reads what it read before they were added.
COLUMNS = ("id", "kind", "clause", "title", "run", "gear", "value", "limit", "margin", "unit",
           "outcome", "message", "uncertainty", "conformance", "decision")


def to_csv(rows: list[AuditRow]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(COLUMNS)
    for row in rows:
        writer.writerow([_text(getattr(row, column)) for column in COLUMNS])
    return buffer.getvalue()


def _shown(row: AuditRow, units) -> dict:
    """A row's value, limit and margin as a person reads them (display units, 4 figures)."""
    if row.kind != "criterion":
        return {"value": "", "limit": "", "margin": ""}
    return {"value": with_unit(row.value, row.quantity, units) if row.value is not None
            else "not available",
            "limit": (f"{row.comparison} {with_unit(row.limit, row.quantity, units)}".strip()
                      if row.limit is not None else "—"),
            "margin": margin_text(row.margin, row.limit, row.quantity, units)}


def to_markdown(rows: list[AuditRow], title: str, units: DisplayUnits | None = None) -> str:
    """A summary fit for a CI job page: the counts, then every row that does not pass,
    then the full table; numbers in ``units`` (the campaign's report.units)."""
    units = units or DisplayUnits()

    def cell(row: AuditRow, column: str) -> str:
        shown = _shown(row, units)
        value = shown[column] if column in shown else _text(getattr(row, column))
        return value.replace("|", "\\|").replace("\n", " ")

    failing = [row for row in rows if row.failed]
    criteria = [row for row in rows if row.kind == "criterion"]
    planning = any(r.kind == PLANNING_ROW for r in rows)
    headline = ("PLANNING ON SYNTHETIC DATA: NOT COMPLIANCE EVIDENCE" if planning
                else "PASS" if not failing else "NOT PASSED")
    lines = [f"# Audit: {title}", "",
             f"**{headline}**: "
             f"{sum(r.outcome == PASS for r in criteria)} of {len(criteria)} criteria "
             f"{'predicted to pass' if planning else 'pass'}; "
             f"{sum(r.kind == 'finding' and r.outcome == 'error' for r in rows)} data-quality "
             f"error(s), {sum(r.kind == 'finding' and r.outcome == 'warning' for r in rows)} "
             f"warning(s)"
             + (f"; {sum(r.kind == NOT_CHECKED for r in rows)} check(s) could not run"
                if any(r.kind == NOT_CHECKED for r in rows) else "")
             + (f"; {sum(r.kind == 'baseline' for r in rows)} change(s) since the baseline"
                if any(r.kind == "baseline" for r in rows) else "") + ".", ""]
    header = ["id", "outcome", "value", "limit", "margin", "message"]
    for heading, chosen in (("Not passing", failing), ("All rows", rows)):
        if not chosen:
            continue
        lines += [f"## {heading}", "", "| " + " | ".join(header) + " |",
                  "|" + "---|" * len(header)]
        lines += ["| " + " | ".join(cell(row, column) for column in header) + " |"
                  for row in chosen]
        lines.append("")
    return "\n".join(lines)


def to_junit(rows: list[AuditRow], title: str, units: DisplayUnits | None = None) -> str:
    """JUnit XML: a test suite of criteria and one of findings, a test case per row; a
    criterion that does not PASS and a finding of severity error are failures.  Messages
    show numbers in ``units`` (the campaign's report.units)."""
    units = units or DisplayUnits()
    planning = any(r.kind == PLANNING_ROW for r in rows)
    prefix = "PLANNING (synthetic data, not compliance evidence): " if planning else ""
    root = ElementTree.Element("testsuites", name=f"certkit audit: {prefix}{title}")
    for kind, name in ((PLANNING_ROW, PLANNING_ROW), ("criterion", "criteria"),
                       ("finding", "data quality"), (NOT_CHECKED, "checks not run"),
                       ("baseline", "baseline")):
        chosen = [row for row in rows if row.kind == kind]
        if kind in ("baseline", PLANNING_ROW, NOT_CHECKED) and not chosen:
            continue
        suite = ElementTree.SubElement(root, "testsuite", name=name, tests=str(len(chosen)),
                                       failures=str(sum(row.failed for row in chosen)),
                                       errors="0",
                                       skipped=str(len(chosen) if kind == NOT_CHECKED else 0))
        for row in chosen:
            case = ElementTree.SubElement(suite, "testcase", name=row.id,
                                          classname=f"{name}.{row.clause}")
            shown = _shown(row, units)
            detail = (f"{row.outcome}: value {shown['value']}, limit {shown['limit']}, "
                      f"margin {shown['margin']}. {row.message}" if kind == "criterion"
                      else f"{row.outcome}: {row.message}")
            if kind == NOT_CHECKED:
                ElementTree.SubElement(case, "skipped", message=row.message[:200]).text = \
                    row.message
            elif row.failed:
                failure = ElementTree.SubElement(case, "failure", type=row.outcome,
                                                 message=detail[:200])
                failure.text = detail
            else:
                ElementTree.SubElement(case, "system-out").text = detail
    ElementTree.indent(root)
    text = ElementTree.tostring(root, encoding="unicode", xml_declaration=True) + "\n"
    # characters XML 1.0 cannot hold (a control character typed into a spec) would make
    # the file unreadable to every CI; each is shown as U+FFFD instead
    return _NOT_XML.sub("\ufffd", text)


_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")
