"""The compliance engine: campaign -> values with provenance -> verdicts per criterion.

``assess(campaign)`` computes, for the aircraft, each requirement set and each run
and gear unit, everything the inputs allow (from time series where a run has them,
otherwise from the values a source reported), evaluates every criterion of the
certification basis, and hands the result to :mod:`certkit.compliance.quality` for the
data-quality audit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from certkit.compliance import clauses
from certkit.spec import requirement_sets
from certkit.spec.campaign import Campaign
from certkit.compliance.quality import audit
from certkit.display import number, with_unit
from certkit.compliance.drop_conditions import drop_weight_share, lift_force_ratio, lift_ratio
from certkit.compliance.measures import (SETTLING_BAND, TOUCHDOWN_SHARE, VELOCITY_WINDOW, GearMeasures,
                       contact_velocity, drop_mass_load_factor, measure_gear)
from certkit.spec.requirement_sets import Criterion, RequirementSet
from certkit.compliance.results import (EQUALITY_TOLERANCE, FAIL, NOT_SHOWN, PASS, Comparison, Finding, Value,
                      Verdict)
from certkit.spec.rundata import RunSeries
from certkit.spec.schema import BasisEntry, GearUnit, Run
from certkit.units import STANDARD_GRAVITY

g = STANDARD_GRAVITY
#: The outcome of a planning campaign: it cannot be read as any of the compliance outcomes.
PLANNING = "PLANNING ONLY: NOT COMPLIANCE EVIDENCE"


class _Values:
    values: dict[str, Value]

    def get(self, key: str) -> float | None:
        """The SI magnitude of a value (None when absent or not computable)."""
        value = self.values.get(key)
        return None if value is None else value.value


@dataclass
class GearResult(_Values):
    """Everything known about one gear unit in one run."""

    run_id: str
    gear_id: str
    basis: str
    values: dict[str, Value]
    measures: GearMeasures | None = None


@dataclass
class RunResult(_Values):
    run: Run
    index: int
    values: dict[str, Value]
    gears: list[GearResult]
    series: RunSeries | None


@dataclass
class BasisResult:
    entry: BasisEntry
    rules: RequirementSet
    values: dict[str, Value]


@dataclass
class Assessment:
    """The evidence record of a campaign (inputs, derived values, verdicts, findings)."""

    campaign: Campaign
    design: dict[str, Value]
    basis: list[BasisResult]
    runs: list[RunResult]
    verdicts: list[Verdict] = field(default_factory=list)
    findings: list[Finding] = field(default_factory=list)
    comparisons: list[Comparison] = field(default_factory=list)

    @property
    def planning(self) -> bool:
        """A planning campaign (campaign.purpose: planning): its verdicts are predictions."""
        return is_planning(self.campaign)

    @property
    def outcome(self) -> str:
        """COMPLIANT only when every criterion passed on evidence free of data-quality errors
        and from confirmed requirement values; otherwise what stops it.  A planning campaign
        is never compliant: its outcome is :data:`PLANNING`."""
        if self.planning:
            return PLANNING
        states = {verdict.verdict for verdict in self.verdicts}
        if FAIL in states:
            return "NOT COMPLIANT"
        if NOT_SHOWN in states or any(f.severity == "error" for f in self.findings):
            return "COMPLIANCE NOT SHOWN"
        if any(verdict.to_confirm for verdict in self.verdicts):
            return "COMPLIANT SUBJECT TO CONFIRMATION"
        return "COMPLIANT"

    def outcome_reasons(self) -> list[str]:
        """Why the outcome is what it is, in words, for the cover page."""
        counts, findings = self.counts(), self.finding_counts()
        reasons = []
        if self.planning:
            reasons.append(
                f"a planning campaign (campaign.purpose: planning): every value is computed "
                f"from simulated histories, so the verdicts below are predictions for the "
                f"planned drops and show no compliance. Predicted: {counts[PASS]} pass, "
                f"{counts[FAIL]} fail, {counts[NOT_SHOWN]} not shown")
        if counts[FAIL]:
            reasons.append(f"{counts[FAIL]} criterion verdict(s) FAIL")
        if counts[NOT_SHOWN]:
            reasons.append(f"{counts[NOT_SHOWN]} criterion verdict(s) NOT SHOWN")
        if findings["error"]:
            reasons.append(f"{findings['error']} data-quality error(s): the evidence they "
                           f"concern cannot support a compliance statement until resolved")
        unconfirmed = sorted({v.requirement_set for v in self.verdicts if v.to_confirm})
        if unconfirmed:
            reasons.append("verdicts of " + ", ".join(unconfirmed) + " rest on values to be "
                           "confirmed against the licensed standard")
        return reasons

    def counts(self) -> dict[str, int]:
        return {state: sum(v.verdict == state for v in self.verdicts)
                for state in (PASS, FAIL, NOT_SHOWN)}

    def finding_counts(self) -> dict[str, int]:
        return {level: sum(f.severity == level for f in self.findings)
                for level in ("error", "warning", "info")}


def is_planning(campaign: Campaign) -> bool:
    """campaign.purpose is planning: values come from synthetic histories, as predictions."""
    return campaign.spec.campaign.purpose == "planning"


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


def _gear_result(campaign: Campaign, run: Run, index: int, gear_id: str,
                 series: RunSeries | None) -> GearResult:
    unit = campaign.gear_units[gear_id]
    strut = unit.strut
    inclination = strut.inclination.si if strut and strut.inclination else 0.0
    cos_theta = math.cos(inclination)
    reported = run.reported.gears.get(gear_id) if run.reported else None
    prefix = f"runs[{index}]"
    values: dict[str, Value] = {}
    measures = None

    def put(key, label, symbol, value, unit_, kind, source, formula="", inputs=None, note=None,
            typed=None):
        values[key] = Value(key, label, symbol, value, unit_, kind, source, formula,
                            inputs or {}, note, typed)

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
        unsprung = strut.unsprung_mass.si if strut and strut.unsprung_mass else 0.0
        measures = measure_gear(series.time, gear_series.load, gear_series.stroke,
                                gear_series.tyre, weight, inclination, unsprung)
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
            source_file | {"m2": _spec_input(f"gear_units[{gear_id}].strut.unsprung_mass",
                                             strut.unsprung_mass.text if unsprung else "not declared")},
            None if unsprung else "unsprung mass not declared: F_s = F_V·cos θ")
        put("E_t", "Energy absorbed by the tyre", "E_t", measures.tyre_energy, "J", "energy",
            "certkit E1", "E_t = ∫ F_V dδ, loading stroke", source_file)
        put("E_d", "Energy absorbed at maximum total travel", "E_d",
            measures.energy_at_max_travel, "J", "energy", "certkit E5",
            "E_d = E_s(t_d) + E_t(t_d), t_d the instant of maximum δ + s·cos θ", source_file,
            None if measures.energy_at_max_travel is not None
            else "needs stroke and tyre channels")
    elif reported is not None:
        basis = "reported values"
        where = f"{prefix}.reported.gears.{gear_id}"

        def rep(key, label, symbol, quantity, kind, name):
            put(key, label, symbol, None if quantity is None else quantity.si,
                {"force": "N", "length": "m", "energy": "J"}[kind], kind, "reported",
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
    else:
        basis = "no data"
        for key, label, kind, un in (("F_peak", "Peak vertical load", "force", "N"),
                                     ("d_s", "Maximum strut stroke", "length", "m"),
                                     ("d_t", "Maximum tyre deflection", "length", "m"),
                                     ("d", "Tyre deflection plus vertical axle travel", "length", "m"),
                                     ("E_s", "Energy absorbed by the strut", "energy", "J"),
                                     ("E_t", "Energy absorbed by the tyre", "energy", "J"),
                                     ("E_d", "Energy absorbed at maximum total travel", "energy",
                                      "J")):
            put(key, label, key, None, un, kind, "none", note="no time series and no reported value")

    result = GearResult(run.id, gear_id, basis, values, measures)
    _derived_gear_values(result, run, unit, cos_theta)
    return result


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
         "L_dev": f"{lift_force:g} (lift force applied by a device)"})
    e_d = get("E_d")
    implied = None
    if None not in (e_d, d):
        implied = e_d / (h + (1 - lift_force) * d)
    put("W_implied", "Drop weight implied by the absorbed energy", "W_implied", implied, "N",
        "force", "certkit E4", "W_implied = E_d/(h + (1 − L_dev)·d)",
        {"E_d": "E_d", "h": run.drop_height.text, "d": "d", "L_dev": f"{lift_force:g}"},
        None if implied is not None else "needs E_d (E5), which reported values do not give")

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


def _run_result(campaign: Campaign, run: Run, index: int) -> RunResult:
    series = campaign.series.get(run.id)
    if run.data is not None and run.data.origin == "synthetic" and not is_planning(campaign):
        series = None  # simulated histories are not test evidence (quality: synthetic-data)
    gears = [_gear_result(campaign, run, index, gear_id, series) for gear_id in run.gear_units]
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


# --------------------------------------------------------------------------- criteria
@dataclass
class _Context:
    assessment: Assessment
    basis: BasisResult

    @property
    def rules(self) -> RequirementSet:
        return self.basis.rules

    def verdict(self, criterion: Criterion, run: str | None, gear: str | None, state: str,
                **fields) -> Verdict:
        parts = [criterion.id] + [part for part in (run, gear) if part]
        return Verdict(id="/".join(parts), requirement_set=self.rules.id, criterion=criterion.id,
                       clause=criterion.clause, title=criterion.title, formula=criterion.formula,
                       run=run, gear=gear, verdict=state, to_confirm=self.rules.to_confirm,
                       **fields)


def _runs_of(assessment: Assessment, test_type: str) -> list[RunResult]:
    return [run for run in assessment.runs if run.run.test_type == test_type]


def _slack(value: float, limit: float, resolution: float | None) -> float:
    slack = EQUALITY_TOLERANCE * max(abs(value), abs(limit))
    return slack if resolution is None else min(slack, resolution)


def at_least(value: float, limit: float, resolution: float | None = None) -> str:
    """PASS when ``value`` is not less than ``limit``: equality holds, as "not less than" in
    14 CFR 23.725-23.727.  Equal means within :data:`~certkit.compliance.results.EQUALITY_TOLERANCE`
    (relative), and never more than ``resolution``: half a unit in the last digit of the
    typed value the criterion turns on (its ``stated_resolution_si``)."""
    return PASS if value >= limit - _slack(value, limit, resolution) else FAIL


def at_most(value: float, limit: float, resolution: float | None = None) -> str:
    """PASS when ``value`` does not exceed ``limit``, equality included (as :func:`at_least`)."""
    return PASS if value <= limit + _slack(value, limit, resolution) else FAIL


def _typed_resolution(quantity, value: float) -> float | None:
    """Half a unit in the last typed digit of ``quantity``, scaled to ``value`` (the same
    relative resolution), None for a quantity not typed."""
    if quantity is None or quantity.si == 0:
        return None
    return abs(value) * quantity.stated_resolution_si / abs(quantity.si)


def _height_check(ctx: _Context, criterion: Criterion, test_type: str, required_key: str,
                  what: str) -> list[Verdict]:
    required = ctx.basis.values.get(required_key)
    runs = _runs_of(ctx.assessment, test_type)
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, limit=required.value, unit="m",
                            kind="length", reason=f"no {what} drop in the test matrix")]
    verdicts = []
    for run in runs:
        h = run.get("h")
        verdicts.append(ctx.verdict(
            criterion, run.run.id, None,
            at_least(h, required.value, run.run.drop_height.stated_resolution_si), value=h,
            limit=required.value, margin=h - required.value, unit="m", kind="length",
            reason=f"{what} drop from {run.run.drop_height.text}"))
    return verdicts


def check_limit_drop_height(ctx, criterion):
    return _height_check(ctx, criterion, "limit", "h_req", "limit")


def check_reserve_drop_height(ctx, criterion):
    return _height_check(ctx, criterion, "reserve", "h_reserve", "reserve energy")


def check_dynamic_drop_height(ctx, criterion):
    """23.726(a): 2.25·h_req, or (option 2) a height developing 1.5 times the limit load factor."""
    required = ctx.basis.values["h_dynamic"]
    runs = _runs_of(ctx.assessment, "dynamic")
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, limit=required.value, unit="m",
                            kind="length", reason="no ground load dynamic drop in the test matrix")]
    n_limit = ctx.assessment.design["n_limit"].value
    n_limit_typed = ctx.assessment.campaign.spec.aircraft.design_limit_inertia_load_factor
    verdicts = []
    for run in runs:
        h = run.get("h")
        if at_least(h, required.value, run.run.drop_height.stated_resolution_si) == PASS:
            verdicts.append(ctx.verdict(criterion, run.run.id, None, PASS, value=h,
                                        limit=required.value, margin=h - required.value,
                                        unit="m", kind="length", reason="option (1): 2.25·h_req"))
            continue
        factors = [gear.get("n") for gear in run.gears]
        if n_limit is None or None in factors:
            verdicts.append(ctx.verdict(
                criterion, run.run.id, None, NOT_SHOWN, value=h, limit=required.value,
                margin=h - required.value, unit="m", kind="length",
                reason="below 2.25·h_req; option (2) needs n measured and n_limit declared"))
            continue
        n = max(factors)
        verdicts.append(ctx.verdict(
            criterion, run.run.id, None,
            at_least(n, 1.5 * n_limit, _typed_resolution(n_limit_typed, 1.5 * n_limit)), value=n,
            limit=1.5 * n_limit, margin=n - 1.5 * n_limit,
            reason="option (2): height developing 1.5 times the limit load factor"))
    return verdicts


def check_reserve_no_failure(ctx, criterion):
    runs = _runs_of(ctx.assessment, "reserve")
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN,
                            reason="no reserve energy drop in the test matrix")]
    verdicts = []
    for run in runs:
        inspection = run.run.inspection
        if ctx.assessment.planning:
            verdicts.append(ctx.verdict(criterion, run.run.id, None, NOT_SHOWN,
                                        reason="a planning campaign: whether the gear fails is "
                                               "found by inspecting it after the drop, which no "
                                               "simulation predicts"))
        elif inspection is None or inspection.failure is None:
            verdicts.append(ctx.verdict(criterion, run.run.id, None, NOT_SHOWN,
                                        reason="post-test inspection result not recorded"))
        else:
            verdicts.append(ctx.verdict(
                criterion, run.run.id, None, FAIL if inspection.failure else PASS,
                reason=("failure reported" if inspection.failure else "no failure reported")
                + (f"; yielding: {'yes' if inspection.yielding else 'no'}"
                   if inspection.yielding is not None else "")))
    return verdicts


def _effective_weight_check(ctx, criterion, test_type: str, what: str) -> list[Verdict]:
    """W_drop ≥ W_e per gear unit of each ``test_type`` drop (W_e: the gear's W1 share
    against the clause's effective weight, computed with the measured d)."""
    maximum = ctx.rules.number("wing_lift_ratio_maximum")
    runs = _runs_of(ctx.assessment, test_type)
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, unit="N", kind="force",
                            reason=f"no {what} drop in the test matrix")]
    verdicts = []
    for run in runs:
        lift = run.get("L")
        method = run.run.lift.method
        if method != "none" and test_type == "limit":
            verdicts.append(ctx.verdict(
                criterion, run.run.id, None,
                at_most(lift, maximum, _typed_resolution(run.run.lift.ratio, lift)), value=lift,
                limit=maximum, margin=maximum - lift, comparison="≤",
                reason=f"wing-lift ratio L represented in the drop ({method})"))
        reason = {"none": "no lift simulated: W_e = W",
                  "lift_device": "lift by a device: the full weight W is dropped",
                  "reduced_mass": ("reserve drop, W_e = W·h/(h + d), d as recorded"
                                   if test_type == "reserve" else
                                   f"reduced mass, L = {lift:g}, d as recorded (23.725(d))")}[method]
        for gear in run.gears:
            w_e, w_drop = gear.get("W_e"), gear.get("W_drop")
            static_weight = ctx.assessment.campaign.gear_units[gear.gear_id].static_weight
            if w_e is None:
                verdicts.append(ctx.verdict(criterion, run.run.id, gear.gear_id, NOT_SHOWN,
                                            unit="N", kind="force",
                                            reason="d (tyre deflection + axle travel) unknown"))
                continue
            verdicts.append(ctx.verdict(
                criterion, run.run.id, gear.gear_id,
                at_least(w_drop, w_e, min(_typed_resolution(run.run.drop_mass, w_drop),
                                          _typed_resolution(static_weight, w_e))),
                value=w_drop,
                limit=w_e, margin=w_drop - w_e, unit="N", kind="force", reason=reason))
    return verdicts


def check_effective_weight(ctx, criterion):
    """23.725(b),(d): limit drops."""
    return _effective_weight_check(ctx, criterion, "limit", "limit")


def check_reserve_effective_weight(ctx, criterion):
    """23.727(b): reserve energy drops, W_e = W·h/(h + d) when lift is simulated."""
    return _effective_weight_check(ctx, criterion, "reserve", "reserve energy")


def check_inertia_load_factor(ctx, criterion):
    n_limit = ctx.assessment.design["n_limit"].value
    n_limit_typed = ctx.assessment.campaign.spec.aircraft.design_limit_inertia_load_factor
    runs = _runs_of(ctx.assessment, "limit")
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, limit=n_limit,
                            reason="no limit drop in the test matrix")]
    verdicts = []
    for run in runs:
        for gear in run.gears:
            n = gear.get("n")
            if n is None:
                verdicts.append(ctx.verdict(criterion, run.run.id, gear.gear_id, NOT_SHOWN,
                                            limit=n_limit, comparison="≤",
                                            reason="drop-mass acceleration not recorded, so n_j "
                                                   "(23.725(e)) is unknown"))
            elif n_limit is None:
                verdicts.append(ctx.verdict(criterion, run.run.id, gear.gear_id, NOT_SHOWN,
                                            value=n, comparison="≤",
                                            reason="design limit inertia load factor not declared"))
            else:
                verdicts.append(ctx.verdict(
                    criterion, run.run.id, gear.gear_id,
                    at_most(n, n_limit, _typed_resolution(n_limit_typed, n_limit)),
                    value=n, limit=n_limit, margin=n_limit - n, comparison="≤",
                    reason=gear.values["n"].formula))
    return verdicts


def check_energy_method_load_factor(ctx, criterion):
    rules = ctx.rules
    lift = rules.number("energy_method_wing_lift_ratio")
    eta_t, eta_s = rules.number("tyre_efficiency"), rules.number("shock_absorber_efficiency")
    n_limit = ctx.assessment.design["n_limit"].value
    n_limit_typed = ctx.assessment.campaign.spec.aircraft.design_limit_inertia_load_factor
    runs = _runs_of(ctx.assessment, "limit")
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, limit=n_limit, comparison="≤",
                            reason="no limit drop in the test matrix")]
    verdicts = []
    for run in runs:
        for gear in run.gears:
            n = gear.get(f"n_energy[{rules.id}]")
            if n is None:
                verdicts.append(ctx.verdict(criterion, run.run.id, gear.gear_id, NOT_SHOWN,
                                            limit=n_limit, comparison="≤",
                                            reason="strut and tyre travel needed"))
            elif n_limit is None:
                verdicts.append(ctx.verdict(
                    criterion, run.run.id, gear.gear_id, NOT_SHOWN, value=n, comparison="≤",
                    reason=f"design limit inertia load factor not declared "
                           f"(n = n_j + L with L = {lift:.4g}, η_t = {eta_t}, η_s = {eta_s})"))
            else:
                verdicts.append(ctx.verdict(
                    criterion, run.run.id, gear.gear_id,
                    at_most(n, n_limit, _typed_resolution(n_limit_typed, n_limit)),
                    value=n, limit=n_limit, margin=n_limit - n, comparison="≤",
                    reason=f"n = n_j + L, L = {lift:.4g}, η_t = {eta_t}, η_s = {eta_s}"))
    return verdicts


def check_design_load_factor_minimum(ctx, criterion):
    n_limit = ctx.assessment.design["n_limit"].value
    n_limit_typed = ctx.assessment.campaign.spec.aircraft.design_limit_inertia_load_factor
    lift = ctx.assessment.design["L_design"].value
    minimum = max(ctx.rules.number("inertia_load_factor_minimum"),
                  ctx.rules.number("ground_reaction_factor_minimum") + lift)
    if n_limit is None:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, limit=minimum,
                            reason="design limit inertia load factor not declared")]
    return [ctx.verdict(criterion, None, None,
                        at_least(n_limit, minimum, _typed_resolution(n_limit_typed, n_limit)),
                        value=n_limit,
                        limit=minimum, margin=n_limit - minimum,
                        reason=f"minimum = max(2.67, 2.0 + L) with L = {lift:g}")]


CHECKS = {
    "limit_drop_height": check_limit_drop_height,
    "reserve_drop_height": check_reserve_drop_height,
    "dynamic_drop_height": check_dynamic_drop_height,
    "reserve_no_failure": check_reserve_no_failure,
    "effective_weight": check_effective_weight,
    "reserve_effective_weight": check_reserve_effective_weight,
    "inertia_load_factor": check_inertia_load_factor,
    "energy_method_load_factor": check_energy_method_load_factor,
    "design_load_factor_minimum": check_design_load_factor_minimum,
}


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
        Design values, per-run values, verdicts, data-quality findings and the
        comparison of reported against recomputed values.
    """
    design = _design_values(campaign)
    basis = []
    for entry in campaign.spec.certification_basis:
        rules = requirement_sets.load(entry.requirement_set)
        basis.append(BasisResult(entry, rules, _basis_values(rules, design,
                                                             campaign.spec.report.units)))
    runs = [_run_result(campaign, run, index) for index, run in enumerate(campaign.spec.runs)]
    assessment = Assessment(campaign, design, basis, runs)
    _energy_method_values(assessment)
    for item in basis:
        ctx = _Context(assessment, item)
        for criterion in item.rules.criteria:
            if criterion.applies_if and not getattr(item.entry, criterion.applies_if):
                continue
            assessment.verdicts.extend(CHECKS[criterion.check](ctx, criterion))
    audit(assessment)
    return assessment
