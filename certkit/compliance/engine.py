"""The compliance engine: campaign -> values with provenance -> verdicts per criterion.

``assess(campaign)`` computes, for the aircraft, each requirement set and each run
and gear unit, everything the inputs allow (from time series where a run has them,
otherwise from the values a source reported), evaluates every criterion of the
certification basis, and hands the result to :mod:`certkit.compliance.quality` for the
data-quality audit.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from functools import partial

from certkit.compliance import clauses
from certkit.compliance.assessment import (Assessment, BasisResult, GearResult, RunResult,
                                           is_planning)
from certkit.compliance.criteria import evaluate as evaluate_criteria
from certkit.compliance.drop_conditions import drop_weight_share, lift_force_ratio, lift_ratio
from certkit.compliance.measures import (SETTLING_BAND, TOUCHDOWN_SHARE, VELOCITY_WINDOW,
                                         GearMeasures, contact_velocity, drop_mass_load_factor,
                                         measure_gear)
from certkit.compliance.quality import audit
from certkit.compliance.uncertainty_inputs import RepeatedMeasures
from certkit.compliance.verdict_uncertainty import budgets
from certkit.display import SI_UNITS, number, with_unit
from certkit.results import Value
from certkit.spec import requirement_sets
from certkit.spec.campaign import Campaign
from certkit.spec.requirement_sets import RequirementSet
from certkit.spec.rundata import RunSeries
from certkit.spec.schema import GearUnit, Run
from certkit.units import STANDARD_GRAVITY

g = STANDARD_GRAVITY


def _spec_input(location: str, text: str) -> str:
    return f"{location} = {text}"


# --------------------------------------------------------------------------- design quantities
def _design_values(campaign: Campaign) -> dict[str, Value]:
    aircraft = campaign.spec.aircraft
    units = campaign.spec.report.units
    weight, area = aircraft.maximum_weight, aircraft.wing_area
    loading = weight.si / area.si
    values = {
        "W": Value("W", "Maximum weight", "W", weight.si, "N", "force", "spec",
                   inputs={"W": _spec_input("aircraft.maximum_weight", weight.text)},
                   note="a mass is converted with standard gravity", typed=weight.text),
        "S": Value("S", "Wing area", "S", area.si, "m^2", "area", "spec",
                   inputs={"S": _spec_input("aircraft.wing_area", area.text)}, typed=area.text),
        "W/S": Value("W/S", "Wing loading", "W/S", loading, "Pa", "wing_loading",
                     "14 CFR 23.725(a) (W/S)", "W/S", {"W": "W", "S": "S"}),
        "L_design": Value("L_design", "Wing-lift ratio of the loads basis", "L",
                          aircraft.wing_lift_ratio.si, "1", "ratio", "spec",
                          inputs={"L": _spec_input("aircraft.wing_lift_ratio",
                                                   aircraft.wing_lift_ratio.text)},
                          typed=aircraft.wing_lift_ratio.text),
    }
    v_formula, v_bounded = clauses.limit_descent_velocity(loading)
    values["V_descent"] = Value(
        "V_descent", "Limit descent velocity", "V", v_bounded, "m/s", "velocity",
        "14 CFR 23.473(d)", "V = 4.4·(W/S)^(1/4) ft/s, not less than 7 ft/s, need not exceed 10 ft/s",
        {"W/S": "W/S"}, note=(None if math.isclose(v_formula, v_bounded)
                              else f"formula gives {with_unit(v_formula, 'velocity', units)}; "
                                   f"bound applied"))
    n_limit = aircraft.design_limit_inertia_load_factor
    values["n_limit"] = Value(
        "n_limit", "Design limit inertia load factor", "n_limit",
        None if n_limit is None else n_limit.si, "1", "ratio", "spec",
        inputs={"n_limit": _spec_input("aircraft.design_limit_inertia_load_factor",
                                       n_limit.text if n_limit else "not declared")},
        note=None if n_limit else "not declared: the load-factor criteria cannot be shown",
        typed=n_limit.text if n_limit else None)
    return values


def _basis_values(rules: RequirementSet, design: dict[str, Value], display_units
                  ) -> dict[str, Value]:
    params = rules.parameters
    units = params["drop_height_formula_units"]
    height = clauses.required_drop_height(
        design["W/S"].value, rules.number("drop_height_coefficient"), units["wing_loading"],
        units["height"], rules.length("drop_height_minimum"), rules.length("drop_height_maximum"))
    coefficient = params["drop_height_coefficient"]
    note = None
    if height.bound:
        note = (f"formula gives {with_unit(height.formula, 'length', display_units)}; the "
                f"clause's {height.bound} applies")
    values = {
        "h_formula": Value("h_formula", "Drop height from the formula", "h",
                           height.formula, "m", "length", f"{rules.id}: drop height",
                           f"h = {coefficient}·√(W/S) {units['height']} "
                           f"(W/S in {units['wing_loading']})", {"W/S": "W/S"}),
        "h_req": Value("h_req", "Required limit drop height", "h_req", height.required, "m",
                       "length", f"{rules.id}: drop height",
                       f"h_req = h bounded to [{params.get('drop_height_minimum')}, "
                       f"{params.get('drop_height_maximum')}]", {"h": "h_formula"}, note),
    }
    for parameter, key, label, symbol, clause in (
            ("reserve_height_factor", "h_reserve", "Required reserve energy drop height",
             "h_reserve", "14 CFR 23.727(a)"),
            ("dynamic_height_factor", "h_dynamic",
             "Ground load dynamic test drop height (23.726 option 1)", "h_dyn",
             "14 CFR 23.726(a)(1)")):
        if parameter in params:
            factor = rules.number(parameter)
            values[key] = Value(key, label, symbol, factor * height.required, "m", "length",
                                clause, f"{symbol} = {factor}·h_req", {"h_req": "h_req"})
    return values


# --------------------------------------------------------------------------- per run, per gear
def _drop_weight_share(run: Run, unit: GearUnit, campaign: Campaign) -> tuple[float, str]:
    share = drop_weight_share(campaign.spec, run, unit.id)
    if len(run.gear_units) == 1:
        return share, "W_drop = m_drop·g (certkit W1)"
    return share, "W_drop = W_unit·m_drop·g/W_max (certkit W1)"


class _Collector:
    """The values of one gear unit in one run, as they are put."""

    def __init__(self):
        self.values: dict[str, Value] = {}

    def put(self, key, label, symbol, value, unit_, kind, source, formula="", inputs=None,
            note=None, typed=None):
        self.values[key] = Value(key, label, symbol, value, unit_, kind, source, formula,
                                 inputs or {}, note, typed)


def _gear_result(campaign: Campaign, run: Run, index: int, gear_id: str,
                 series: RunSeries | None, measure: Callable = measure_gear) -> GearResult:
    unit = campaign.gear_units[gear_id]
    strut = unit.strut
    inclination = strut.inclination.si if strut and strut.inclination else 0.0
    cos_theta = math.cos(inclination)
    assumptions = {}
    if not (strut and strut.inclination is not None):
        assumptions["θ"] = (f"θ = 0 assumed (strut vertical): "
                            f"gear_units[{gear_id}].strut.inclination not declared")
    reported = run.reported.gears.get(gear_id) if run.reported else None
    prefix = f"runs[{index}]"
    collected = _Collector()
    put = collected.put
    measures = None

    weight = unit.static_weight.si
    put("W", "Static weight on the unit", "W", weight, "N", "force", "spec",
        inputs={"W": _spec_input(f"gear_units[{gear_id}].static_weight", unit.static_weight.text)},
        note=("assumed, not weighed per 23.725(b)" if unit.static_weight_basis == "assumed"
              else None), typed=unit.static_weight.text)
    drop_weight, drop_formula = _drop_weight_share(run, unit, campaign)
    put("W_drop", "Drop weight acting on the unit", "W_drop", drop_weight, "N", "force",
        "certkit W1", drop_formula,
        {"m_drop": _spec_input(f"{prefix}.drop_mass", run.drop_mass.text), "W_unit": "W",
         "W_max": "aircraft.maximum_weight"})

    gear_series = series.gears.get(gear_id) if series else None
    if gear_series is not None:
        basis = f"time series ({series.file})"
        measures = _measured_values(put, series, gear_series, unit, weight, inclination,
                                    measure)
        if not (strut and strut.unsprung_mass is not None):
            assumptions["m2"] = (f"m2 = 0 assumed (F_s = F_V·cos θ): "
                                 f"gear_units[{gear_id}].strut.unsprung_mass not declared")
    elif reported is not None:
        basis = "reported values"
        _reported_values(put, reported, f"{prefix}.reported.gears.{gear_id}", cos_theta)
    else:
        basis = "no data"
        _no_data_values(put)
    result = GearResult(run.id, gear_id, basis, collected.values, measures, assumptions)
    _derived_gear_values(result, run, unit, cos_theta)
    return result


#: How an assumed input shows in a value's formula (the values that use it directly).
_ASSUMED_SYMBOLS = {"θ": "θ", "m2": "m2"}


def mark_assumptions(gear: GearResult) -> None:
    """Print each of ``gear``'s assumptions beside every value it affects: the values whose
    formula uses the assumed symbol, and every value computed from one of those (through
    its inputs).  A value not computed (None) keeps its own note."""
    for symbol, words in gear.assumptions.items():
        affected: set[str] = set()
        changed = True
        while changed:
            changed = False
            for key, value in gear.values.items():
                if key in affected:
                    continue
                uses = (_ASSUMED_SYMBOLS[symbol] in value.formula
                        or any(name in affected for name in (*value.inputs, *value.inputs.values())))
                if uses:
                    affected.add(key)
                    changed = True
        for key in affected:
            value = gear.values[key]
            if value.value is None:
                continue
            note = f"{value.note}; {words}" if value.note else words
            gear.values[key] = replace(value, note=note,
                                       inputs={**value.inputs, symbol: words.split(":")[0]})


def _measured_values(put, series: RunSeries, gear_series, unit: GearUnit, weight: float,
                     inclination: float, measure: Callable = measure_gear) -> GearMeasures:
    """The values measured from a gear unit's time series (certkit M1-M3, E1, E5)."""
    strut = unit.strut
    declared = strut is not None and strut.unsprung_mass is not None
    unsprung = strut.unsprung_mass.si if declared else 0.0
    measures = measure(series.time, gear_series.load, gear_series.stroke, gear_series.tyre,
                       weight, inclination, unsprung)
    source_file = {"data": series.file}
    put("t0", "Touchdown time", "t_0", measures.touchdown_time, "s", "time", "certkit M3",
        inputs=source_file,
        note=None if measures.touchdown_time is not None else
        "record starts with the tyre already loaded: touchdown not observed")
    put("F_peak", "Peak vertical load", "F_peak", measures.peak_load, "N", "force",
        "certkit M1", "F_peak = max F_V(t)", source_file)
    put("d_s", "Maximum strut stroke", "d_s", measures.max_stroke, "m", "length",
        "certkit M2", "d_s = max s(t)", source_file,
        None if measures.max_stroke is not None else "stroke not recorded")
    put("d_t", "Maximum tyre deflection", "d_t", measures.max_tyre, "m", "length",
        "certkit M2", "d_t = max δ(t)", source_file,
        None if measures.max_tyre is not None else "tyre deflection not recorded")
    put("d", "Tyre deflection plus vertical axle travel", "d", measures.max_total_travel,
        "m", "length", "14 CFR 23.725(b); certkit M2", "d = max(δ + s·cos θ)", source_file,
        None if measures.max_total_travel is not None else "needs stroke and tyre channels")
    put("E_s", "Energy absorbed by the strut", "E_s", measures.strut_energy, "J", "energy",
        "certkit E1", "E_s = ∫ F_s ds, F_s/cos θ = F_V − m2·(g − δ̈), loading stroke",
        source_file | ({"m2": _spec_input(f"gear_units[{unit.id}].strut.unsprung_mass",
                                          strut.unsprung_mass.text)} if declared else {}))
    put("E_t", "Energy absorbed by the tyre", "E_t", measures.tyre_energy, "J", "energy",
        "certkit E1", "E_t = ∫ F_V dδ, loading stroke", source_file)
    if declared or measures.energy_at_max_travel is None:
        put("E_d", "Energy absorbed at maximum total travel", "E_d",
            measures.energy_at_max_travel, "J", "energy", "certkit E5",
            "E_d = E_s(t_d) + E_t(t_d), t_d the instant of maximum δ + s·cos θ",
            source_file | {"m2": "m2"},
            None if measures.energy_at_max_travel is not None
            else "needs stroke and tyre channels")
    else:
        # with m2 = 0 the force decelerating the wheel counts as strut work: E_d would exceed
        # what the drop supplied by about m2·g·h, which is what E5 against E3 checks
        put("E_d", "Energy absorbed at maximum total travel", "E_d", None, "J", "energy",
            "certkit E5", "E_d = E_s(t_d) + E_t(t_d), t_d the instant of maximum δ + s·cos θ",
            source_file,
            f"needs the unsprung mass m2 (gear_units[{unit.id}].strut.unsprung_mass): with "
            f"m2 = 0 the force that decelerates the wheel would count as absorbed work")
    return measures


def _reported_values(put, reported, where: str, cos_theta: float) -> None:
    """The values a source reported for a gear unit without time series."""
    def rep(key, label, symbol, quantity, kind, name):
        put(key, label, symbol, None if quantity is None else quantity.si,
            SI_UNITS[kind], kind, "reported",
            inputs={symbol: _spec_input(f"{where}.{name}", quantity.text)} if quantity else {},
            note=None if quantity is not None else "not reported",
            typed=None if quantity is None else quantity.text)

    rep("F_peak", "Peak vertical load", "F_peak", reported.peak_vertical_load, "force",
        "peak_vertical_load")
    rep("d_s", "Maximum strut stroke", "d_s", reported.strut_stroke, "length", "strut_stroke")
    rep("d_t", "Maximum tyre deflection", "d_t", reported.tyre_deflection, "length",
        "tyre_deflection")
    total = None
    if reported.strut_stroke is not None and reported.tyre_deflection is not None:
        total = reported.tyre_deflection.si + reported.strut_stroke.si * cos_theta
    put("d", "Tyre deflection plus vertical axle travel", "d", total, "m", "length",
        "14 CFR 23.725(b); certkit M2", "d = d_t + d_s·cos θ", {"d_t": "d_t", "d_s": "d_s"},
        "upper bound from the reported maxima" if total is not None else "not computable")
    rep("E_s", "Energy absorbed by the strut", "E_s", reported.strut_energy, "energy",
        "strut_energy")
    rep("E_t", "Energy absorbed by the tyre", "E_t", reported.tyre_energy, "energy",
        "tyre_energy")
    put("E_d", "Energy absorbed at maximum total travel", "E_d", None, "J", "energy",
        "certkit E5", note="not known from reported values: E_s and E_t each run to their "
                           "own maximum, so their sum is not the work at maximum travel")


def _no_data_values(put) -> None:
    """Neither time series nor reported values: every measured value absent, and why."""
    for key, label, kind, un in (("F_peak", "Peak vertical load", "force", "N"),
                                 ("d_s", "Maximum strut stroke", "length", "m"),
                                 ("d_t", "Maximum tyre deflection", "length", "m"),
                                 ("d", "Tyre deflection plus vertical axle travel", "length", "m"),
                                 ("E_s", "Energy absorbed by the strut", "energy", "J"),
                                 ("E_t", "Energy absorbed by the tyre", "energy", "J"),
                                 ("E_d", "Energy absorbed at maximum total travel", "energy",
                                  "J")):
        put(key, label, key, None, un, kind, "none", note="no time series and no reported value")


def _derived_gear_values(result: GearResult, run: Run, unit: GearUnit, cos_theta: float) -> None:
    values = result.values
    get = result.get
    h, lift, lift_force = run.drop_height.si, lift_ratio(run), lift_force_ratio(run)

    def put(key, label, symbol, value, unit_, kind, source, formula, inputs, note=None):
        values[key] = Value(key, label, symbol, value, unit_, kind, source, formula, inputs, note)

    f_peak, weight = get("F_peak"), get("W")
    put("F/W", "Ground-reaction factor", "F_peak/W",
        None if f_peak is None else f_peak / weight, "1", "ratio", "certkit G1",
        "F_peak/W", {"F_peak": "F_peak", "W": "W"})
    for element, energy, travel, factor in (("s", "E_s", "d_s", cos_theta),
                                            ("t", "E_t", "d_t", 1.0)):
        e, d = get(energy), get(travel)
        eta = None
        if None not in (e, d, f_peak):
            eta = e / (f_peak * d * factor) if f_peak > 0 and d > 0 else None
        name = "strut" if element == "s" else "tyre"
        rectangle = "F_peak·cos θ·d_s" if element == "s" else "F_peak·d_t"
        put(f"eta_{element}", f"Efficiency of the {name}", f"η_{element}", eta, "1", "ratio",
            "certkit E2", f"η_{element} = {energy}/({rectangle})",
            {energy: energy, "F_peak": "F_peak", travel: travel},
            None if eta is not None else "needs energy, peak load and travel")
    d, drop_weight = get("d"), get("W_drop")
    available = None if d is None else clauses.available_energy(drop_weight, h, d, lift_force)
    put("E_avail", "Energy available to absorb", "E_avail", available, "J", "energy",
        "certkit E3", "E_avail = W_drop·(h + d) − L_dev·W_drop·d",
        {"W_drop": "W_drop", "h": f"drop height {run.drop_height.text}", "d": "d",
         "L_dev": f"{lift_force:g} (share of the weight a lift device carries; 0 without "
                  f"a device)"})
    e_d = get("E_d")
    implied = None
    if None not in (e_d, d):
        implied = e_d / (h + (1 - lift_force) * d)
    put("W_implied", "Drop weight implied by the absorbed energy", "W_implied", implied, "N",
        "force", "certkit E4", "W_implied = E_d/(h + (1 − L_dev)·d)",
        {"E_d": "E_d", "h": run.drop_height.text, "d": "d", "L_dev": f"{lift_force:g}"},
        None if implied is not None else
        f"needs E_d (E5): {values['E_d'].note or 'not known'}")

    if run.lift.method == "reduced_mass" and run.test_type == "reserve":
        w_e = None if d is None else clauses.reserve_effective_weight(weight, h, d)
        put("W_e", "Effective weight (reserve drop)", "W_e", w_e, "N", "force",
            "14 CFR 23.727(b)", "W_e = W·h/(h + d)",
            {"W": "W", "h": run.drop_height.text, "d": "d"}, None if d is not None else "needs d")
    elif run.lift.method == "reduced_mass":
        w_e = None if d is None else clauses.effective_weight(weight, h, d, lift)
        put("W_e", "Effective weight", "W_e", w_e, "N", "force", "14 CFR 23.725(b)",
            "W_e = W·(h + (1 − L)·d)/(h + d)",
            {"W": "W", "h": run.drop_height.text, "d": "d (as recorded, 23.725(d))", "L": f"{lift:g}"},
            None if d is not None else "needs d")
    else:
        reason = ("no lift simulated" if run.lift.method == "none"
                  else "lift applied by a device, not by a reduced mass")
        put("W_e", "Weight to be dropped", "W_e", weight, "N", "force", "14 CFR 23.725(b)",
            "W_e = W", {"W": "W"}, f"{reason}: the full static weight is dropped")
    if unit.design_stroke is not None:
        d_s = get("d_s")
        put("bottoming_margin", "Stroke left before the design stroke", "s_design − d_s",
            None if d_s is None else unit.design_stroke.si - d_s, "m", "length", "certkit B1",
            "design stroke − d_s", {"design stroke": unit.design_stroke.text, "d_s": "d_s"})
    measures = result.measures
    if measures is not None:
        put("min_stroke_after_peak", "Minimum stroke after the maximum (rebound)", "s_reb",
            measures.min_stroke_after_peak, "m", "length", "certkit R1", "min s(t > t(d_s))",
            {"s": "stroke channel"})
        put("lift_off", "Time the wheel is off the platform after the peak", "t_off",
            measures.lift_off_duration if measures.lift_off_duration is not None else 0.0,
            "s", "time", "certkit R1",
            f"time with F_V < {100 * TOUCHDOWN_SHARE:g} % W after the peak", {"F_V": "load"})
        put("settling_time", "Settling time of the stroke", "t_settle", measures.settling_time,
            "s", "time", "certkit S1",
            f"±{100 * SETTLING_BAND:g} % band", {"s": "stroke channel"},
            None if measures.settling_time is not None or measures.max_stroke is None
            else "not settled within the record")


def _run_result(campaign: Campaign, run: Run, index: int,
                measure: Callable = measure_gear) -> RunResult:
    series = campaign.series.get(run.id)
    if run.data is not None and run.data.origin == "synthetic" and not is_planning(campaign):
        series = None  # simulated histories are not test evidence (quality: synthetic-data)
    gears = [_gear_result(campaign, run, index, gear_id, series, measure)
             for gear_id in run.gear_units]
    values: dict[str, Value] = {}
    h = run.drop_height
    values["h"] = Value("h", "Free drop height", "h", h.si, "m", "length", "spec",
                        inputs={"h": _spec_input(f"runs[{index}].drop_height", h.text)},
                        typed=h.text)
    values["m_drop"] = Value("m_drop", "Drop mass", "m_drop", run.drop_mass.si, "kg", "mass",
                             "spec", inputs={"m": _spec_input(f"runs[{index}].drop_mass",
                                                              run.drop_mass.text)},
                             typed=run.drop_mass.text)
    values["L"] = Value("L", "Wing-lift ratio simulated in the drop", "L", lift_ratio(run), "1",
                        "ratio", "spec", inputs={"lift": f"runs[{index}].lift.method = "
                                                         f"{run.lift.method}"})
    values["v0_ideal"] = Value("v0_ideal", "Contact velocity of a free drop", "v_0",
                               clauses.ideal_impact_velocity(h.si), "m/s", "velocity",
                               "certkit V1", "v_0 = √(2·g·h)", {"h": "h"})
    touchdowns = [gear.get("t0") for gear in gears if gear.get("t0") is not None]
    if series is not None and series.displacement is not None and touchdowns:
        velocity = contact_velocity(series.time, series.displacement, min(touchdowns))
        values["v0_measured"] = Value(
            "v0_measured", "Contact velocity from the recorded drop", "v_0,meas", velocity, "m/s", "velocity",
            "certkit V2", f"dx/dt at touchdown, parabola fitted over the "
                          f"{VELOCITY_WINDOW * 1e3:g} ms before it",
            {"x": "drop_mass_displacement"},
            None if velocity is not None else "fewer than 5 samples before touchdown")
    n_j = None
    if series is not None and series.acceleration is not None and touchdowns:
        n_j = drop_mass_load_factor(series.time, series.acceleration,
                                    series.acceleration_reference, min(touchdowns))
    values["n_j"] = Value(
        "n_j", "Load factor developed in the drop", "n_j", n_j, "1", "ratio",
        "14 CFR 23.725(e)", "n_j = (dv/dt)/g + 1 (peak drop-mass acceleration)",
        {"a": "drop_mass_acceleration"},
        None if n_j is not None else "drop-mass acceleration not recorded")
    mains = [gear for gear in gears if campaign.gear_units[gear.gear_id].position == "main"]
    peaks = [gear.get("F_peak") for gear in mains]
    if len(mains) >= 2 and None not in peaks:
        values["n_combined"] = Value(
            "n_combined", "Combined ground-reaction factor of the main units", "ΣF_peak/(m·g)",
            sum(peaks) / (run.drop_mass.si * g), "1", "ratio", "certkit G2",
            "ΣF_peak(main)/(m_drop·g)",
            {f"F_peak[{gear.gear_id}]": "F_peak" for gear in mains} | {"m_drop": "m_drop"})
    result = RunResult(run, index, values, gears, series)
    for gear in gears:
        weight = gear.get("W")
        if n_j is not None:
            ratio = gear.get("W_drop") / weight
            if run.lift.method == "lift_device":
                # the device's lift acts on the drop mass, so n_j already contains L
                n = clauses.inertia_load_factor(n_j, gear.get("W_drop"), weight, 0.0)
                formula = "n = n_j·W_drop/W (lift applied by a device is already in n_j)"
                lift_text = "in n_j"
            else:
                n = clauses.inertia_load_factor(n_j, gear.get("W_drop"), weight, lift_ratio(run))
                formula = "n = n_j·W_e/W + L (W_e: the weight actually dropped)"
                lift_text = f"{lift_ratio(run):g}"
            gear.values["n"] = Value(
                "n", "Limit inertia load factor from the drop", "n", n, "1", "ratio",
                "14 CFR 23.725(e)", formula,
                {"n_j": "n_j", "W_e/W": number(ratio), "L": lift_text})
    return result


def _energy_method_values(assessment: Assessment) -> None:
    """The energy-method load factor of each set that defines one, per run and gear."""
    for basis in assessment.basis:
        rules = basis.rules
        if "tyre_efficiency" not in rules.parameters:
            continue
        lift = rules.number("energy_method_wing_lift_ratio")
        eta_t, eta_s = rules.number("tyre_efficiency"), rules.number("shock_absorber_efficiency")
        for run in assessment.runs:
            h = run.get("h")
            for gear in run.gears:
                unit = assessment.campaign.gear_units[gear.gear_id]
                strut = unit.strut
                cos_theta = math.cos(strut.inclination.si if strut and strut.inclination else 0.0)
                d_t, d_s = gear.get("d_t"), gear.get("d_s")
                n_g = None
                if (d_t is not None and d_s is not None
                        and eta_t * d_t + eta_s * d_s * cos_theta > 0):
                    n_g = clauses.energy_method_load_factor(h, d_t, d_s * cos_theta, lift,
                                                            eta_t, eta_s)
                formula = (f"n_j = (h + (1 − L)·d)/(η_t·d_t + η_s·d_s·cos θ), L = {lift:.4g}, "
                           f"η_t = {eta_t}, η_s = {eta_s}")
                inputs = {"h": "h", "d_t": "d_t", "d_s": "d_s"}
                gear.values[f"n_j_energy[{rules.id}]"] = Value(
                    f"n_j_energy[{rules.id}]", "Energy-method load factor", "n_j,E", n_g, "1",
                    "ratio", f"{rules.id}: energy method", formula, inputs,
                    None if n_g is not None else "needs positive strut and tyre travel")
                gear.values[f"n_energy[{rules.id}]"] = Value(
                    f"n_energy[{rules.id}]", "Energy-method inertia load factor", "n_E",
                    None if n_g is None else n_g + lift, "1", "ratio",
                    f"{rules.id}: energy method", "n = n_j,E + L",
                    {"n_j,E": f"n_j_energy[{rules.id}]", "L": f"{lift:.4g}"})


def assess(campaign: Campaign) -> Assessment:
    """Assess a loaded campaign against its certification basis.

    Returns
    -------
    Assessment
        Design values, per-run values, verdicts (each with its measurement uncertainty and
        its outcome under the campaign's decision rule), data-quality findings and the
        comparison of reported against recomputed values.
    """
    assessment = evaluate(campaign)
    # the probes re-read a gear's records only when they changed (RepeatedMeasures)
    found = budgets(assessment, partial(evaluate, measure=RepeatedMeasures()))
    assessment.uncertainty = found
    assessment.verdicts = [replace(verdict, verdict=found.verdicts[verdict.id].outcome,
                                   uncertainty=found.verdicts[verdict.id])
                           if verdict.id in found.verdicts else verdict
                           for verdict in assessment.verdicts]
    audit(assessment)
    return assessment


def evaluate(campaign: Campaign, measure: Callable = measure_gear) -> Assessment:
    """The values and verdicts of a campaign, without the data-quality audit and the
    uncertainties: the function every sensitivity of
    :mod:`certkit.compliance.verdict_uncertainty` is a difference of.  ``measure`` reads a
    gear unit's records (:func:`~certkit.compliance.measures.measure_gear`, or one that
    remembers its results: :class:`~certkit.compliance.uncertainty_inputs.RepeatedMeasures`)."""
    design = _design_values(campaign)
    basis = []
    for entry in campaign.spec.certification_basis:
        rules = requirement_sets.load(entry.requirement_set)
        basis.append(BasisResult(entry, rules, _basis_values(rules, design,
                                                             campaign.spec.report.units)))
    runs = [_run_result(campaign, run, index, measure)
            for index, run in enumerate(campaign.spec.runs)]
    assessment = Assessment(campaign, design, basis, runs)
    _energy_method_values(assessment)
    for run in runs:
        for gear in run.gears:
            mark_assumptions(gear)
    for item in basis:
        assessment.verdicts.extend(evaluate_criteria(assessment, item))
    return assessment
