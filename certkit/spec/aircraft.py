"""The campaign spec's blocks of the airplane and its gear units: weights and wing area, each
unit's static weight, tyre, shock strut (servicing, geometry and the optional drop-model
effects) and test article.

:mod:`certkit.spec.schema` assembles the whole spec from these and the other block modules.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from certkit.spec.types import (Area, Damping, Density, Duration, Force, Fraction, Identifier,
                                Inclination, Length, Mass, NonNegativeMass, PositiveLength,
                                PositiveNumber, Pressure, SpecBlock, Stiffness, Text, Volume,
                                Weight, quantity)
from certkit.units import parse_quantity


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


# --------------------------------------------------------------------------- tyre
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


# --------------------------------------------------------------------------- shock strut
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


# --------------------------------------------------------------------------- gear unit
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
