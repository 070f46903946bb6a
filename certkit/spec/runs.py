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


# --------------------------------------------------------------------------- data file
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


# --------------------------------------------------------------------------- run
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
