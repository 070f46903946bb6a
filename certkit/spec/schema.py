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
    id: Identifier
    title: Text
    description: str | None = None
    purpose: Literal["certification", "planning"] = Field(
        "certification",
        description="planning: a campaign planned before there is a rig; every value is "
                    "computed from its (synthetic) histories, every page is marked PLANNING "
                    "and the outcome is never a compliance statement")


class Signatory(SpecBlock):
    role: Literal["prepared", "checked", "verified", "approved", "witnessed"]
    name: Text
    organisation: str | None = None
    date: Date | None = None


class Revision(SpecBlock):
    revision: Text
    date: Date
    description: Text


class Document(SpecBlock):
    report_number: Text
    revision: Text
    date: Date = Field(description="Issue date; also fixes every date written into outputs")
    applicant: Text
    facility: Text
    test_dates: list[Date] = Field(min_length=1)
    signatories: list[Signatory] = Field(min_length=1)
    revisions: list[Revision] = []
    compliance_checklist_item: str | None = None


class BasisEntry(SpecBlock):
    requirement_set: Text = Field(description="id of a shipped requirement set, see `certkit sets`")
    edition: str | None = Field(None, description="edition the applicant is certifying against")
    ground_load_dynamic_test: bool = Field(
        False, description="strength shown dynamically by drop test (14 CFR 23.726)")


# --------------------------------------------------------------------------- claims, references
class CampaignReported(SpecBlock):
    wing_loading: WingLoading | None = None
    required_drop_height: PositiveLength | None = None


class ReferenceModelErrors(SpecBlock):
    """Published free-run RMSEs of one output, per model (each a length with its unit)."""

    governing_equation: Length | None = Field(None, description="the physics (EOM) model")
    hammerstein: Length | None = None
    wiener: Length | None = None
    narx: Length | None = None


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
    campaign: CampaignInfo
    document: Document
    certification_basis: list[BasisEntry] = Field(min_length=1)
    aircraft: Aircraft
    gear_units: list[GearUnit] = Field(min_length=1)
    instrumentation: Instrumentation | None = None
    setup: TestSetup | None = Field(None, description="how the drops were set up and conducted")
    runs: list[Run] = Field(min_length=1)
    reported: CampaignReported | None = None
    reference_results: ReferenceResults | None = Field(
        None, description="published model errors for these drops (shown beside certkit's)")
    assumptions: list[str] = []
    audit: AuditSettings = AuditSettings()
    model: ModelSettings = ModelSettings()
    report: ReportSettings = ReportSettings()
    uncertainty: UncertaintySpec | None = Field(
        None, description="measurement uncertainties and the decision rule (none: every "
                          "uncertainty not stated, simple acceptance)")


def json_schema() -> dict:
    """JSON Schema of the campaign spec (for editors and CI)."""
    schema = CampaignSpec.model_json_schema()
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = "certkit campaign spec"
    return schema
