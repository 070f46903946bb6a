"""The campaign spec: one pydantic schema that validates, documents and exports JSON Schema.

Every dimensional value is a string with its unit, parsed by pint into SI
(:mod:`certkit.units`).  Unknown keys are errors.  Cross-references (a run
naming a gear unit that does not exist, ...) are checked in
:mod:`certkit.spec.campaign`, where the line numbers are known.

The blocks live by what they describe: the airplane and its gear units in
:mod:`certkit.spec.aircraft`, the instrumentation, set-up and runs in
:mod:`certkit.spec.runs`, the audit, display and drop-model settings in
:mod:`certkit.spec.settings`, the uncertainties in :mod:`certkit.spec.uncertainty`.  This
module holds the document blocks and the whole spec, and every block is importable from it.
"""


from __future__ import annotations

from typing import Literal

from pydantic import Field

from certkit.spec.aircraft import (Aircraft, GearUnit, HeatTransferSpec, LegSpec,
                                   MeteringPinSpec, OilSpec, SealFrictionSpec, Strut,
                                   TestArticle, Tyre, TyreCurve)
from certkit.spec.runs import (AccelerationColumn, Column, GearChannels, Inspection,
                               InstrumentChannel, Instrumentation, LengthColumn, Lift,
                               LoadColumn, PlatformSpec, ReportedGear, ReportedRun, Run,
                               RunData, TestSetup, TimeColumn, WaivableCheck, Waiver)
from certkit.spec.settings import (UNIT_SYSTEMS, AuditSettings, BlockModelSpec,
                                   CalibrationParameter, CalibrationSpec, DisplayUnits, Effect,
                                   GapSpec, IdentificationSpec, ModelSettings, ReportSettings,
                                   SensorSpec, SmallSignalSpec)
from certkit.spec.types import (Date, Duration, Identifier, Length, PositiveLength, SpecBlock,
                                Text, WingLoading)
from certkit.spec.uncertainty import UncertaintySpec

#: The spec's blocks and names, wherever they are defined.
__all__ = [
    "AccelerationColumn", "Aircraft", "AuditSettings", "BasisEntry", "BlockModelSpec",
    "CalibrationParameter", "CalibrationSpec", "CampaignInfo", "CampaignReported",
    "CampaignSpec", "Column", "DisplayUnits", "Document", "Effect", "GapSpec", "GearChannels",
    "GearUnit", "HeatTransferSpec", "IdentificationSpec", "Inspection", "InstrumentChannel",
    "Instrumentation", "LegSpec", "LengthColumn", "Lift", "LoadColumn", "MeteringPinSpec",
    "ModelSettings", "OilSpec", "PlatformSpec", "ReferenceModelErrors", "ReferenceResults",
    "ReportSettings", "ReportedGear", "ReportedRun", "Revision", "Run", "RunData",
    "SealFrictionSpec", "SensorSpec", "Signatory", "SmallSignalSpec", "Strut", "TestArticle",
    "TestSetup", "TimeColumn", "Tyre", "TyreCurve", "UNIT_SYSTEMS", "UncertaintySpec",
    "WaivableCheck", "Waiver", "json_schema"]


# --------------------------------------------------------------------------- document
class CampaignInfo(SpecBlock):
    """The campaign's identity and purpose."""

    id: Identifier = Field(description="the campaign's identifier, on the report's cover and "
                                       "in its archive and catalog entry")
    title: Text = Field(description="the campaign's title, heading the report's cover and "
                                    "every page")
    description: str | None = Field(None, description="what the campaign is, in a paragraph "
                                                      "printed on the report's cover")
    purpose: Literal["certification", "planning"] = Field(
        "certification",
        description="planning: a campaign planned before there is a rig; every value is "
                    "computed from its (synthetic) histories, every page is marked PLANNING "
                    "and the outcome is never a compliance statement")


class Signatory(SpecBlock):
    """One sign-off of the report, listed on its cover with a space to sign."""

    role: Literal["prepared", "checked", "verified", "approved", "witnessed"] = Field(
        description="what the signatory did; the cover has a line for prepared, checked, "
                    "approved and witnessed whether named or not")
    name: Text = Field(description="the signatory's name")
    organisation: str | None = Field(None, description="the signatory's organisation")
    date: Date | None = Field(None, description="date of the signature")


class Revision(SpecBlock):
    """One entry of the report's record of revisions."""

    revision: Text = Field(description="the revision's letter or number")
    date: Date = Field(description="date of the revision")
    description: Text = Field(description="what the revision changed")


class Document(SpecBlock):
    """The report as a controlled document: number, revision, issue date, applicant, facility,
    test dates and sign-off."""

    report_number: Text = Field(description="the report's number, on its cover, its running "
                                            "header and in its archive")
    revision: Text = Field(description="the report's current revision, beside its number")
    date: Date = Field(description="issue date; also fixes every date written into outputs")
    applicant: Text = Field(description="who applies for certification (the archive's source "
                                        "organisation)")
    facility: Text = Field(description="where the drops were made")
    test_dates: list[Date] = Field(
        min_length=1, description="the dates of the drops: the cover lists them, and a run "
                                  "without its own date has each channel's calibration "
                                  "checked against every one")
    signatories: list[Signatory] = Field(
        min_length=1, description="who prepared, checked, verified, approved or witnessed the "
                                  "report")
    revisions: list[Revision] = Field([], description="the record of revisions, on the cover")
    compliance_checklist_item: str | None = Field(
        None, description="the applicant's compliance checklist item for this report, shown "
                          "on its cover ('—' when not given)")


class BasisEntry(SpecBlock):
    """One requirement set the campaign shows compliance with."""

    requirement_set: Text = Field(description="id of a shipped requirement set, see `certkit sets`")
    edition: str | None = Field(None, description="edition the applicant is certifying against")
    ground_load_dynamic_test: bool = Field(
        False, description="strength shown dynamically by drop test (14 CFR 23.726): only "
                           "then does the 23.726 drop-height criterion apply")


# --------------------------------------------------------------------------- claims, references
class CampaignReported(SpecBlock):
    """Figures an earlier report states for the whole campaign, which the audit checks."""

    wing_loading: WingLoading | None = Field(
        None, description="W/S as the source states it (a force per area): compared with "
                          "aircraft.maximum_weight/aircraft.wing_area")
    required_drop_height: PositiveLength | None = Field(
        None, description="the required drop height the source states (a length): compared "
                          "with h_req of the first certification basis entry, a match in "
                          "another unit named a unit slip")


class ReferenceModelErrors(SpecBlock):
    """Published free-run RMSEs of one output, per model (each a length with its unit)."""

    governing_equation: Length | None = Field(None, description="the physics (EOM) model")
    hammerstein: Length | None = Field(None, description="the Hammerstein model")
    wiener: Length | None = Field(None, description="the Wiener model")
    narx: Length | None = Field(None, description="the NARX model")


class ReferenceResults(SpecBlock):
    """Results a source published for this campaign's drops, shown beside certkit's own.

    Only a campaign that has such a source fills this block; the report shows reference
    figures nowhere else.
    """

    source: Text = Field(description="where the figures are published (paper, table, figure)")
    gear: Identifier | None = Field(None, description="gear unit the figures are for")
    run: Identifier | None = Field(None, description="run the figures are for (if stated)")
    window: Duration = Field(description="interval from touchdown the RMSEs are taken over")
    note: str | None = Field(None, description="caveats of the source (unit not stated, ...)")
    stroke: ReferenceModelErrors | None = Field(None, description="strut stroke RMSEs")
    tyre: ReferenceModelErrors | None = Field(None, description="tyre deflection RMSEs")


# --------------------------------------------------------------------------- the spec
class CampaignSpec(SpecBlock):
    """A drop-test campaign: who, what aircraft, which gear, which runs, against which rules."""

    certkit: Literal[1] = Field(description="spec format version")
    campaign: CampaignInfo = Field(description="the campaign's identity and purpose")
    document: Document = Field(description="the report as a controlled document")
    certification_basis: list[BasisEntry] = Field(
        min_length=1, description="the requirement sets compliance is shown with")
    aircraft: Aircraft = Field(description="the airplane: weight, wing area, load factors")
    gear_units: list[GearUnit] = Field(min_length=1, description="the landing-gear units "
                                                                 "tested")
    instrumentation: Instrumentation | None = Field(None, description="the logger and the "
                                                                      "transducers")
    setup: TestSetup | None = Field(None, description="how the drops were set up and conducted")
    runs: list[Run] = Field(min_length=1, description="the drops, in the order the report "
                                                      "lists them")
    reported: CampaignReported | None = Field(
        None, description="figures of an earlier report to audit (wing loading, required drop "
                          "height)")
    reference_results: ReferenceResults | None = Field(
        None, description="published model errors for these drops (shown beside certkit's)")
    assumptions: list[str] = Field([], description="assumptions the applicant declares, each "
                                                   "listed in the report's data-quality "
                                                   "section")
    audit: AuditSettings = Field(AuditSettings(), description="thresholds of the data-quality "
                                                              "audit")
    model: ModelSettings = Field(ModelSettings(), description="the drop model and its "
                                                              "appendices (not compliance "
                                                              "evidence)")
    report: ReportSettings = Field(ReportSettings(), description="how the report shows its "
                                                                 "numbers")
    uncertainty: UncertaintySpec | None = Field(
        None, description="measurement uncertainties and the decision rule (none: every "
                          "uncertainty not stated, simple acceptance)")


def json_schema() -> dict:
    """JSON Schema of the campaign spec (for editors and CI)."""
    schema = CampaignSpec.model_json_schema()
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = "certkit campaign spec"
    return schema
