"""The assessment of a campaign: the evidence record the compliance engine fills in and
the data-quality audit, the report and the audit tables read.

Values per aircraft, requirement set, run and gear unit (each a
:class:`~certkit.results.Value` with its provenance), the criterion verdicts, the
data-quality findings and the comparison of reported against recomputed values; and the
campaign's outcome with its reasons.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from certkit.compliance.measures import GearMeasures
from certkit.results import FAIL, NOT_SHOWN, PASS, Comparison, Finding, Unchecked, Value, Verdict
from certkit.spec.campaign import Campaign
from certkit.spec.requirement_sets import RequirementSet
from certkit.spec.rundata import RunSeries
from certkit.spec.schema import BasisEntry, Run

#: The outcome of a planning campaign: it cannot be read as any of the compliance outcomes.
PLANNING = "PLANNING ONLY: NOT COMPLIANCE EVIDENCE"


class _Values:
    values: dict[str, Value]

    def get(self, key: str) -> float | None:
        """The SI magnitude of a value (None when absent or not computable)."""
        value = self.values.get(key)
        return None if value is None else value.value


@dataclass
class GearResult(_Values):
    """Everything known about one gear unit in one run."""

    run_id: str
    gear_id: str
    basis: str
    values: dict[str, Value]
    measures: GearMeasures | None = None
    #: optional spec inputs this unit's values were computed with although the spec leaves
    #: them out: symbol -> the assumption in words (printed beside every value it affects)
    assumptions: dict = field(default_factory=dict)


@dataclass
class RunResult(_Values):
    run: Run
    index: int
    values: dict[str, Value]
    gears: list[GearResult]
    series: RunSeries | None


@dataclass
class BasisResult:
    entry: BasisEntry
    rules: RequirementSet
    values: dict[str, Value]


@dataclass
class Assessment:
    """The evidence record of a campaign (inputs, derived values, verdicts, findings)."""

    campaign: Campaign
    design: dict[str, Value]
    basis: list[BasisResult]
    runs: list[RunResult]
    verdicts: list[Verdict] = field(default_factory=list)
    findings: list[Finding] = field(default_factory=list)
    comparisons: list[Comparison] = field(default_factory=list)
    unchecked: list[Unchecked] = field(default_factory=list)
    #: the measurement uncertainties (certkit.compliance.verdict_uncertainty.Budgets)
    uncertainty: object | None = None

    @property
    def planning(self) -> bool:
        """A planning campaign (campaign.purpose: planning): its verdicts are predictions."""
        return is_planning(self.campaign)

    @property
    def outcome(self) -> str:
        """COMPLIANT only when every criterion passed on evidence free of data-quality errors
        and from confirmed requirement values; otherwise what stops it.  A planning campaign
        is never compliant: its outcome is :data:`PLANNING`."""
        if self.planning:
            return PLANNING
        states = {verdict.verdict for verdict in self.verdicts}
        if FAIL in states:
            return "NOT COMPLIANT"
        if NOT_SHOWN in states or any(f.severity == "error" for f in self.findings):
            return "COMPLIANCE NOT SHOWN"
        if any(verdict.to_confirm for verdict in self.verdicts):
            return "COMPLIANT SUBJECT TO CONFIRMATION"
        return "COMPLIANT"

    def outcome_reasons(self) -> list[str]:
        """Why the outcome is what it is, in words, for the cover page."""
        counts, findings = self.counts(), self.finding_counts()
        reasons = []
        if self.planning:
            reasons.append(
                f"a planning campaign (campaign.purpose: planning): every value is computed "
                f"from simulated histories, so the verdicts below are predictions for the "
                f"planned drops and show no compliance. Predicted: {counts[PASS]} pass, "
                f"{counts[FAIL]} fail, {counts[NOT_SHOWN]} not shown")
        if counts[FAIL]:
            reasons.append(f"{counts[FAIL]} criterion verdict(s) FAIL")
        if counts[NOT_SHOWN]:
            reasons.append(f"{counts[NOT_SHOWN]} criterion verdict(s) NOT SHOWN")
        if findings["error"]:
            reasons.append(f"{findings['error']} data-quality error(s): the evidence they "
                           f"concern cannot support a compliance statement until resolved")
        unconfirmed = sorted({v.requirement_set for v in self.verdicts if v.to_confirm})
        if unconfirmed:
            reasons.append("verdicts of " + ", ".join(unconfirmed) + " rest on values to be "
                           "confirmed against the licensed standard")
        return reasons

    def counts(self) -> dict[str, int]:
        return {state: sum(v.verdict == state for v in self.verdicts)
                for state in (PASS, FAIL, NOT_SHOWN)}

    def finding_counts(self) -> dict[str, int]:
        return {level: sum(f.severity == level for f in self.findings)
                for level in ("error", "warning", "info")}


def is_planning(campaign: Campaign) -> bool:
    """campaign.purpose is planning: values come from synthetic histories, as predictions."""
    return campaign.spec.campaign.purpose == "planning"


