"""The typed view of the report: one frozen dataclass per section, as the templates read it.

Every string is already formatted (numbers in the campaign's display units); the templates
only lay the sections out.  Rows of a table are plain mappings of formatted cells.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class CampaignSection:
    id: str
    title: str
    description: str


@dataclass(frozen=True)
class DocumentSection:
    report_number: str
    revision: str
    date: str
    applicant: str
    facility: str
    test_dates: str
    checklist: str
    signatories: list[dict]
    revisions: list[dict]


@dataclass(frozen=True)
class AircraftSection:
    model: str
    notes: str


@dataclass(frozen=True)
class InstrumentationSection:
    sampling_rate: str
    logger: str
    channels: list[dict]


@dataclass(frozen=True)
class ModelSection:
    """Appendix A: the drop model, calibrated on the training runs, validated on the others."""

    method: str
    intro: str                   # what the appendix is, what data, not compliance evidence
    synthetic: str
    note: str
    failures: list[str]          # gear units not computed: why, what to change
    gears: list[dict]
    effects: str
    reference_rows: list[dict]
    reference: dict | None


@dataclass(frozen=True)
class IdentificationSection:
    """Appendix B: Hammerstein, Wiener and NARX models, and the protocol they follow."""

    intro: str
    available: bool
    gears: list[dict]
    plant_note: str
    note: str
    failures: list[str]
    window: str
    paper_samples: str
    tolerance: str
    whiteness: str
    gain: str
    length_unit: str
    force_unit: str
    reference: dict | None
    protocols: str


@dataclass(frozen=True)
class BlindSection:
    """The blind check's record, or why there is none."""

    recorded: bool
    command: str
    absent: str = ""
    file: str = ""
    sha256: str = ""
    template: str = ""
    truths: str = ""
    cases: str = ""
    settings: object = None
    metrics: list[dict] = field(default_factory=list)
    verdict: str = ""
    confusion: dict | None = None
    curve: list[dict] = field(default_factory=list)
    curve_figure: dict | None = None
    forms: list[dict] = field(default_factory=list)
    #: the sealed battery's record beside the development one ("" / []: none named)
    sealed: str = ""
    comparison: list[dict] = field(default_factory=list)


@dataclass(frozen=True)
class GapSection:
    """Appendix C: where the model disagrees, which effect explains it, how far it shrinks."""

    intro: str
    available: bool
    note: str
    notes: list[str]
    failures: list[str]
    gears: list[dict]
    blind: BlindSection
    time_unit: str
    split: str
    where: str
    which: str
    missing_force: str
    candidates: list[dict]


@dataclass(frozen=True)
class ReportView:
    """Everything the report shows, section by section."""

    lang: str
    title: str
    campaign: CampaignSection
    document: DocumentSection
    created: str
    outcome: str
    outcome_css: str
    planning: bool
    headings: dict                  # section anchor -> numbered or lettered heading
    contents: list                  # (anchor, numbered heading) in order
    conclusions: dict               # what is shown, not shown, open (lists of sentences)
    references: list
    outcome_reasons: list[str]
    cover_reasons: list[str]        # page 1: each reason a criterion is not PASS, one line
    cover_reasons_title: str
    model_left_out: str             # one line when the report has no model appendices
    counts: dict[str, int]
    finding_counts: dict[str, int]
    aircraft: AircraftSection
    design: list[dict]
    basis: list[dict]
    any_to_confirm: bool
    gear_units: list[dict]
    setup: list[tuple]              # (label, value as stated or "not stated")
    instrumentation: InstrumentationSection | None
    matrix: list[dict]
    completeness: list[dict]
    results_rows: list[dict]
    results_assumptions: list[str]  # what a value marked ‡ was computed with
    results_units: dict[str, str]
    load_factors: list[dict]
    load_factor_statement: str
    load_factor_columns: dict[str, bool]
    runs: list[dict]
    verdicts: list[dict]
    uncertainty: dict | None        # the rule, inputs, budgets and figure (uncertainty_view)
    findings: list[dict]
    comparisons: list[dict]
    not_checked: list[dict]
    equations: list[tuple[str, str]]
    gravity_note: str
    display_rule: str
    assumptions: list[str]
    audit: dict[str, str]
    provenance: dict
    version: str
    model: ModelSection | None           # the appendices (None: left out, model_left_out)
    identification: IdentificationSection | None
    gap: GapSection | None
