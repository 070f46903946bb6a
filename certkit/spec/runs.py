"""The campaign spec's blocks of the tests: the instrumentation, how the drops were set up,
and each run (drop) with its data file's column mapping, waivers, reported values, lift
simulation and inspection.

:mod:`certkit.spec.rundata` reads the data files these blocks map; :mod:`certkit.spec.schema`
assembles the whole spec from these and the other block modules.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, field_validator
from pydantic_core import PydanticCustomError

from certkit.spec.types import (ClockTime, Damping, Date, Energy, Force, Fraction, Frequency,
                                Identifier, Length, Mass, PositiveLength, PositiveNumber,
                                SpecBlock, Stiffness, Text, unit_text)
from certkit.units import parse_quantity


# --------------------------------------------------------------------------- instrumentation
class InstrumentChannel(SpecBlock):
    """One transducer channel of the drop rig, as the report's instrumentation table lists
    it."""

    name: Text = Field(description="the channel's name (e.g. as the logger labels it)")
    measures: Text = Field(description="what it measures, in words (e.g. 'vertical load on "
                                       "the platform')")
    transducer: str | None = Field(None, description="the transducer: kind, make, model")
    range: str | None = Field(None, description="its measuring range, as text (e.g. "
                                                "'0-10000 lbf')")
    filter: str | None = Field(None, description="the filter on the channel (e.g. an "
                                                 "anti-alias low-pass and its cut-off), as text")
    calibration_date: Date | None = Field(
        None, description="date of its calibration: a drop before it is an error of the "
                          "audit's calibration check (instrument-calibration)")
    calibration_due: Date | None = Field(
        None, description="date the calibration expires: a drop after it is an error")
    calibration_reference: str | None = Field(None, description="calibration certificate")


class PlatformSpec(SpecBlock):
    """The drop rig's platform on its load cells (effect 'platform-compliance')."""

    mass: Mass = Field(description="m_p, the platform's mass on the load cells (a mass)")
    stiffness: Stiffness = Field(description="load cells and foundation under the platform (a "
                                             "force per length)")
    damping: Damping = Field(parse_quantity("0 N*s/m", "damping"),
                             description="c_p, the load cells' damping (a force per velocity)")


class TestSetup(SpecBlock):
    """How the drops were set up and conducted: the applicant's statement, reported as given
    (certkit cannot check it); what is absent is reported as not stated."""

    rig: str | None = Field(None, description="the drop rig: description, drawing or photo "
                                              "reference")
    height_setting: str | None = Field(
        None, description="how the free drop height was set and measured")
    height_tolerance: Length | None = Field(None, description="tolerance of the drop height "
                                                              "(a length)")
    drop_mass_weighing: str | None = Field(None, description="weighing record of the drop mass")
    attitude: str | None = Field(None, description="gear attitude in the drops (14 CFR "
                                                   "23.725(c))")
    drag_loads: str | None = Field(
        None, description="how spin-up and drag loads were represented, or that they were "
                          "not (14 CFR 23.725(c))")
    test_plan: str | None = Field(None, description="test plan reference and revision")
    witness: str | None = Field(None, description="who witnessed the drops, and for whom")


class Instrumentation(SpecBlock):
    """The drop rig's logger and transducers: the sampling rate the data files are checked
    against and the channels whose calibration the audit checks."""

    sampling_rate: Frequency = Field(
        description="the logger's sampling rate (a frequency): each run's data file is "
                    "checked against it unless the run declares its own")
    platform: PlatformSpec | None = Field(
        None, description="the platform on its load cells, for the effect "
                          "'platform-compliance'")
    logger: str | None = Field(None, description="the data logger (kind, resolution, record "
                                                 "length), as text")
    channels: list[InstrumentChannel] = Field(
        [], description="the transducer channels: the report lists them, and the audit checks "
                        "each one's calibration against the test dates")


# --------------------------------------------------------------------------- data file
class Column(SpecBlock):
    """Where a channel sits in the data file and how to bring it to SI.

    value_SI = sign * scale * (raw - offset) converted from ``unit``.
    """

    column: Text = Field(description="the column's name in the data file's header")
    unit: str = Field(description="the unit the column is written in")
    scale: float = Field(1.0, description="factor on the raw values, not zero: value = "
                                          "sign·scale·(raw − offset), in unit")
    sign: Literal[1, -1] = Field(1, description="1, or -1 for a channel recorded with the "
                                                "opposite sign")
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
    """A vertical-load column: the platform's load under the unit, positive pressing on the
    platform."""

    unit: unit_text("weight") = Field(  # type: ignore[valid-type]
        description="the column's unit: of force, or of mass taken with standard gravity "
                    "(e.g. 'lbf', 'kN', 'kgf')")


class LengthColumn(Column):
    """A travel column: stroke or tyre deflection positive in compression, drop-mass
    displacement positive downward."""

    unit: unit_text("length") = Field(  # type: ignore[valid-type]
        description="the column's unit, of length (e.g. 'mm', 'in')")


class AccelerationColumn(Column):
    """The drop mass's acceleration column, positive upward (a decelerating fall reads
    positive)."""

    unit: unit_text("acceleration") = Field(  # type: ignore[valid-type]
        description="the column's unit, of acceleration (e.g. 'm/s^2', 'g0')")
    reference: Literal["kinematic", "specific_force"] = Field(
        description="kinematic: dv/dt (free fall reads -1 g); specific_force: what an "
                    "accelerometer reads (free fall reads 0 g, rest +1 g)")


class TimeColumn(SpecBlock):
    """The time column of a data file: numbers increasing at the declared sampling rate."""

    column: Text = Field(description="the time column's name in the data file's header")
    unit: unit_text("time") = Field(  # type: ignore[valid-type]
        description="the column's unit, of time (e.g. 's', 'ms')")


class GearChannels(SpecBlock):
    """The columns of one gear unit's channels in a data file."""

    vertical_load: LoadColumn = Field(
        description="F_V, the platform's vertical load under the unit: touchdown, the peak "
                    "load and the energies (certkit M1, M3, E1)")
    strut_stroke: LengthColumn | None = Field(
        None, description="s, the strut stroke: the maximum stroke d_s, the strut energy and "
                          "the total travel d of 14 CFR 23.725(b)")
    tyre_deflection: LengthColumn | None = Field(
        None, description="δ, the tyre deflection: the maximum deflection d_t, the tyre energy "
                          "and the total travel d of 14 CFR 23.725(b)")


WaivableCheck = Literal["sample_rate", "gaps", "clipping", "implausible_range"]


class Waiver(SpecBlock):
    """A data problem accepted knowingly: the run is read despite it, and the problem becomes
    a data-quality finding with the reason."""

    check: WaivableCheck = Field(
        description="the data check whose problem is accepted: sample_rate (the time steps "
                    "off the declared rate), gaps (gaps in time, missing values), clipping (a "
                    "channel at its full scale or flat at its maximum), implausible_range "
                    "(values outside the plausible range)")
    reason: Text = Field(description="why the problem is accepted, printed with the finding")


class RunData(SpecBlock):
    """A run's logger file and where each channel sits in it."""

    file: Text = Field(description="the data file (CSV or Parquet), relative to the spec's "
                                   "folder and inside it, written with '/'")
    origin: Literal["measured", "synthetic"] = Field(
        "measured", description="synthetic (simulated) data are never used as compliance "
                                "evidence, only by the physics model")
    time: TimeColumn = Field(description="the time column")
    sampling_rate: Frequency | None = Field(
        None, description="declared rate (a frequency); defaults to "
                          "instrumentation.sampling_rate; the time steps must agree with it "
                          "within audit.sample_rate_tolerance")
    gears: dict[str, GearChannels] = Field(
        min_length=1, description="the channels of each gear unit recorded, by gear unit id "
                                  "(each one of the run's gear_units)")
    drop_mass_acceleration: AccelerationColumn | None = Field(
        None, description="the drop mass's acceleration: its peak after touchdown gives n_j "
                          "and the load factor n of 14 CFR 23.725(e)")
    drop_mass_displacement: LengthColumn | None = Field(
        None, description="the drop mass's displacement (distance fallen): the measured "
                          "contact velocity (certkit V2), which the calibration's "
                          "simulations also start from")
    waivers: list[Waiver] = Field([], description="data problems accepted knowingly, each "
                                                  "stated as a finding")


# --------------------------------------------------------------------------- run
class Lift(SpecBlock):
    """How the drop represents the wing lift of 14 CFR 23.725(b): not at all, by a reduced
    drop mass, or by a device applying a force."""

    method: Literal["none", "reduced_mass", "lift_device"] = Field(
        description="none: no lift, the full weight W is dropped; reduced_mass: the drop mass "
                    "is reduced to the effective weight W_e (23.725(b), 23.727(b)); "
                    "lift_device: a device applies the lift force L·W_drop during the drop")
    ratio: Fraction | None = Field(
        None, description="L, the lift as a share of the weight (a fraction), required unless "
                          "method is none; the 14 CFR 23 set allows at most 0.667 in a limit "
                          "drop (23.725(b))")


class ReportedGear(SpecBlock):
    """Values a source reported for one gear unit in a drop: the run's values where it has no
    data file, else compared with those recomputed from it."""

    strut_stroke: Length | None = Field(None, description="d_s, the maximum strut stroke (a "
                                                          "length)")
    tyre_deflection: Length | None = Field(None, description="d_t, the maximum tyre deflection "
                                                             "(a length)")
    peak_vertical_load: Force | None = Field(None, description="F_peak, the peak vertical load "
                                                               "(a force)")
    strut_energy: Energy | None = Field(None, description="E_s, the energy the strut absorbed "
                                                          "(an energy)")
    tyre_energy: Energy | None = Field(None, description="E_t, the energy the tyre absorbed "
                                                         "(an energy)")


class ReportedRun(SpecBlock):
    """Values a source (an earlier test report) gives for a drop, audited against what
    certkit computes."""

    impact_load_factor: PositiveNumber | None = Field(
        None, description="a load factor the source states for this drop (definition unknown); "
                          "the audit compares it with ΣF_peak/(m_drop·g) of the main units "
                          "(certkit G2)")
    gears: dict[str, ReportedGear] = Field(
        {}, description="the values reported per gear unit, by gear unit id (each one of the "
                        "run's gear_units)")


class Inspection(SpecBlock):
    """The inspection of the gear before and after the drop, as the report states it."""

    before: str | None = Field(None, description="inspection before the drop and its finding")
    failure: bool | None = Field(
        None, description="whether the gear failed in the drop: a reserve energy drop shows "
                          "14 CFR 23.723(b) only with false; not recorded, that criterion is "
                          "NOT SHOWN")
    yielding: bool | None = Field(
        None, description="whether the gear yielded (23.723(b) permits it), stated with the "
                          "reserve-drop verdict and in the report")
    permanent_set: Length | None = Field(None, description="permanent set found after the drop "
                                                           "(a length)")
    notes: str | None = Field(None, description="free text on the inspection, in the report")


class Run(SpecBlock):
    """One drop: its type, the gear units it loads, height, mass, lift, data file, reported
    values and inspection."""

    id: Identifier = Field(description="identifier the report, the model settings and the "
                                       "reference results name the drop by")
    test_type: Literal["build-up", "limit", "reserve", "dynamic", "small-signal"] = Field(
        description="limit: judged by the limit-drop criteria (14 CFR 23.725; ASTM F2245); "
                    "reserve: by 23.727 and 23.723(b); dynamic: by 23.726; build-up and "
                    "small-signal: by no criterion (their values and data checks are "
                    "reported); a small-signal run is a record for the identification's "
                    "Wiener linear block, not a drop the drop model is fitted to")
    gear_units: list[Identifier] = Field(
        min_length=1, description="the gear units the drop loads, by id: one on a single-unit "
                                  "rig; several in a complete-airplane drop, each carrying "
                                  "its share of the drop weight (certkit W1)")
    date: Date | None = Field(
        None, description="date of the drop: the calibration check compares it with each "
                          "channel's calibration (without it, every document.test_dates date "
                          "stands for it)")
    time: ClockTime | None = Field(None, description="local time of the drop, HH:MM in quotes")
    ambient_temperature: str | None = Field(None, description="ambient temperature at the "
                                                              "drop, e.g. '21 degC'")
    drop_height: PositiveLength = Field(
        description="h, the free drop height (a length): compared with the required height "
                    "(14 CFR 23.725(a), 23.727(a), 23.726(a)); it enters W_e, the energy "
                    "available and the ideal contact velocity")
    drop_mass: Mass = Field(
        description="m_drop, the mass dropped (a mass): its weight W_drop = m_drop·g is "
                    "compared with the effective weight W_e (14 CFR 23.725(b), 23.727(b))")
    lift: Lift = Field(description="how the drop represents wing lift")
    data: RunData | None = Field(None, description="the drop's logger file; without it, the "
                                                   "values reported for it are used")
    reported: ReportedRun | None = Field(None, description="values a source reported for this "
                                                           "drop")
    deviations: list[str] = Field([], description="deviations recorded for this drop, each "
                                                  "listed in the report's run details")
    inspection: Inspection | None = Field(None, description="the inspection of the gear "
                                                            "before and after the drop")
    notes: str | None = Field(None, description="free text on the drop, in the report's run "
                                                "details")
