"""The drop model of a campaign's gear unit, built from its spec (servicing, geometry, tyre).

Every physical parameter comes from the campaign spec with its unit; a parameter the
model needs and the spec lacks is an input error naming the key to add.  The end
stops' stiffness and damping are numerical constants of the model, not gear data.
"""

from __future__ import annotations

import math

from certkit.compliance.drop_conditions import drop_weight_share, lift_force_ratio
from certkit.physics.dynamics import PIN_POINTS
from certkit.physics.drop_model import P_ATM, DropModel, EndStops, GasSpring, Orifice, Tyre
from certkit.physics.effects import (GasHeatTransfer, LegFlexibility, MeteringPin, OilCompressibility,
                      PlatformCompliance, ReboundOrifice, SealFriction, TyreHysteresis)
from certkit.errors import CertkitInputError, Problem
from certkit.spec.schema import CampaignSpec, Run
from certkit.units import STANDARD_GRAVITY

#: Stop stiffness and damping: stiff enough that the stop compression under the largest
#: strut load is a fraction of a millimetre; the damping is about half critical against a
#: ~9 kg unsprung mass at top-out (lightly damped against the upper mass at bottoming).
STOP_STIFFNESS = 2.0e7      # N/m
STOP_DAMPING = 1.3e4        # N·s/m


def _circle(diameter: float) -> float:
    return math.pi * diameter ** 2 / 4


def gear_mass(spec: CampaignSpec, run: Run, gear_id: str) -> float:
    """Mass the gear unit carries in the drop [kg] (certkit W1, drop_conditions)."""
    return drop_weight_share(spec, run, gear_id) / STANDARD_GRAVITY


def drop_model_for(spec: CampaignSpec, run: Run, gear_id: str, spec_file: str = "campaign",
                   lines=None, effects: list[str] | None = None) -> DropModel:
    """The :class:`~certkit.physics.drop_model.DropModel` of ``gear_id`` in ``run``.

    Parameters
    ----------
    effects : list of str, optional
        Optional effects to switch on; default: the campaign's ``model.effects``.

    Raises
    ------
    CertkitInputError
        Listing every parameter the model needs that the spec does not give.
    """
    from certkit.spec.yamlsource import line_of

    index = next(i for i, g in enumerate(spec.gear_units) if g.id == gear_id)
    unit = spec.gear_units[index]
    strut, tyre = unit.strut, unit.tyre
    missing: list[Problem] = []

    def need(owner, name: str, where: tuple):
        value = getattr(owner, name, None) if owner is not None else None
        if value is None:
            location = ("gear_units", index) + where + (name,)
            line = line_of(lines, location) if lines else None
            missing.append(Problem(spec_file, line, "gear_units[{}].{}".format(
                index, ".".join(map(str, where + (name,)))), "needed to simulate this gear unit"))
        return value

    pneumatic = need(strut, "pneumatic_area", ("strut",))
    volume = need(strut, "gas_volume", ("strut",))
    precharge = need(strut, "gas_precharge_pressure", ("strut",))
    reference = need(strut, "pressure_reference", ("strut",))
    exponent = need(strut, "polytropic_exponent", ("strut",))
    hydraulic = need(strut, "hydraulic_area", ("strut",))
    discharge = need(strut, "discharge_coefficient", ("strut",))
    density = need(strut, "oil_density", ("strut",))
    unsprung = need(strut, "unsprung_mass", ("strut",))
    curve = need(tyre, "load_deflection", ("tyre",))
    orifice_area = None
    if strut is not None:
        if strut.orifice_area is not None:
            orifice_area = strut.orifice_area.si
        elif strut.orifice_diameter is not None:
            orifice_area = _circle(strut.orifice_diameter.si)
        else:
            need(strut, "orifice_diameter", ("strut",))
    chosen = spec.model.effects if effects is None else effects
    if "rebound-orifice" in chosen:
        need(strut, "rebound_orifice_diameter", ("strut",))
    if "seal-friction" in chosen:
        need(strut, "seal_friction", ("strut",))
    if "metering-pin" in chosen:
        need(strut, "metering_pin", ("strut",))
    if "tyre-hysteresis" in chosen:
        need(tyre, "hysteresis", ("tyre",))
    if "heat-transfer" in chosen:
        need(strut, "heat_transfer", ("strut",))
    if "oil-compressibility" in chosen:
        need(strut, "oil", ("strut",))
    if "leg-flexibility" in chosen:
        need(unit, "leg", ())
    platform = spec.instrumentation.platform if spec.instrumentation else None
    if "platform-compliance" in chosen and platform is None:
        missing.append(Problem(spec_file, line_of(lines, ("instrumentation",)) if lines else None,
                               "instrumentation.platform", "needed to simulate the platform's "
                               "compliance (effect platform-compliance)"))
    if missing:
        raise CertkitInputError(missing)

    total = gear_mass(spec, run, gear_id)
    if unsprung.si >= total:
        raise CertkitInputError.single(spec_file, None, f"gear_units[{index}].strut.unsprung_mass",
                                       f"{unsprung.text} is not less than the {total:.6g} kg the "
                                       f"unit carries in run {run.id}")
    swept = pneumatic.si * unit.design_stroke.si
    if 0.98 * volume.si <= swept:  # the gas law's 2 % volume floor must lie beyond the stroke
        raise CertkitInputError.single(
            spec_file, line_of(lines, ("gear_units", index, "strut", "gas_volume")) if lines
            else None, f"gear_units[{index}].strut.gas_volume",
            f"{volume.text} leaves less than 2 % of itself at the design stroke (the piston "
            f"sweeps A_a·s_max = {swept * 1e6:.6g} cm^3): the gas would be compressed to nothing")
    inclination = strut.inclination.si if strut.inclination is not None else 0.0
    absolute = precharge.si + (P_ATM if reference == "gauge" else 0.0)
    gas = GasSpring(pneumatic.si, volume.si, absolute, exponent.si)
    static_load = (unit.static_weight.si - unsprung.si * STANDARD_GRAVITY) * math.cos(inclination)
    if gas.equilibrium_stroke(static_load) >= unit.design_stroke.si:
        raise CertkitInputError.single(
            spec_file, None, f"gear_units[{index}].strut",
            f"the gas spring cannot hold the static load within the design stroke "
            f"{unit.design_stroke.text} (pre-charge too low or gas volume too small)")
    orifice = Orifice(hydraulic.si, orifice_area, discharge.si, density.si)
    terms = []
    if "rebound-orifice" in chosen:
        rebound = Orifice(hydraulic.si, _circle(strut.rebound_orifice_diameter.si), discharge.si,
                          density.si)
        terms.append(ReboundOrifice(rebound.coefficient - orifice.coefficient))
    if "seal-friction" in chosen:
        friction = strut.seal_friction
        terms.append(SealFriction(friction.constant.si, friction.pressure_factor.si,
                                  friction.breakaway.si, friction.stribeck_velocity.si))
    if "metering-pin" in chosen:
        pin = strut.metering_pin
        strokes = tuple(q.si for q in pin.strokes)
        if (len(pin.strokes) != len(pin.areas) or len(pin.strokes) > PIN_POINTS
                or any(b <= a for a, b in zip(strokes, strokes[1:]))):
            raise CertkitInputError.single(
                spec_file, None, f"gear_units[{index}].strut.metering_pin",
                f"expected as many areas as strokes (at most {PIN_POINTS}), with the strokes "
                f"increasing; found {len(pin.strokes)} strokes and {len(pin.areas)} areas")
        terms.append(MeteringPin(strokes, tuple(q.si for q in pin.areas), hydraulic.si,
                                 orifice_area, discharge.si, density.si))
    if "tyre-hysteresis" in chosen:
        terms.append(TyreHysteresis(tyre.hysteresis.si))
    if "heat-transfer" in chosen:
        heat = strut.heat_transfer
        terms.append(GasHeatTransfer(heat.time_constant.si, heat.ratio_of_specific_heats.si))
    if "oil-compressibility" in chosen:
        terms.append(OilCompressibility.from_oil(strut.oil.bulk_modulus.si, hydraulic.si,
                                                 strut.oil.volume.si))
    if "leg-flexibility" in chosen:
        leg = unit.leg
        if leg.axle_mass.si >= unsprung.si:
            raise CertkitInputError.single(
                spec_file, line_of(lines, ("gear_units", index, "leg", "axle_mass")) if lines
                else None, f"gear_units[{index}].leg.axle_mass",
                f"{leg.axle_mass.text} is not less than the unsprung mass {unsprung.text} it is "
                f"part of")
        terms.append(LegFlexibility(leg.axle_mass.si, leg.stiffness.si, leg.damping.si))
    if "platform-compliance" in chosen:
        terms.append(PlatformCompliance(platform.mass.si, platform.stiffness.si,
                                        platform.damping.si))
    return DropModel(
        upper_mass=total - unsprung.si, lower_mass=unsprung.si, gas=gas, orifice=orifice,
        stops=EndStops(unit.design_stroke.si, STOP_STIFFNESS, STOP_DAMPING),
        tyre=Tyre(curve.reference_load.si, curve.reference_deflection.si, curve.exponent.si,
                  tyre.damping.si if tyre.damping is not None else 0.0),
        lift_ratio=lift_force_ratio(run), inclination=inclination, effects=tuple(terms))
