"""Data-quality checks of travel, load and the declared hardware.

The relations (docs/audit-checklist.md lists them with their sources):

* with the same drop weight and lift, a higher drop makes a larger stroke, tyre deflection,
  peak load, absorbed energy and load factor;
* the strut travels no further than its design stroke;
* left and right main units of one drop agree;
* at maximum travel the strut carries at least the static load, so the stroke is at least
  the static stroke; the declared static stroke is the one the strut's servicing gives;
* the tyre carries at its maximum deflection what its declared load-deflection curve says;
* the main units' static weights add up to no more than the airplane weighs.
"""

from __future__ import annotations

from certkit.compliance.assessment import Assessment
from certkit.compliance.drop_conditions import lift_force_ratio, lift_ratio, static_strut_load
from certkit.compliance.findings import add, gear_items, not_checked, rises, shown
from certkit.compliance.servicing import absolute_pressure, gas_equilibrium_stroke

#: (key, what it is, kind, check name) of the gear values that rise with drop height.
RISING = (("d_s", "strut stroke", "length", "stroke-not-rising"),
          ("d_t", "tyre deflection", "length", "tyre-deflection-not-rising"),
          ("F_peak", "peak vertical load", "force", "load-not-rising"),
          ("absorbed", "absorbed energy", "energy", "energy-not-rising"))


def _condition(run) -> tuple:
    """What must be equal for two drops to differ by their height alone."""
    return (run.drop_mass.si, run.lift.method, lift_ratio(run))


def _absorbed(gear) -> float | None:
    if gear.get("E_d") is not None:
        return gear.get("E_d")
    if gear.get("E_s") is None or gear.get("E_t") is None:
        return None
    return gear.get("E_s") + gear.get("E_t")


def check_rising_with_height(assessment: Assessment) -> None:
    """Stroke, tyre deflection, peak load and absorbed energy of a gear unit, and the
    combined load factor of a run, rise with drop height between drops of the same drop
    mass and lift: a higher drop brings more energy, which a passive gear absorbs by more
    travel under more force.  A value that does not rise is a warning (bottoming, a
    servicing change between drops, a sensor fault or a transcription slip)."""
    series: dict[tuple, list] = {}
    for run, gear in gear_items(assessment):
        for key, *_ in RISING:
            value = _absorbed(gear) if key == "absorbed" else gear.get(key)
            if value is not None:
                series.setdefault((gear.gear_id, key, _condition(run.run)), []).append(
                    (run.get("h"), value, run.run.id))
    compared = {gear_id for (gear_id, _, _), items in series.items()
                if len({h for h, _, _ in items}) > 1}
    for unit in assessment.campaign.spec.gear_units:
        if unit.id not in compared:
            not_checked(assessment, "rising-with-height", unit.id,
                        "needs two drop heights with the same drop mass and lift")
    for (gear_id, key, _), items in series.items():
        _, label, kind, check = next(item for item in RISING if item[0] == key)
        for (h0, v0, r0), (h1, v1, r1) in rises(items):
            add(assessment, check, "warning", r1, gear_id,
                f"{gear_id}: {label} {shown(assessment, v1, kind)} in run {r1} "
                f"(h = {shown(assessment, h1, 'length')}) is not larger than "
                f"{shown(assessment, v0, kind)} in run {r0} (h = {shown(assessment, h0, 'length')})"
                f" with the same drop mass and lift: check for bottoming, a servicing change "
                f"between the drops, the sensor or the transcription", values=[v0, v1])
    factors: dict[tuple, list] = {}
    for run in assessment.runs:
        if run.get("n_combined") is not None:
            factors.setdefault(_condition(run.run), []).append(
                (run.get("h"), run.get("n_combined"), run.run.id))
    for items in factors.values():
        for (h0, v0, r0), (h1, v1, r1) in rises(items):
            add(assessment, "load-factor-not-rising", "warning", r1, None,
                f"run {r1}: combined load factor {v1:.4g} (h = {shown(assessment, h1, 'length')})"
                f" is not larger than {v0:.4g} in run {r0} (h = {shown(assessment, h0, 'length')})"
                f" with the same drop mass and lift: check the peak loads of both runs",
                values=[v0, v1])


def check_bottoming(assessment: Assessment) -> None:
    """Maximum stroke within the stated margin of the design stroke (a warning), or beyond
    the design stroke by more than ``audit.zero_travel_tolerance`` (an error: the strut
    cannot travel past its stops, so the stroke's scale or the design stroke is wrong)."""
    margin = assessment.campaign.spec.audit.bottoming_margin.si
    slack = assessment.campaign.spec.audit.zero_travel_tolerance.si
    for run, gear in gear_items(assessment):
        unit = assessment.campaign.gear_units[gear.gear_id]
        d_s = gear.get("d_s")
        if d_s is None:
            continue
        where = f"run {run.run.id}, {gear.gear_id}"
        if d_s > unit.design_stroke.si + slack:
            add(assessment, "stroke-exceeds-design", "error", run.run.id, gear.gear_id,
                f"{where}: stroke {shown(assessment, d_s, 'length')} exceeds the design stroke "
                f"{unit.design_stroke.text} (tolerance {shown(assessment, slack, 'length')}): "
                f"a strut cannot travel past its stops; check the stroke channel's scale and "
                f"offset, or gear_units[].design_stroke", stroke=d_s,
                design=unit.design_stroke.si)
        elif d_s >= (1 - margin) * unit.design_stroke.si:
            # at or past the stops but within the tolerance: the strut bottomed
            reach = (f"reaches the design stroke {unit.design_stroke.text} (past it by "
                     f"{shown(assessment, d_s - unit.design_stroke.si, 'length')}, within the "
                     f"tolerance {shown(assessment, slack, 'length')}): the strut bottomed"
                     if d_s >= unit.design_stroke.si else
                     f"is within {margin:.0%} of the design stroke {unit.design_stroke.text}")
            add(assessment, "near-bottoming", "warning", run.run.id, gear.gear_id,
                f"{where}: stroke {shown(assessment, d_s, 'length')} {reach}",
                stroke=d_s, design=unit.design_stroke.si)


def check_asymmetry(assessment: Assessment) -> None:
    """Left/right main units in one drop differ by more than the stated threshold."""
    threshold = assessment.campaign.spec.audit.asymmetry_threshold.si
    for run in assessment.runs:
        mains = [gear for gear in run.gears
                 if assessment.campaign.gear_units[gear.gear_id].position == "main"]
        if len(mains) != 2:
            continue
        a, b = mains
        for key, label, kind in (("F_peak", "peak load", "force"), ("d_s", "strut stroke", "length"),
                                 ("d_t", "tyre deflection", "length")):
            x, y = a.get(key), b.get(key)
            if x is None or y is None or x + y == 0:
                continue
            difference = abs(x - y) / (0.5 * (x + y))
            if difference > threshold:
                add(assessment, f"asymmetry-{key.replace('_', '-').lower()}", "warning",
                    run.run.id, None,
                    f"run {run.run.id}: {label} differs by {difference:.1%} between "
                    f"{a.gear_id} ({shown(assessment, x, kind)}) and {b.gear_id} "
                    f"({shown(assessment, y, kind)}); threshold {threshold:.0%}: check the "
                    f"two units' servicing, the airplane's attitude at touchdown and both "
                    f"channels", difference=difference)


def _static_load(unit) -> float:
    """Axial strut load at rest [N]: the unit's static weight less its unsprung mass."""
    strut = unit.strut
    unsprung = strut.unsprung_mass.si if strut.unsprung_mass is not None else 0.0
    inclination = strut.inclination.si if strut.inclination is not None else 0.0
    return static_strut_load(unit.static_weight.si, unsprung, inclination)


def check_static_stroke(assessment: Assessment) -> None:
    """Two relations of the declared static stroke s_0 (``strut.static_stroke``).

    Dynamic: at maximum travel of a drop that carries at least the static weight with no
    lift force, the upper mass is at rest and about to rebound, so the strut carries at
    least the static load, and with the damping force zero at the stroke's maximum the
    stroke is at least s_0 (less what seal friction holds: ``audit.static_stroke_tolerance``).

    Servicing: the gas law at rest (isothermal) gives the stroke at which the declared
    pre-charge, gas volume and pneumatic area carry the static load; with seal friction
    the strut may rest anywhere the gas force is within the friction of the load, and gas
    not yet at wall temperature sits nearer the polytropic stroke.  A declared s_0 outside
    that range by more than the tolerance is a warning: one of them is not as declared.
    """
    tolerance = assessment.campaign.spec.audit.static_stroke_tolerance.si
    for unit in assessment.campaign.spec.gear_units:
        strut = unit.strut
        if strut is None or strut.static_stroke is None:
            not_checked(assessment, "stroke-below-static", unit.id,
                        f"needs gear_units[{unit.id}].strut.static_stroke")
            continue
        s0 = strut.static_stroke.si
        low = [(run.run.id, gear.get("d_s")) for run, gear in gear_items(assessment)
               if gear.gear_id == unit.id and gear.get("d_s") is not None
               and lift_force_ratio(run.run) == 0
               and gear.get("W_drop") >= unit.static_weight.si * (1 - 1e-9)
               and gear.get("d_s") < (1 - tolerance) * s0]
        if low:
            listing = ", ".join(f"{run_id}: {shown(assessment, d, 'length')}" for run_id, d in low)
            add(assessment, "stroke-below-static", "warning", None, unit.id,
                f"{unit.id}: the maximum strut stroke ({listing}) is below the declared static "
                f"stroke {strut.static_stroke.text} by more than {tolerance:.0%}, in drops "
                f"carrying the full static weight without a lift force: at maximum travel the "
                f"strut carries at least the static load, so it travels at least the static "
                f"stroke; check the datum of the static stroke and the stroke channel",
                strokes=[d for _, d in low], static=s0)
        _check_servicing(assessment, unit, s0, tolerance)


def _check_servicing(assessment: Assessment, unit, s0: float, tolerance: float) -> None:
    strut = unit.strut
    needed = {"gas_precharge_pressure": strut.gas_precharge_pressure,
              "pressure_reference": strut.pressure_reference, "gas_volume": strut.gas_volume,
              "pneumatic_area": strut.pneumatic_area}
    missing = [name for name, value in needed.items() if value is None]
    if missing:
        not_checked(assessment, "static-stroke-vs-servicing", unit.id,
                    f"needs gear_units[{unit.id}].strut." + ", .".join(missing))
        return
    volume, area = strut.gas_volume.si, strut.pneumatic_area.si
    precharge = absolute_pressure(strut.gas_precharge_pressure.si, strut.pressure_reference)
    load = _static_load(unit)
    friction = 0.0
    if strut.seal_friction is not None:
        friction = strut.seal_friction.constant.si + strut.seal_friction.pressure_factor.si * load
    exponent = strut.polytropic_exponent.si if strut.polytropic_exponent is not None else 1.0
    lowest = gas_equilibrium_stroke(volume, area, precharge, max(load - friction, 0.0),
                                    max(exponent, 1.0))
    highest = gas_equilibrium_stroke(volume, area, precharge, load + friction, 1.0)
    if (1 + tolerance) * s0 < lowest or (1 - tolerance) * s0 > highest:
        isothermal = gas_equilibrium_stroke(volume, area, precharge, load, 1.0)
        add(assessment, "static-stroke-vs-servicing", "warning", None, unit.id,
            f"{unit.id}: the declared static stroke {strut.static_stroke.text} is not what the "
            f"servicing gives: the gas law at rest, p0·V0 = p·(V0 − A·s) with p0 = "
            f"{strut.gas_precharge_pressure.text} ({strut.pressure_reference}), V0 = "
            f"{strut.gas_volume.text}, A = {strut.pneumatic_area.text} and the static load "
            f"{shown(assessment, load, 'force')}, gives s = {shown(assessment, isothermal, 'length')}"
            f"; with seal friction and the polytropic exponent the strut rests between "
            f"{shown(assessment, lowest, 'length')} and {shown(assessment, highest, 'length')} "
            f"(tolerance {tolerance:.0%}); check the pre-charge and its reference (gauge or "
            f"absolute), the gas volume and how the static stroke was measured",
            declared=s0, isothermal=isothermal, low=lowest, high=highest)


def check_tyre_curve(assessment: Assessment) -> None:
    """At its maximum deflection d_t the tyre carries its static curve f(d_t) (damping is
    zero when the deflection stops growing, and a dynamic tyre is if anything stiffer), and
    the peak load is at least that: F_peak ≥ f(d_t).  A peak load below f(d_t) by more than
    ``audit.tyre_curve_tolerance`` is a warning: the tyre deflected more than its declared
    curve allows for the load (pressure, the curve or the deflection channel)."""
    tolerance = assessment.campaign.spec.audit.tyre_curve_tolerance.si
    for run, gear in gear_items(assessment):
        unit = assessment.campaign.gear_units[gear.gear_id]
        curve = unit.tyre.load_deflection
        f_peak, d_t = gear.get("F_peak"), gear.get("d_t")
        if curve is None:
            not_checked(assessment, "tyre-deflection-vs-curve", gear.gear_id,
                        f"needs gear_units[{gear.gear_id}].tyre.load_deflection")
        if curve is None or f_peak is None or d_t is None or d_t <= 0:
            continue   # a deflection that never rose above zero has no point on the curve
        expected = curve.reference_load.si * (d_t / curve.reference_deflection.si) \
            ** curve.exponent.si
        if f_peak < (1 - tolerance) * expected:
            add(assessment, "tyre-deflection-vs-curve", "warning", run.run.id, gear.gear_id,
                f"run {run.run.id}, {gear.gear_id}: tyre deflection "
                f"{shown(assessment, d_t, 'length')} needs {shown(assessment, expected, 'force')} "
                f"by the declared curve f(δ) = {curve.reference_load.text}·(δ/"
                f"{curve.reference_deflection.text})^{curve.exponent.si:g}, but the peak load "
                f"is {shown(assessment, f_peak, 'force')} ({f_peak / expected - 1:+.1%}, "
                f"tolerance {tolerance:.0%}): the tyre deflected more than its curve allows; "
                f"check the tyre pressure, the declared curve and the deflection channel",
                expected=expected, peak=f_peak)


def check_main_unit_weights(assessment: Assessment) -> None:
    """The main units' static weights, all defined in the same attitude (23.725(b): level,
    nose wheel clear, or tail down), add up to no more than the airplane's maximum weight.
    An error beyond ``audit.reported_tolerance``: the weights cannot all be right; a warning
    where one of them is only assumed."""
    spec = assessment.campaign.spec
    tolerance = spec.audit.reported_tolerance.si
    mains = [unit for unit in spec.gear_units if unit.position == "main"]
    if not mains:
        return
    total = sum(unit.static_weight.si for unit in mains)
    maximum = spec.aircraft.maximum_weight.si
    if total > maximum * (1 + tolerance):
        listing = " + ".join(f"{unit.id} {unit.static_weight.text}" for unit in mains)
        assumed = [unit.id for unit in mains if unit.static_weight_basis == "assumed"]
        add(assessment, "main-units-outweigh-aircraft", "warning" if assumed else "error",
            None, None,
            f"the main units' static weights {listing} = {shown(assessment, total, 'force')} "
            f"exceed the airplane's maximum weight {spec.aircraft.maximum_weight.text} by "
            f"{total / maximum - 1:.1%} (tolerance {tolerance:.0%}): the units carry the "
            f"airplane between them; check gear_units[].static_weight and "
            f"aircraft.maximum_weight"
            + (f" (assumed, not weighed: {', '.join(assumed)})" if assumed else ""),
            total=total, maximum=maximum)
