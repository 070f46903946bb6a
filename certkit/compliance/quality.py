"""The data-quality audit: physical consistency of the evidence and reported-vs-recomputed values.

Each check is one function appending :class:`~certkit.results.Finding` records;
thresholds come from the campaign's ``audit`` section, so a lab can tighten them
and the report states the ones used.
"""

from __future__ import annotations

from certkit.compliance.assessment import Assessment
from certkit.compliance.clauses import required_drop_height
from certkit.compliance.drop_conditions import lift_force_ratio
from certkit.compliance.measures import ZERO_WINDOW
from certkit.compliance.findings import add, gear_items, not_checked, shown
from certkit.compliance.quality_energy import (check_airplane_energy, check_available_energy,
                                               check_energy_bounds, check_implied_drop_weight)
from certkit.compliance.quality_travel import (check_asymmetry, check_bottoming,
                                               check_main_unit_weights, check_rising_with_height,
                                               check_static_stroke, check_tyre_curve)
from certkit.results import Comparison
from certkit.units import STANDARD_GRAVITY, ureg

#: Alternative units tried when a reported value disagrees: a match in another unit
#: of the same kind is reported as a probable unit slip (inch-pound and SI values typed in
#: the wrong unit are the commonest transcription error in a drop-test record).
ALTERNATIVE_UNITS = {"length": ["mm", "cm", "m", "in", "ft"],
                     "wing_loading": ["lbf/ft^2", "kgf/m^2", "N/m^2"]}
UNIT_SLIP_TOLERANCE = 0.05

#: 14 CFR 23.725(b)'s definition of W for each position, as the finding quotes it.
STATIC_WEIGHT_DEFINITION = {
    "main": "for a main unit, the static weight in the level attitude with the nose wheel clear",
    "nose": "for a nose unit, the static reaction with the airplane at maximum weight and the "
            "centre of gravity forward, under 1.0 g down and 0.33 g forward",
    "tail": "for a tail unit, the static weight in the tail-down attitude"}


# --------------------------------------------------------------------------- inputs
def check_static_weight_basis(assessment: Assessment) -> None:
    for gear in assessment.campaign.spec.gear_units:
        if gear.static_weight_basis == "assumed":
            add(assessment, "static-weight-assumed", "warning", None, gear.id,
                 f"{gear.id}: static weight {gear.static_weight.text} is assumed"
                 f"{' (' + gear.static_weight_note.strip() + ')' if gear.static_weight_note else ''}"
                 f"; 23.725(b) defines W {STATIC_WEIGHT_DEFINITION[gear.position]}; "
                 f"weigh it so and state the basis (static_weight_basis)")


def check_synthetic_data(assessment: Assessment) -> None:
    """Synthetic histories are never test evidence: in a certification campaign no value is
    computed from them; in a planning campaign every value is, as a prediction."""
    for run in assessment.campaign.spec.runs:
        if run.data is None or run.data.origin != "synthetic":
            continue
        if assessment.planning:
            add(assessment, "synthetic-data", "info", run.id, None,
                 f"run {run.id}: the time histories in {run.data.file} are synthetic "
                 f"(simulated, origin: synthetic); this is a planning campaign, so the values "
                 f"are computed from them as predictions for the planned drop, not as test "
                 f"evidence")
        else:
            add(assessment, "synthetic-data", "warning", run.id, None,
                 f"run {run.id}: the time histories in {run.data.file} are synthetic "
                 f"(simulated, origin: synthetic); they are not test evidence, so no "
                 f"compliance value is computed from them (the physics-model sections use them)")


def _test_dates(spec) -> list[tuple[str | None, object]]:
    """(run id, date) of every drop with measured data (synthetic histories were recorded by
    no instrument); a run without its own date stands for every test date of the document
    (run id None)."""
    dates = []
    for run in spec.runs:
        if run.data is None or run.data.origin == "synthetic":
            continue
        if run.date is not None:
            dates.append((run.id, run.date))
        else:
            dates.extend((None, day) for day in spec.document.test_dates)
    return sorted(set(dates), key=lambda item: (item[1], item[0] or ""))


def check_instrument_calibration(assessment: Assessment) -> None:
    """Every transducer channel had a valid calibration at every test date: calibrated on or
    before it and not due before it.  A channel without a calibration date, or a campaign
    listing no channels, cannot show that."""
    spec = assessment.campaign.spec
    dates = _test_dates(spec)
    if assessment.planning or not dates:
        return
    channels = spec.instrumentation.channels if spec.instrumentation else []
    if not channels:
        add(assessment, "instrument-calibration", "warning", None, None,
             "instrumentation.channels lists no transducer, so the calibration of the "
             "channels recorded is not shown")
        return

    def drop(run_id, day) -> str:
        return (f"drop {run_id} on {day.isoformat()}" if run_id
                else f"the test date {day.isoformat()}")

    for channel in channels:
        name = f"channel '{channel.name}'"
        if channel.calibration_date is None:
            add(assessment, "instrument-calibration", "warning", None, None,
                 f"{name}: no calibration date stated (instrumentation.channels"
                 f"[].calibration_date), so its calibration at the test dates is not shown")
            continue
        early = [(r, d) for r, d in dates if d < channel.calibration_date]
        late = [(r, d) for r, d in dates
                if channel.calibration_due is not None and d > channel.calibration_due]
        for run_id, day in early:
            add(assessment, "instrument-calibration", "error", run_id, None,
                 f"{name}: calibrated on {channel.calibration_date.isoformat()}, after "
                 f"{drop(run_id, day)}: no valid calibration at that drop")
        for run_id, day in late:
            add(assessment, "instrument-calibration", "error", run_id, None,
                 f"{name}: calibration due {channel.calibration_due.isoformat()}, before "
                 f"{drop(run_id, day)}: its calibration had expired")
        if channel.calibration_due is None:
            add(assessment, "instrument-calibration", "info", None, None,
                 f"{name}: calibrated on {channel.calibration_date.isoformat()}; no due date "
                 f"stated (calibration_due), so its validity at the test dates rests on the "
                 f"calibration date alone")


def check_data_waivers(assessment: Assessment) -> None:
    for run in assessment.runs:
        if run.series is None:
            continue
        for item in run.series.findings:
            add(assessment, f"data-{item.check.replace('_', '-')}", "warning", run.run.id, None,
                 f"{item.message} — accepted by waiver: {item.reason}")
        if run.series.layout is not None:
            add(assessment, "data-layout", "info", run.run.id, None,
                 f"{run.series.file} was read as {run.series.layout} (found from its header "
                 f"line and its numbers; not the comma-separated CSV of RFC 4180)")
        for gear in run.gears:
            if gear.measures is not None and gear.measures.touchdown_time is None:
                add(assessment, "touchdown-not-observed", "error", run.run.id, gear.gear_id,
                     f"run {run.run.id}, {gear.gear_id}: the load record starts with the tyre "
                     f"already loaded, so touchdown and the start of the energy integrals are "
                     f"not observed")


# --------------------------------------------------------------------------- reported values
def _compare(assessment: Assessment, run: str | None, gear: str | None, quantity: str, kind: str,
             unit: str, reported, recomputed: float | None, basis: str,
             relative_tolerance: float) -> Comparison:
    tolerance = difference = agrees = None
    if recomputed is not None:
        difference = reported.si - recomputed
        tolerance = max(reported.stated_resolution_si, relative_tolerance * abs(recomputed))
        agrees = abs(difference) <= tolerance
    item = Comparison(run, gear, quantity, kind, unit, reported.si, reported.text, recomputed,
                      difference, tolerance, agrees, basis)
    assessment.comparisons.append(item)
    return item


def _unit_slip(reported, recomputed: float, kind: str) -> str | None:
    """If the reported number matches in another unit of the same kind, say which."""
    magnitude_text = reported.text.split()[0]
    try:
        number = float(magnitude_text)
    except ValueError:
        return None
    for unit in ALTERNATIVE_UNITS.get(kind, []):
        si = ureg.Quantity(number, unit).to("m" if kind == "length" else "Pa").magnitude
        if abs(si / recomputed - 1) <= UNIT_SLIP_TOLERANCE and abs(si - reported.si) > 1e-12:
            return unit
    return None


def check_reported_values(assessment: Assessment) -> None:
    spec = assessment.campaign.spec
    tolerance = spec.audit.reported_tolerance.si
    design = assessment.design
    claims = spec.reported
    if claims is not None and claims.wing_loading is not None:
        item = _compare(assessment, None, None, "wing loading W/S", "wing_loading", "Pa",
                        claims.wing_loading, design["W/S"].value,
                        "W/S from aircraft.maximum_weight and aircraft.wing_area", tolerance)
        if not item.agrees:
            add(assessment, "reported-wing-loading", "warning", None, None,
                 f"stated wing loading {claims.wing_loading.text} disagrees with W/S = "
                 f"{shown(assessment, item.recomputed, 'wing_loading')} computed from "
                 f"W = {spec.aircraft.maximum_weight.text} and S = {spec.aircraft.wing_area.text} "
                 f"({item.reported / item.recomputed - 1:+.1%}); the required drop height is "
                 f"computed from W and S")
    if claims is not None and claims.required_drop_height is not None and assessment.basis:
        basis = assessment.basis[0]
        h_req = basis.values["h_req"].value
        item = _compare(assessment, None, None, "required drop height", "length", "m",
                        claims.required_drop_height, h_req,
                        f"h_req of {basis.rules.id} from W/S", tolerance)
        if not item.agrees:
            message = (f"stated required drop height {claims.required_drop_height.text} disagrees "
                       f"with h_req = {shown(assessment, h_req, 'length')} ({basis.rules.id})")
            slip = _unit_slip(claims.required_drop_height, h_req, "length")
            if slip:
                number = claims.required_drop_height.text.split()[0]
                message += (f"; read as {number} {slip} it is within "
                            f"{UNIT_SLIP_TOLERANCE:.0%}: probable unit slip")
            if claims.wing_loading is not None:
                rules = basis.rules
                units = rules.parameters["drop_height_formula_units"]
                from_stated = required_drop_height(
                    claims.wing_loading.si, rules.number("drop_height_coefficient"),
                    units["wing_loading"], units["height"], rules.length("drop_height_minimum"),
                    rules.length("drop_height_maximum")).required
                message += (f"; the formula applied to the stated wing loading "
                            f"{claims.wing_loading.text} gives "
                            f"{shown(assessment, from_stated, 'length')}")
            add(assessment, "reported-drop-height", "warning", None, None, message)

    for run in assessment.runs:
        reported = run.run.reported
        if reported is None:
            continue
        if reported.impact_load_factor is not None and run.get("n_combined") is not None:
            basis_text = ("ΣF_peak of the main units/(m_drop·g) (certkit G2), from "
                          + ("the time series" if run.series else "the reported peak loads"))
            item = _compare(assessment, run.run.id, None, "impact load factor", "ratio", "1",
                            reported.impact_load_factor, run.get("n_combined"), basis_text, 0.0)
            if not item.agrees:
                add(assessment, "reported-impact-load-factor", "warning", run.run.id, None,
                     f"run {run.run.id}: stated impact load factor "
                     f"{reported.impact_load_factor.text} is not ΣF_peak/(m_drop·g) = "
                     f"{item.recomputed:.4g}")
        if run.series is None:
            continue
        for gear in run.gears:
            claimed = reported.gears.get(gear.gear_id)
            if claimed is None:
                continue
            for name, key, kind, unit in (
                    ("peak_vertical_load", "F_peak", "force", "N"),
                    ("strut_stroke", "d_s", "length", "m"),
                    ("tyre_deflection", "d_t", "length", "m"),
                    ("strut_energy", "E_s", "energy", "J"),
                    ("tyre_energy", "E_t", "energy", "J")):
                value = getattr(claimed, name)
                if value is None:
                    continue
                item = _compare(assessment, run.run.id, gear.gear_id, name.replace("_", " "),
                                kind, unit, value, gear.get(key),
                                f"recomputed from {run.series.file}", tolerance)
                if item.agrees is False:
                    relative = (f" by {item.difference / item.recomputed:+.1%}"
                                if item.recomputed else "")
                    add(assessment, f"reported-{name.replace('_', '-')}", "warning", run.run.id,
                         gear.gear_id,
                         f"run {run.run.id}, {gear.gear_id}: reported {name.replace('_', ' ')} "
                         f"{value.text} differs from the recomputed "
                         f"{shown(assessment, item.recomputed, kind)}{relative}")


def check_acceleration_against_load(assessment: Assessment) -> None:
    """n_j from the drop-mass accelerometer agrees with the platform loads.

    When every unit that carries the drop mass is measured (a single-unit rig, or all the
    aircraft's units), the peak of ΣF + L_dev·W_drop over W_drop is the drop-mass load
    factor (unsprung-mass inertia neglected, hence a tolerance).
    """
    tolerance = assessment.campaign.spec.audit.load_consistency_tolerance.si
    all_units = set(assessment.campaign.gear_units)
    for run in assessment.runs:
        n_j = run.get("n_j")
        if run.series is not None and n_j is None:
            not_checked(assessment, "acceleration-vs-load", f"run {run.run.id}",
                        "needs the drop-mass acceleration channel "
                        "(runs[].data.drop_mass_acceleration)")
        if n_j is None or run.series is None:
            continue
        measured = set(run.run.gear_units)
        if len(measured) > 1 and measured != all_units:
            continue
        total = sum(run.series.gears[g].load for g in run.run.gear_units if g in run.series.gears)
        drop_weight = run.run.drop_mass.si * STANDARD_GRAVITY
        lift = lift_force_ratio(run.run)
        from_load = float(total.max()) / drop_weight + lift
        if abs(n_j / from_load - 1) > tolerance:
            add(assessment, "acceleration-vs-load", "warning", run.run.id, None,
                 f"run {run.run.id}: the drop-mass accelerometer gives n_j = {n_j:.4g}, the "
                 f"platform load gives max ΣF_V/W_drop + L_dev = {from_load:.4g} "
                 f"({n_j / from_load - 1:+.1%}, tolerance ±{tolerance:.0%}): check the "
                 f"accelerometer's reference, sign and calibration, or the drop mass",
                 n_j=n_j, from_load=from_load)


def check_travel_zero_at_touchdown(assessment: Assessment) -> None:
    """Stroke and tyre deflection read zero just before touchdown (else an offset is missing):
    their median over the :data:`~certkit.compliance.measures.ZERO_WINDOW` before the touchdown sample."""
    tolerance = assessment.campaign.spec.audit.zero_travel_tolerance.si
    for run, gear in gear_items(assessment):
        measures = gear.measures
        if measures is None or measures.touchdown_time is None:
            continue
        for name, value in (("strut stroke", measures.stroke_at_touchdown),
                            ("tyre deflection", measures.tyre_at_touchdown)):
            if value is not None and abs(value) > tolerance:
                add(assessment, f"{name.split()[0]}-not-zero-at-touchdown", "warning",
                     run.run.id, gear.gear_id,
                     f"run {run.run.id}, {gear.gear_id}: {name} reads "
                     f"{shown(assessment, value, 'length')} just before touchdown (median "
                     f"over {shown(assessment, ZERO_WINDOW, 'time')}), not zero; the "
                     f"maxima and energies are measured from zero, so set the channel's offset",
                     value=value)


def check_energy_method_lift(assessment: Assessment) -> None:
    """The energy method assumes a lift L acting through d; say when the drop simulated another."""
    for basis in assessment.basis:
        if "energy_method_wing_lift_ratio" not in basis.rules.parameters:
            continue
        assumed = basis.rules.number("energy_method_wing_lift_ratio")
        for run, gear in gear_items(assessment):
            n_energy = gear.get(f"n_energy[{basis.rules.id}]")
            if n_energy is None or run.run.test_type != "limit":
                continue
            simulated = run.get("L")
            if abs(simulated - assumed) > 1e-3:
                measured = gear.get("F/W")
                message = (f"run {run.run.id}, {gear.gear_id}: the {basis.rules.id} energy-method "
                           f"load factor n = {n_energy:.4g} assumes L = {assumed:.4g} acting "
                           f"through d, but the drop simulated L = {simulated:g}, so d is not "
                           f"the travel the method models")
                if measured is not None:
                    message += f"; the measured ground-reaction factor F_peak/W is {measured:.4g}"
                add(assessment, "energy-method-lift", "warning", run.run.id, gear.gear_id, message)


#: Every check, in the order the report lists their findings (docs/audit-checklist.md
#: states each relation, its threshold and its source).
CHECKS = (check_static_weight_basis, check_main_unit_weights, check_synthetic_data,
          check_instrument_calibration, check_data_waivers,
          check_energy_bounds, check_available_energy, check_airplane_energy,
          check_implied_drop_weight, check_rising_with_height, check_bottoming,
          check_static_stroke, check_tyre_curve, check_asymmetry, check_reported_values,
          check_acceleration_against_load, check_travel_zero_at_touchdown,
          check_energy_method_lift)


def audit(assessment: Assessment) -> None:
    """Run every data-quality check, appending findings and comparisons to ``assessment``."""
    for check in CHECKS:
        check(assessment)
