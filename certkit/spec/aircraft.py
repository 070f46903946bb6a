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
    """The airplane the gear units belong to: the weight, wing area and load factors of its
    loads basis."""

    model: Text = Field(description="the airplane's model designation, on the report's cover "
                                    "and in its archive")
    maximum_weight: Weight = Field(
        description="W, the maximum weight (a force, or a mass taken with standard gravity): "
                    "W/S gives the required drop height (14 CFR 23.725(a); ASTM F2245 as cited) "
                    "and the limit descent velocity (23.473(d)); in a complete-airplane drop "
                    "each unit carries static_weight/W of the drop weight")
    wing_area: Area = Field(
        description="S, the wing area (an area): the wing loading W/S gives the required drop "
                    "height (14 CFR 23.725(a); ASTM F2245 as cited) and the limit descent "
                    "velocity (23.473(d))")
    design_limit_inertia_load_factor: PositiveNumber | None = Field(
        None, description="n_limit, the design limit inertia load factor of the loads report "
                          "(a number): a limit drop's load factor may not exceed it (14 CFR "
                          "23.725(f); the ASTM F2245 energy method), it must meet the minima "
                          "of 23.473(g), and option (2) of 23.726(a) drops to develop 1.5 "
                          "times it; not declared, these criteria are NOT SHOWN")
    wing_lift_ratio: Fraction = Field(
        description="L of the loads basis, the wing lift assumed in the landing conditions as a "
                    "share of the weight (a fraction): 14 CFR 23.473(g) requires n_limit of at "
                    "least 2.0 + L (and 2.67); the lift a drop represents is runs[].lift.ratio")
    design_landing_weight: Weight | None = Field(
        None, description="the design landing weight (a force or mass), for the record: "
                          "certkit computes nothing from it and the report does not show it")
    notes: str | None = Field(None, description="free text on the aircraft, printed in the "
                                                "report's design inputs")


# --------------------------------------------------------------------------- tyre
#: C_T of the tyre force F = f(δ)·(1 + C_T·δ̇): a time per length ("0.05 s/m")
TyreDamping = quantity("slowness", "a time per length with its unit, e.g. '0.05 s/m'")


class TyreCurve(SpecBlock):
    """Static load-deflection law f(δ) = reference_load·(δ/reference_deflection)^exponent."""

    reference_load: Force = Field(description="F_ref, the static load the tyre carries at "
                                              "reference_deflection (a force)")
    reference_deflection: PositiveLength = Field(
        description="δ_ref, the deflection at which the tyre carries reference_load (a length)")
    exponent: PositiveNumber = Field(description="n of f(δ) = F_ref·(δ/δ_ref)^n (a number; 1 "
                                                 "for a linear tyre)")


class Tyre(SpecBlock):
    """The gear unit's tyre: its size and inflation as tested, and the laws the drop model and
    the audit take for it."""

    size: Text = Field(description="the tyre size as marked (e.g. '5.00-5, 6 ply'), in the "
                                   "report's test-article section")
    pressure: Pressure = Field(
        description="inflation pressure as tested (a pressure, gauge or absolute as "
                    "pressure_reference says), in the report's test-article section")
    pressure_reference: Literal["gauge", "absolute"] = Field(
        description="whether pressure is a gauge or an absolute pressure")
    diameter: PositiveLength | None = Field(
        None, description="outside diameter of the tyre (a length): half of it is the upper end "
                          "of the tyre-deflection channel's plausible range (else half "
                          "wheel_diameter, else half a 1 m tyre)")
    load_deflection: TyreCurve | None = Field(
        None, description="static load-deflection curve f(δ): the drop model's tyre law, and "
                          "the audit checks each drop's peak load against it "
                          "(tyre-deflection-vs-curve)")
    hysteresis: Fraction | None = Field(
        None, description="h, half-width of the loading/unloading loop as a share of f(δ) (a "
                          "fraction), for the effect 'tyre-hysteresis'")
    damping: TyreDamping | None = Field(  # type: ignore[valid-type]
        None, description="C_T of the drop model's tyre force F = f(δ)·(1 + C_T·δ̇) (a time per "
                          "length); 0 when not given")


# --------------------------------------------------------------------------- shock strut
class MeteringPinSpec(SpecBlock):
    """Net orifice area against stroke, linear between points and held beyond the ends
    (effect 'metering-pin')."""

    strokes: list[Length] = Field(min_length=2, description="stroke points of the table, "
                                                            "increasing (lengths)")
    areas: list[Area] = Field(
        min_length=2, description="net orifice area A_n at each of those strokes (areas), as "
                                  "many as strokes; in place of the orifice's fixed area")


class SealFrictionSpec(SpecBlock):
    """Seal friction F = (constant + pressure_factor·|F_gas| + breakaway·exp(−(ṡ/v_s)²))·sign(ṡ)."""

    constant: Force = Field(
        description="F_0, the Coulomb friction that does not depend on the gas pressure (a "
                    "force); with pressure_factor it also widens the band of static strokes "
                    "the audit accepts")
    pressure_factor: Fraction = Field(
        parse_quantity("0", "dimensionless"),
        description="μ, the share of the gas force |F_gas| that acts as friction (a fraction)")
    breakaway: Force = Field(parse_quantity("0 N", "force"),
                             description="Stribeck excess of static over Coulomb friction (a "
                                         "force)")
    stribeck_velocity: quantity("velocity", exclusive=True) = Field(  # type: ignore[valid-type]
        parse_quantity("10 mm/s", "velocity"),
        description="v_s, the stroke speed over which the breakaway excess fades (a velocity)")


class HeatTransferSpec(SpecBlock):
    """Gas-to-wall heat transfer (effect 'heat-transfer'): replaces the polytropic law."""

    time_constant: Duration = Field(description="τ = m·c_v/(h·A), the gas's thermal time "
                                                "constant (a time, e.g. '1 s')")
    ratio_of_specific_heats: PositiveNumber = Field(
        parse_quantity("1.4", "dimensionless"),
        description="γ = c_p/c_v of the gas (a number; 1.4 for nitrogen)")


class OilSpec(SpecBlock):
    """Oil compressibility (effect 'oil-compressibility'): k_oil = β·A_h²/V_oil."""

    bulk_modulus: Pressure = Field(description="effective β (a pressure, e.g. '1.5 GPa'; less "
                                               "if aerated)")
    volume: Volume = Field(description="oil volume between piston and orifice (a volume)")


class LegSpec(SpecBlock):
    """Gear-leg flexibility (effect 'leg-flexibility'): axle mass on a leg spring."""

    axle_mass: Mass = Field(description="axle and wheel (a mass), part of the unsprung mass "
                                        "and less than it")
    stiffness: Stiffness = Field(description="k_l, the leg's stiffness between axle and strut "
                                             "(a force per length)")
    damping: Damping = Field(parse_quantity("0 N*s/m", "damping"),
                             description="c_l, the leg's damping (a force per velocity)")


class Strut(SpecBlock):
    """The shock strut's servicing and geometry: the drop model's parameters, and the
    inclination, unsprung mass and static stroke the compliance values and the audit use."""

    gas_precharge_pressure: Pressure | None = Field(
        None, description="p0, the gas pre-charge pressure with the strut fully extended (a "
                          "pressure, gauge or absolute as pressure_reference says): the drop "
                          "model's gas spring and the audit's static-stroke check")
    pressure_reference: Literal["gauge", "absolute"] | None = Field(
        None, description="whether gas_precharge_pressure is a gauge or an absolute pressure "
                          "(a gauge pressure is taken above the standard atmosphere, "
                          "101.325 kPa)")
    gas_volume: Volume | None = Field(None, description="V0, the gas volume with the strut "
                                                        "fully extended (a volume)")
    pneumatic_area: Area | None = Field(None, description="A_a, the area the gas pressure acts "
                                                          "on (an area)")
    hydraulic_area: Area | None = Field(None, description="A_h, the area that drives oil "
                                                          "through the orifice (an area)")
    orifice_diameter: PositiveLength | None = Field(
        None, description="diameter of the compression orifice (a length); its circle's area "
                          "is taken unless orifice_area is given")
    orifice_area: Area | None = Field(
        None, description="A_n, the net area of the compression orifice (an area), in place of "
                          "orifice_diameter")
    rebound_orifice_diameter: PositiveLength | None = Field(
        None, description="diameter of the rebound orifice (a length), for the effect "
                          "'rebound-orifice': extra damping on extension")
    discharge_coefficient: PositiveNumber | None = Field(
        None, description="C_d of the orifice (a number)")
    oil_density: Density | None = Field(None, description="ρ, the oil's density (a mass per "
                                                          "volume)")
    polytropic_exponent: PositiveNumber | None = Field(
        None, description="n of the gas law p·Vⁿ = const in a drop (a number: 1 isothermal, 1.4 "
                          "adiabatic for nitrogen); the audit's static-stroke check uses it too")
    inclination: Inclination | None = Field(
        None, description="θ, the strut axis from vertical (an angle): the stroke enters the "
                          "total travel d = δ + s·cos θ, the strut energy and the static strut "
                          "load; not declared, θ = 0 is assumed and said so")
    static_stroke: Length | None = Field(
        None, description="s_0, the stroke at rest under the static weight (a length): the "
                          "audit checks it against the drops' maximum strokes and against the "
                          "gas law of the servicing")
    minimum_stroke: Length | None = Field(
        None, description="the design minimum stroke (a length), in the report's test-article "
                          "section; certkit computes nothing from it")
    unsprung_mass: NonNegativeMass | None = Field(
        None, description="m2, the mass below the strut (wheel, tyre, brake, axle and piston; a "
                          "mass): the energies need it (certkit E1, E5); 0 declares it "
                          "negligible; the drop model needs it positive")
    seal_friction: SealFrictionSpec | None = Field(
        None, description="seal friction, for the effect 'seal-friction' (and the band of "
                          "static strokes the audit accepts)")
    metering_pin: MeteringPinSpec | None = Field(
        None, description="orifice area against stroke, for the effect 'metering-pin'")
    heat_transfer: HeatTransferSpec | None = Field(
        None, description="gas-to-wall heat transfer, for the effect 'heat-transfer'")
    oil: OilSpec | None = Field(None, description="oil compressibility, for the effect "
                                                  "'oil-compressibility'")
    notes: str | None = Field(None, description="free text on the strut, in the report's "
                                                "test-article section")


class TestArticle(SpecBlock):
    """What was tested, as the conformity record identifies it, and how it was serviced."""

    part_number: str | None = Field(None, description="part number of the gear unit tested")
    serial_number: str | None = Field(None, description="serial number of the gear unit "
                                                        "tested")
    drawing: str | None = Field(None, description="drawing number and revision")
    conformity_record: str | None = Field(
        None, description="conformity inspection record of the test article (e.g. FAA Form "
                          "8100-1 number)")
    tyre_part_number: str | None = Field(None, description="part number of the tyre fitted")
    tyre_ply_rating: str | None = Field(None, description="ply rating of the tyre fitted")
    oil_volume: Volume | None = Field(None, description="oil volume as serviced for the test "
                                                        "(a volume)")
    gas_pressure: Pressure | None = Field(
        None, description="gas pressure as serviced, a pressure such as '180 psi' (gauge or "
                          "absolute as strut.pressure_reference says)")
    gas_temperature: str | None = Field(
        None, description="temperature at which the gas was charged, e.g. '18 degC'")


# --------------------------------------------------------------------------- gear unit
class GearUnit(SpecBlock):
    """One landing-gear unit under test: its static weight, stroke, tyre, strut and test
    article."""

    id: Identifier = Field(description="identifier the runs, data mappings and uncertainties "
                                       "name the unit by")
    position: Literal["main", "nose", "tail"] = Field(
        description="main, nose or tail: 14 CFR 23.725(b) defines W for each; the main units "
                    "make up the combined load factor and the left/right and airplane energy "
                    "checks")
    static_weight: Weight = Field(
        description="W of 14 CFR 23.725(b) for this unit (a force, or a mass taken with "
                    "standard gravity): the effective weight (23.725(b), 23.727(b)) and the "
                    "load factor n (23.725(e)) are taken against it")
    static_weight_basis: Literal["level-attitude-nose-wheel-clear", "tail-down-attitude",
                                 "nose-reaction-1g-down-0.33g-forward", "assumed"] = Field(
        description="how W was obtained: one of the 23.725(b) definitions, or 'assumed' (a "
                    "warning, and no error rests on it)")
    static_weight_note: str | None = Field(
        None, description="how W was obtained, in words: printed beside its basis in the "
                          "report and in the assumed-weight finding")
    shock_absorber: Text = Field(description="the kind of shock absorber (e.g. "
                                             "'oleo-pneumatic, single orifice'), in the "
                                             "report's test-article section")
    design_stroke: PositiveLength = Field(
        description="the strut's full stroke to its stops (a length): the bottoming margin "
                    "and checks, the stroke channel's plausible range (to 1.2 times it) and "
                    "the drop model's end stop")
    tyre: Tyre = Field(description="the tyre: size, inflation and load-deflection law")
    strut: Strut | None = Field(
        None, description="the shock strut's servicing and geometry (the drop model needs it; "
                          "its inclination and unsprung mass enter the energies)")
    leg: LegSpec | None = Field(None, description="gear-leg flexibility, for the effect "
                                                  "'leg-flexibility'")
    wheel_diameter: PositiveLength | None = Field(
        None, description="wheel diameter (a length), in the report; half of it bounds the "
                          "tyre-deflection channel when tyre.diameter is not given")
    article: TestArticle | None = Field(None, description="the test article's identity and "
                                                        "servicing")
