"""The campaign spec: one pydantic schema that validates, documents and exports JSON Schema.

Every dimensional value is a string with its unit, parsed by pint into SI
(:mod:`certkit.units`).  Unknown keys are errors.  Cross-references (a run
naming a gear unit that does not exist, ...) are checked in
:mod:`certkit.spec.campaign`, where the line numbers are known.
"""


from __future__ import annotations

import re
from typing import Literal

from pydantic import Field, field_validator, model_validator
from pydantic_core import PydanticCustomError

from certkit.spec.types import (Area, ClockTime, Damping, Date, Density, Duration, Energy,
                                Force, Fraction, Frequency, Identifier, Inclination, Length, Mass,
                                NonNegativeMass, PositiveLength, PositiveNumber, Pressure,
                                SpecBlock, Stiffness, Text, Volume, Weight, WingLoading,
                                quantity, unit_text)
from certkit.spec.uncertainty import UncertaintySpec
from certkit.units import parse_quantity


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


# --------------------------------------------------------------------------- aircraft
class Aircraft(SpecBlock):
    model: Text
    maximum_weight: Weight
    wing_area: Area
    design_limit_inertia_load_factor: PositiveNumber | None = Field(
        None, description="limit inertia load factor used in the 23.473 landing conditions")
    wing_lift_ratio: Fraction = Field(description="L: assumed wing lift / weight used in the loads basis")
    design_landing_weight: Weight | None = None
    notes: str | None = None


class TyreCurve(SpecBlock):
    """Static load-deflection law f(δ) = reference_load·(δ/reference_deflection)^exponent."""

    reference_load: Force
    reference_deflection: PositiveLength
    exponent: PositiveNumber


class Tyre(SpecBlock):
    size: Text
    pressure: Pressure
    pressure_reference: Literal["gauge", "absolute"]
    diameter: PositiveLength | None = None
    load_deflection: TyreCurve | None = Field(None, description="static curve (physics model)")
    hysteresis: Fraction | None = Field(
        None, description="half-width of the loading/unloading loop as a share of f(δ)")
    damping: quantity("slowness", "C_T of F = f(δ)·(1 + C_T·δ̇), e.g. '0.05 s/m'") | None = None  # type: ignore[valid-type]


class MeteringPinSpec(SpecBlock):
    """Net orifice area against stroke (linear between points)."""

    strokes: list[Length] = Field(min_length=2)
    areas: list[Area] = Field(min_length=2)


class SealFrictionSpec(SpecBlock):
    """Seal friction F = (constant + pressure_factor·|F_gas| + breakaway·exp(−(ṡ/v_s)²))·sign(ṡ)."""

    constant: Force
    pressure_factor: Fraction = Field(parse_quantity("0", "dimensionless"))
    breakaway: Force = Field(parse_quantity("0 N", "force"),
                             description="Stribeck excess of static over Coulomb friction")
    stribeck_velocity: quantity("velocity", exclusive=True) = Field(  # type: ignore[valid-type]
        parse_quantity("10 mm/s", "velocity"))


class HeatTransferSpec(SpecBlock):
    """Gas-to-wall heat transfer (effect 'heat-transfer'): replaces the polytropic law."""

    time_constant: Duration = Field(description="τ = m·c_v/(h·A), e.g. '1 s'")
    ratio_of_specific_heats: PositiveNumber = Field(parse_quantity("1.4", "dimensionless"))


class OilSpec(SpecBlock):
    """Oil compressibility (effect 'oil-compressibility'): k_oil = β·A_h²/V_oil."""

    bulk_modulus: Pressure = Field(description="effective β, e.g. '1.5 GPa' (less if aerated)")
    volume: Volume = Field(description="oil volume between piston and orifice")


class LegSpec(SpecBlock):
    """Gear-leg flexibility (effect 'leg-flexibility'): axle mass on a leg spring."""

    axle_mass: Mass = Field(description="axle and wheel, part of the unsprung mass")
    stiffness: Stiffness
    damping: Damping = Field(parse_quantity("0 N*s/m", "damping"))


class Strut(SpecBlock):
    """Servicing and geometry of the shock strut (used by the physics model)."""

    gas_precharge_pressure: Pressure | None = None
    pressure_reference: Literal["gauge", "absolute"] | None = None
    gas_volume: Volume | None = None
    pneumatic_area: Area | None = None
    hydraulic_area: Area | None = None
    orifice_diameter: PositiveLength | None = None
    orifice_area: Area | None = None
    rebound_orifice_diameter: PositiveLength | None = None
    discharge_coefficient: PositiveNumber | None = None
    oil_density: Density | None = None
    polytropic_exponent: PositiveNumber | None = None
    inclination: Inclination | None = None
    static_stroke: Length | None = None
    minimum_stroke: Length | None = None
    unsprung_mass: NonNegativeMass | None = Field(
        None, description="wheel, tyre, brake, axle and piston below the strut: the energies "
                          "need it (certkit E1, E5); 0 declares it negligible; the drop model "
                          "needs it positive")
    seal_friction: SealFrictionSpec | None = None
    metering_pin: MeteringPinSpec | None = None
    heat_transfer: HeatTransferSpec | None = None
    oil: OilSpec | None = None
    notes: str | None = None


class TestArticle(SpecBlock):
    """What was tested, as the conformity record identifies it, and how it was serviced."""

    part_number: str | None = None
    serial_number: str | None = None
    drawing: str | None = Field(None, description="drawing number and revision")
    conformity_record: str | None = Field(
        None, description="conformity inspection record of the test article (e.g. FAA Form "
                          "8100-1 number)")
    tyre_part_number: str | None = None
    tyre_ply_rating: str | None = None
    oil_volume: Volume | None = Field(None, description="oil volume as serviced for the test")
    gas_pressure: Pressure | None = Field(
        None, description="gas pressure as serviced, a pressure such as '180 psi' (gauge or "
                          "absolute as strut.pressure_reference says)")
    gas_temperature: str | None = Field(
        None, description="temperature at which the gas was charged, e.g. '18 degC'")


class GearUnit(SpecBlock):
    id: Identifier
    position: Literal["main", "nose", "tail"]
    static_weight: Weight = Field(description="W of 14 CFR 23.725(b) for this unit")
    static_weight_basis: Literal["level-attitude-nose-wheel-clear", "tail-down-attitude",
                                 "nose-reaction-1g-down-0.33g-forward", "assumed"] = Field(
        description="how W was obtained: one of the 23.725(b) definitions, or 'assumed'")
    static_weight_note: str | None = None
    shock_absorber: Text
    design_stroke: PositiveLength
    tyre: Tyre
    strut: Strut | None = None
    leg: LegSpec | None = None
    wheel_diameter: PositiveLength | None = None
    article: TestArticle | None = Field(None, description="the test article's identity and "
                                                        "servicing")


# --------------------------------------------------------------------------- instrumentation and data
class InstrumentChannel(SpecBlock):
    name: Text
    measures: Text
    transducer: str | None = None
    range: str | None = None
    filter: str | None = None
    calibration_date: Date | None = None
    calibration_due: Date | None = Field(None, description="date the calibration expires")
    calibration_reference: str | None = Field(None, description="calibration certificate")


class PlatformSpec(SpecBlock):
    """The drop rig's platform on its load cells (effect 'platform-compliance')."""

    mass: Mass
    stiffness: Stiffness = Field(description="load cells and foundation under the platform")
    damping: Damping = Field(parse_quantity("0 N*s/m", "damping"))


class TestSetup(SpecBlock):
    """How the drops were set up and conducted: the applicant's statement, reported as given
    (certkit cannot check it); what is absent is reported as not stated."""

    rig: str | None = Field(None, description="the drop rig: description, drawing or photo "
                                              "reference")
    height_setting: str | None = Field(
        None, description="how the free drop height was set and measured")
    height_tolerance: Length | None = Field(None, description="tolerance of the drop height")
    drop_mass_weighing: str | None = Field(None, description="weighing record of the drop mass")
    attitude: str | None = Field(None, description="gear attitude in the drops (14 CFR "
                                                   "23.725(c))")
    drag_loads: str | None = Field(
        None, description="how spin-up and drag loads were represented, or that they were "
                          "not (14 CFR 23.725(c))")
    test_plan: str | None = Field(None, description="test plan reference and revision")
    witness: str | None = Field(None, description="who witnessed the drops, and for whom")


class Instrumentation(SpecBlock):
    sampling_rate: Frequency
    platform: PlatformSpec | None = None
    logger: str | None = None
    channels: list[InstrumentChannel] = []


class Column(SpecBlock):
    """Where a channel sits in the data file and how to bring it to SI.

    value_SI = sign * scale * (raw - offset) converted from ``unit``.
    """

    column: Text
    unit: str
    scale: float = 1.0
    sign: Literal[1, -1] = 1
    offset: float = Field(0.0, description="zero offset, in the column's own unit")
    full_scale: float | None = Field(
        None, description="transducer full-scale reading in the column's unit (clipping check)")

    @field_validator("scale")
    @classmethod
    def _scale_not_zero(cls, value: float) -> float:
        if value == 0:
            raise PydanticCustomError("scale", "scale must not be zero")
        return value


class LoadColumn(Column):
    unit: unit_text("weight")  # type: ignore[valid-type]


class LengthColumn(Column):
    unit: unit_text("length")  # type: ignore[valid-type]


class AccelerationColumn(Column):
    unit: unit_text("acceleration")  # type: ignore[valid-type]
    reference: Literal["kinematic", "specific_force"] = Field(
        description="kinematic: dv/dt (free fall reads -1 g); specific_force: what an "
                    "accelerometer reads (free fall reads 0 g, rest +1 g)")


class TimeColumn(SpecBlock):
    column: Text
    unit: unit_text("time")  # type: ignore[valid-type]


class GearChannels(SpecBlock):
    vertical_load: LoadColumn
    strut_stroke: LengthColumn | None = None
    tyre_deflection: LengthColumn | None = None


WaivableCheck = Literal["sample_rate", "gaps", "clipping", "implausible_range"]


class Waiver(SpecBlock):
    check: WaivableCheck
    reason: Text


class RunData(SpecBlock):
    file: Text
    origin: Literal["measured", "synthetic"] = Field(
        "measured", description="synthetic (simulated) data are never used as compliance "
                                "evidence, only by the physics model")
    time: TimeColumn
    sampling_rate: Frequency | None = Field(
        None, description="declared rate; defaults to instrumentation.sampling_rate")
    gears: dict[str, GearChannels] = Field(min_length=1)
    drop_mass_acceleration: AccelerationColumn | None = None
    drop_mass_displacement: LengthColumn | None = None
    waivers: list[Waiver] = []


class Lift(SpecBlock):
    method: Literal["none", "reduced_mass", "lift_device"]
    ratio: Fraction | None = Field(None, description="L, required unless method is none")


class ReportedGear(SpecBlock):
    strut_stroke: Length | None = None
    tyre_deflection: Length | None = None
    peak_vertical_load: Force | None = None
    strut_energy: Energy | None = None
    tyre_energy: Energy | None = None


class ReportedRun(SpecBlock):
    impact_load_factor: PositiveNumber | None = Field(
        None, description="a load factor the source states for this drop (definition unknown)")
    gears: dict[str, ReportedGear] = {}


class Inspection(SpecBlock):
    before: str | None = Field(None, description="inspection before the drop and its finding")
    failure: bool | None = None
    yielding: bool | None = None
    permanent_set: Length | None = None
    notes: str | None = None


class Run(SpecBlock):
    id: Identifier
    test_type: Literal["build-up", "limit", "reserve", "dynamic", "small-signal"]
    gear_units: list[Identifier] = Field(min_length=1)
    date: Date | None = None
    time: ClockTime | None = Field(None, description="local time of the drop, HH:MM in quotes")
    ambient_temperature: str | None = Field(None, description="e.g. '21 degC'")
    drop_height: PositiveLength
    drop_mass: Mass
    lift: Lift
    data: RunData | None = None
    reported: ReportedRun | None = None
    deviations: list[str] = []
    inspection: Inspection | None = None
    notes: str | None = None


# --------------------------------------------------------------------------- claims, audit, report
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


class AuditSettings(SpecBlock):
    asymmetry_threshold: Fraction = Field(parse_quantity("10 %", "dimensionless"))
    reported_tolerance: Fraction = Field(parse_quantity("2 %", "dimensionless"))
    energy_tolerance: Fraction = Field(parse_quantity("1 %", "dimensionless"))
    energy_sum_tolerance: Fraction = Field(
        parse_quantity("10 %", "dimensionless"),
        description="how far E_s + E_t, each to its own peak, may exceed the energy available")
    reported_energy_spread: Fraction = Field(
        parse_quantity("15 %", "dimensionless"),
        description="spread across runs of the drop weight implied by reported energies")
    static_stroke_tolerance: Fraction = Field(
        parse_quantity("15 %", "dimensionless"),
        description="share of the static stroke seal friction and gas temperature may move it")
    tyre_curve_tolerance: Fraction = Field(
        parse_quantity("15 %", "dimensionless"),
        description="how far the peak load may fall below the tyre curve at maximum deflection")
    bottoming_margin: Fraction = Field(parse_quantity("5 %", "dimensionless"))
    drop_mass_spread: Fraction = Field(parse_quantity("10 %", "dimensionless"))
    sample_rate_tolerance: Fraction = Field(parse_quantity("1 %", "dimensionless"))
    load_consistency_tolerance: Fraction = Field(parse_quantity("10 %", "dimensionless"))
    zero_travel_tolerance: Length = Field(parse_quantity("1 mm", "length"))


#: Display units of each unit system; a unit not given in report.units comes from here.
UNIT_SYSTEMS = {
    "SI": {"length": "mm", "force": "N", "mass": "kg", "energy": "J", "velocity": "m/s",
           "pressure": "kPa", "area": "m^2", "wing_loading": "N/m^2", "time": "ms"},
    "US": {"length": "in", "force": "lbf", "mass": "lb", "energy": "ft*lbf", "velocity": "ft/s",
           "pressure": "psi", "area": "ft^2", "wing_loading": "lbf/ft^2", "time": "ms"},
}
_US_LENGTHS = {"in", "inch", "inches", "ft", "foot", "feet", "yd", "yard", "mil", "thou"}
_US_UNITS = _US_LENGTHS | {"lbf", "lb", "lbs", "pound", "pounds", "psi", "ksi", "mph", "kip",
                           "slug", "ozf", "oz"}


def _is_us(unit: object) -> bool:
    """Whether a unit text names a US customary unit (in, ft, lbf, psi, ...)."""
    return isinstance(unit, str) and bool(set(re.split(r"[\s*/·^0-9+\-]+", unit)) & _US_UNITS)


class DisplayUnits(SpecBlock):
    """The units every number a person reads is shown in.

    A unit not given follows ``system``; without ``system``, the system of the length unit
    (US customary for in or ft, else SI), or without a length unit the system of the units
    given, so ``{length: in, force: lbf}`` and ``{force: lbf}`` show areas in ft^2 and
    energies in ft*lbf.
    """

    system: Literal["SI", "US"] | None = Field(
        None, description="unit system of the units not given (default: the length unit's)")
    length: unit_text("length") = "mm"  # type: ignore[valid-type]
    force: unit_text("weight") = "N"  # type: ignore[valid-type]
    mass: unit_text("mass") = "kg"  # type: ignore[valid-type]
    energy: unit_text("energy") = "J"  # type: ignore[valid-type]
    velocity: unit_text("velocity") = "m/s"  # type: ignore[valid-type]
    pressure: unit_text("pressure") = "kPa"  # type: ignore[valid-type]
    area: unit_text("area") = "m^2"  # type: ignore[valid-type]
    wing_loading: unit_text("wing_loading") = "N/m^2"  # type: ignore[valid-type]
    time: unit_text("time") = "ms"  # type: ignore[valid-type]

    @model_validator(mode="before")
    @classmethod
    def _fill_from_system(cls, data):
        if not isinstance(data, dict):
            return data
        system = data.get("system")
        if system not in UNIT_SYSTEMS:
            given = [data["length"]] if "length" in data else list(data.values())
            system = "US" if any(_is_us(unit) for unit in given) else "SI"
        return {**UNIT_SYSTEMS[system], **data}


#: The effects a campaign can switch on: the names of certkit.physics.effects' registry (kept
#: here so a spec validates without the physics; tests/test_effect_registry.py holds the two
#: equal).
Effect = Literal["seal-friction", "rebound-orifice", "metering-pin", "tyre-hysteresis",
                 "heat-transfer", "oil-compressibility", "leg-flexibility",
                 "platform-compliance", "sensor-dynamics", "load-cell-gain"]


class SensorSpec(SpecBlock):
    """Low-pass and delay of the recorded channels (effect 'sensor-dynamics')."""

    cutoff: Frequency
    order: int = Field(2, ge=1, le=8)
    delay: quantity("time") = Field(parse_quantity("0 s", "time"))  # type: ignore[valid-type]


CalibrationParameter = Literal[
    "discharge-coefficient", "gas-precharge", "gas-volume", "polytropic-exponent",
    "tyre-stiffness", "tyre-exponent", "tyre-damping", "friction", "friction-pressure-factor",
    "rebound-damping", "load-cell-gain", "top-out-compression"]


class CalibrationSpec(SpecBlock):
    """What `certkit calibrate` fits (default: C_d, pre-charge, n, tyre stiffness and
    exponent, the top-out stop's compression, friction and load-cell gain when those are on)."""

    parameters: list[CalibrationParameter] = Field([], description="parameters to fit")
    runs: list[Identifier] = Field(
        [], description="runs to fit to (default: the drops the identification trains on: "
                        "every drop but those at the highest drop height, and the middle "
                        "height's when there are four heights or more); the others are "
                        "simulated to validate the calibrated model")


class BlockModelSpec(SpecBlock):
    """Orders and (optionally fixed) LS-SVM hyper-parameters of one identified model."""

    na: int = Field(ge=0, le=20, description="past outputs (denominator order)")
    nb: int = Field(ge=1, le=20, description="input terms (numerator terms)")
    gamma: PositiveNumber | None = Field(None, description="regularisation γ; default: tuned")
    sigma2: PositiveNumber | None = Field(
        None, description="RBF width σ² of K = exp(−‖x − z‖²/σ²); default: tuned")


class SmallSignalSpec(SpecBlock):
    """The seed's small-signal method (§4): first amplitude, scaling K, linearity tolerance."""

    amplitude: Force = Field(parse_quantity("500 N", "force"),
                             description="RMS of the first small random force")
    gain: PositiveNumber = Field(parse_quantity("2", "dimensionless"), description="K")
    tolerance: Fraction = Field(parse_quantity("5 %", "dimensionless"))


class IdentificationSpec(SpecBlock):
    """Identification settings; defaults follow the seed paper (6 poles, 4 input terms)."""

    hammerstein: BlockModelSpec = BlockModelSpec(na=6, nb=4)
    wiener: BlockModelSpec = BlockModelSpec(na=6, nb=4)
    narx: BlockModelSpec = BlockModelSpec(na=2, nb=2)
    held_out: list[Identifier] = Field(
        [], description="runs kept out of fitting and tuning (default: the highest drop)")
    small_signal: SmallSignalSpec = SmallSignalSpec()
    nonlinearity_target: Length = Field(
        parse_quantity("0.1 mm", "length"),
        description="step 9: the static nonlinearity's tuning stops once its cross-validated "
                    "RMSE is at or below this")


class GapSpec(SpecBlock):
    """Sim-to-real gap diagnosis (`certkit gap`, the report's gap section)."""

    held_out: list[Identifier] = Field(
        [], description="runs kept out of calibration, scoring and refits, only evaluated "
                        "(default: every drop at the highest drop height, and the middle "
                        "height's when there are four heights or more)")
    blind_check: Text | None = Field(
        None, description="the JSON file written by benchmarks/blind_independent.py --battery development, relative to "
                          "this spec file and inside its folder; the report summarises it and "
                          "hashes it with the other inputs")
    sealed_blind_check: Text | None = Field(
        None, description="the record of the SEALED battery (benchmarks/blind_independent.py "
                          "--battery sealed), relative to this spec file and inside its "
                          "folder: the report gives its held-out figures beside the "
                          "development record's in-sample ones (model.gap.blind_check)")


class ModelSettings(SpecBlock):
    """The physics model used to simulate and calibrate: which optional effects are on."""

    effects: list[Effect] = Field([], description="optional effects switched on (default none)")
    sensor: SensorSpec | None = None
    calibration: CalibrationSpec | None = None
    identification: IdentificationSpec = IdentificationSpec()
    gap: GapSpec = GapSpec()


class ReportSettings(SpecBlock):
    units: DisplayUnits = DisplayUnits()


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
