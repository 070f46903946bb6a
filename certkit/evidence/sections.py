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
    """Section 9: the governing-equation model, calibrated against the runs."""

    method: str
    available: bool
    note: str
    synthetic: str
    gears: list[dict]
    effects: str
    reference_rows: list[dict]
    reference: dict | None


@dataclass(frozen=True)
class IdentificationSection:
    """Section 10: Hammerstein, Wiener and NARX models, and the protocol they follow."""

    available: bool
    gears: list[dict]
    plant_note: str
    note: str
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


@dataclass(frozen=True)
class GapSection:
    """Section 11: where the model disagrees, which effect explains it, how far it shrinks."""

    available: bool
    note: str
    notes: list[str]
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
    headings: dict                  # section anchor -> numbered heading
    contents: list                  # (anchor, numbered heading) in order
    conclusions: dict               # what is shown, not shown, open (lists of sentences)
    references: list
    outcome_reasons: list[str]
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
    results_units: dict[str, str]
    load_factors: list[dict]
    load_factor_statement: str
    load_factor_columns: dict[str, bool]
    runs: list[dict]
    verdicts: list[dict]
    findings: list[dict]
    comparisons: list[dict]
    equations: list[tuple[str, str]]
    gravity_note: str
    display_rule: str
    assumptions: list[str]
    audit: dict[str, str]
    provenance: dict
    version: str
    model: ModelSection
    identification: IdentificationSection
    gap: GapSection
