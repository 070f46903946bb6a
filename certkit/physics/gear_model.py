"""The drop model of a campaign's gear unit, built from its spec (servicing, geometry, tyre).

Every physical parameter comes from the campaign spec with its unit; a parameter the
model needs and the spec lacks is an input error naming the key to add.  The end
stops' stiffness and damping are numerical constants of the model, not gear data.
"""

from __future__ import annotations

import math

from certkit.compliance.drop_conditions import drop_weight_share, lift_force_ratio
from certkit.errors import CertkitInputError, Problem
from certkit.compliance.drop_conditions import static_strut_load
from certkit.compliance.servicing import absolute_pressure
from certkit.physics.drop_model import DropModel, EndStops, GasSpring, Orifice, Tyre
from certkit.physics.effects import BY_NAME, EFFECTS
from certkit.physics.effects.base import Gear
from certkit.spec.schema import CampaignSpec, Run
from certkit.spec.yamlsource import line_of
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
    chosen = [BY_NAME[name] for name in (spec.model.effects if effects is None else effects)]
    platform = spec.instrumentation.platform if spec.instrumentation else None
    for effect in chosen:
        for need_ in effect.needs:
            path, message = need_ if isinstance(need_[0], tuple) else (need_, None)
            if path[0] == "instrumentation":
                if platform is None:
                    missing.append(Problem(spec_file, line_of(lines, path[:1]) if lines else None,
                                           ".".join(path), message))
            else:
                owner = unit
                for step in path[:-1]:
                    owner = getattr(owner, step, None) if owner is not None else None
                need(owner, path[-1], path[:-1])
    if missing:
        raise CertkitInputError(missing)

    total = gear_mass(spec, run, gear_id)
    if unsprung.si <= 0:
        raise CertkitInputError.single(
            spec_file, line_of(lines, ("gear_units", index, "strut", "unsprung_mass")) if lines
            else None, f"gear_units[{index}].strut.unsprung_mass",
            f"the drop model needs a positive unsprung mass (wheel, tyre, axle and piston), "
            f"found {unsprung.text}; 0 declares it negligible for the energies only")
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
    absolute = absolute_pressure(precharge.si, reference)
    gas = GasSpring(pneumatic.si, volume.si, absolute, exponent.si)
    static_load = static_strut_load(unit.static_weight.si, unsprung.si, inclination)
    if gas.equilibrium_stroke(static_load) >= unit.design_stroke.si:
        # at rest V = V0·(p0/p)^(1/n): a larger V0 (or a lower p0) sits deeper in the stroke
        raise CertkitInputError.single(
            spec_file, line_of(lines, ("gear_units", index, "strut")) if lines else None,
            f"gear_units[{index}].strut",
            f"the gas spring cannot hold the static load within the design stroke "
            f"{unit.design_stroke.text}: the pre-charge is too low, or the gas volume too "
            f"large, for the static weight {unit.static_weight.text}")
    orifice = Orifice(hydraulic.si, orifice_area, discharge.si, density.si)
    gear = Gear(unit, index, platform, orifice, unsprung.si, spec_file,
                lambda location: line_of(lines, location) if lines else None)
    terms = [effect.build(gear) for effect in EFFECTS if effect in chosen and effect.build]
    return DropModel(
        upper_mass=total - unsprung.si, lower_mass=unsprung.si, gas=gas, orifice=orifice,
        stops=EndStops(unit.design_stroke.si, STOP_STIFFNESS, STOP_DAMPING),
        tyre=Tyre(curve.reference_load.si, curve.reference_deflection.si, curve.exponent.si,
                  tyre.damping.si if tyre.damping is not None else 0.0),
        lift_ratio=lift_force_ratio(run), inclination=inclination, effects=tuple(terms))
