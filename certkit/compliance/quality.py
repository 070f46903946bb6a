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
from certkit.display import number, with_unit
from certkit.results import Comparison, Finding
from certkit.units import STANDARD_GRAVITY, ureg

#: Alternative units tried when a reported value disagrees: a match in another unit
#: of the same kind is reported as a probable unit slip (inch-pound and SI values typed in
#: the wrong unit are the commonest transcription error in a drop-test record).
ALTERNATIVE_UNITS = {"length": ["mm", "cm", "m", "in", "ft"],
                     "wing_loading": ["lbf/ft^2", "kgf/m^2", "N/m^2"]}
UNIT_SLIP_TOLERANCE = 0.05
#: Tyre efficiency ceiling: a tyre whose force rises linearly or faster with deflection
#: absorbs at most half the rectangle F_peak·δ_max (for F = k·δⁿ, ∫F dδ = F_peak·δ_max/(n + 1)
#: with n ≥ 1).
TYRE_EFFICIENCY_CEILING = 0.5


def _display(assessment: Assessment, value: float, kind: str) -> str:
    """A value in the campaign's display units, as every finding states it."""
    return with_unit(value, kind, assessment.campaign.spec.report.units)


def _add(assessment: Assessment, check: str, severity: str, run: str | None, gear: str | None,
         message: str, **values) -> None:
    parts = ["QA", check] + [part for part in (run, gear) if part]
    identifier, taken = "/".join(parts), {f.id for f in assessment.findings}
    # the same check can find twice in one place (two channels of a run): number the
    # repeats in the order found, so every id stays unique and stable
    repeat = 2
    while identifier in taken:
        identifier = "/".join(parts) + f"#{repeat}"
        repeat += 1
    assessment.findings.append(Finding(identifier, check, severity, run, gear, message, values))


def _gear_items(assessment: Assessment):
    for run in assessment.runs:
        for gear in run.gears:
            yield run, gear


# --------------------------------------------------------------------------- energy consistency
def check_energy_bounds(assessment: Assessment) -> None:
    """E ≤ F_peak·δ_max for strut and tyre (η ≤ 1), η > 0, tyre η ≤ 0.5."""
    for run, gear in _gear_items(assessment):
        for element, name in (("s", "strut"), ("t", "tyre")):
            eta = gear.get(f"eta_{element}")
            if eta is None:
                continue
            energy = gear.get(f"E_{element}")
            bound = gear.get("F_peak") * gear.get(f"d_{element}")
            where = f"run {run.run.id}, {gear.gear_id}"
            if eta > 1:
                _add(assessment, f"energy-exceeds-bound-{name}", "error", run.run.id, gear.gear_id,
                     f"{where}: {name} energy {_display(assessment, energy, 'energy')} exceeds "
                     f"F_peak·d = {_display(assessment, bound, 'energy')} (η = {eta:.4g} > 1): "
                     f"impossible for any {name}; "
                     f"check the energy integral, the load or the travel",
                     eta=eta, energy=energy, bound=bound)
            elif eta <= 0:
                _add(assessment, f"efficiency-not-positive-{name}", "error", run.run.id,
                     gear.gear_id, f"{where}: {name} efficiency η = {eta:.4g} is not positive",
                     eta=eta)
            elif element == "t" and eta > TYRE_EFFICIENCY_CEILING:
                _add(assessment, "tyre-efficiency-above-half", "warning", run.run.id, gear.gear_id,
                     f"{where}: tyre efficiency η_t = {number(eta)} exceeds "
                     f"{TYRE_EFFICIENCY_CEILING}, "
                     f"the ceiling for a tyre whose force rises at least linearly with deflection",
                     eta=eta)


def check_available_energy(assessment: Assessment) -> None:
    """The absorbed energy cannot exceed what the drop supplied (certkit E5 against E3),
    within the stated tolerance.

    From time histories: E_d = E_s(t_d) + E_t(t_d) ≤ E_avail = W_drop·(h + d) − L_dev·W_drop·d.
    By the instant t_d of maximum total travel the upper mass m1 is at rest, so for the
    two-mass gear on a rigid platform (unsprung mass m2) E_d = W_drop·h + m1·g·d +
    m2·g·δ(t_d) − ½·m2·δ̇(t_d)² ≤ W_drop·(h + d), less the lift device's work.

    From reported values E_d is not known: E_s and E_t each run to their own maximum and the
    first element to peak gives energy back before the other peaks, so their sum can exceed
    E_avail on a valid drop.  What holds for any drop is that each element alone absorbs no
    more than the drop supplied by maximum travel, E_s ≤ E_avail and E_t ≤ E_avail: each is
    checked on its own.
    """
    tolerance = assessment.campaign.spec.audit.energy_tolerance.si
    for run, gear in _gear_items(assessment):
        available = gear.get("E_avail")
        if available is None:
            continue
        where = f"run {run.run.id}, {gear.gear_id}"
        absorbed = gear.get("E_d")
        severity, assumed = "error", ""
        if absorbed is not None:
            candidates = [("E_d", "the work strut and tyre absorbed up to the instant of "
                                  "maximum total travel", absorbed)]
            if "θ" in gear.assumptions:
                # E_d and E_avail both move with θ: a finding that rests on an assumed input
                # is no error, and says what to declare
                severity = "warning"
                assumed = f"; computed with {gear.assumptions['θ']}"
        elif gear.measures is not None:
            _add(assessment, "energy-balance-not-checked", "warning", run.run.id, gear.gear_id,
                 f"{where}: the absorbed energy is not checked against the energy available "
                 f"(certkit E5 against E3): E_d {gear.values['E_d'].note}; declare it so that "
                 f"the check runs",
                 reason=gear.values["E_d"].note)
            continue
        else:
            candidates = [(key, f"the {name} energy alone, as reported", gear.get(key))
                          for key, name in (("E_s", "strut"), ("E_t", "tyre"))
                          if gear.get(key) is not None]
        for symbol, what, energy in candidates:
            if energy > available * (1 + tolerance):
                _add(assessment, "energy-exceeds-available", severity, run.run.id, gear.gear_id,
                     f"{where}: {symbol} = {_display(assessment, energy, 'energy')} ({what}; "
                     f"certkit E5) exceeds the energy available W_drop·(h + d) − L_dev·W_drop·d "
                     f"= {_display(assessment, available, 'energy')} by "
                     f"{energy / available - 1:.1%} (tolerance {tolerance:.0%}){assumed}",
                     absorbed=energy, available=available)


def check_implied_drop_weight(assessment: Assessment) -> None:
    """The drop weight implied by the absorbed energy is the declared one and is constant."""
    spread = assessment.campaign.spec.audit.drop_mass_spread.si
    implied = [(run, gear, gear.get("W_implied")) for run, gear in _gear_items(assessment)
               if gear.get("W_implied") is not None]
    for run, gear, weight in implied:
        declared = gear.get("W_drop")
        if abs(weight / declared - 1) > spread:
            _add(assessment, "implied-drop-weight", "warning", run.run.id, gear.gear_id,
                 f"run {run.run.id}, {gear.gear_id}: the absorbed energy implies a drop weight of "
                 f"{_display(assessment, weight, 'force')}, {weight / declared - 1:+.1%} from the "
                 f"{_display(assessment, declared, 'force')} dropped (tolerance ±{spread:.0%})",
                 implied=weight, declared=declared)
    # across runs, each implied weight is compared with the weight that run dropped: a
    # reserve drop made lighter on purpose (23.727(b)) is not a spread
    by_gear: dict[str, list] = {}
    for run, gear, weight in implied:
        by_gear.setdefault(gear.gear_id, []).append((run.run.id, weight, gear.get("W_drop")))
    for gear_id, items in by_gear.items():
        if len(items) < 2:
            continue
        ratios = [w / dropped for _, w, dropped in items]
        low, high = min(ratios), max(ratios)
        if high + low > 0 and (high - low) / (0.5 * (high + low)) > spread:
            listing = ", ".join(f"{run_id}: {_display(assessment, w, 'force')} of "
                                f"{_display(assessment, dropped, 'force')} dropped"
                                for run_id, w, dropped in items)
            _add(assessment, "implied-drop-weight-spread", "warning", None, gear_id,
                 f"{gear_id}: the drop weight implied by the absorbed energy, as a share of the "
                 f"weight dropped, varies across runs by {(high - low) / (0.5 * (high + low)):.0%}"
                 f" ({listing}); the same measuring chain should imply the weight dropped in "
                 f"every run", values=[w for _, w, _ in items])


# --------------------------------------------------------------------------- travel
def check_stroke_trend(assessment: Assessment) -> None:
    """Strut stroke rises with drop height (else suspect bottoming or a sensor)."""
    by_gear: dict[str, list] = {}
    for run, gear in _gear_items(assessment):
        if gear.get("d_s") is not None:
            by_gear.setdefault(gear.gear_id, []).append((run.get("h"), gear.get("d_s"), run.run.id))
    for gear_id, items in by_gear.items():
        items.sort()
        for (h0, s0, r0), (h1, s1, r1) in zip(items, items[1:]):
            if h1 > h0 and s1 <= s0:
                _add(assessment, "stroke-not-rising", "warning", r1, gear_id,
                     f"{gear_id}: strut stroke {_display(assessment, s1, 'length')} in run {r1} "
                     f"(h = {_display(assessment, h1, 'length')}) is not larger than "
                     f"{_display(assessment, s0, 'length')} in run {r0} "
                     f"(h = {_display(assessment, h0, 'length')}): suspect bottoming, a "
                     f"servicing change or a sensor fault", stroke=[s0, s1], height=[h0, h1])


def check_bottoming(assessment: Assessment) -> None:
    """Maximum stroke within the stated margin of the design stroke."""
    margin = assessment.campaign.spec.audit.bottoming_margin.si
    for run, gear in _gear_items(assessment):
        unit = assessment.campaign.gear_units[gear.gear_id]
        d_s = gear.get("d_s")
        if d_s is None:
            continue
        if d_s >= (1 - margin) * unit.design_stroke.si:
            _add(assessment, "near-bottoming", "warning", run.run.id, gear.gear_id,
                 f"run {run.run.id}, {gear.gear_id}: stroke {_display(assessment, d_s, 'length')} "
                 f"is within {margin:.0%} of the design stroke {unit.design_stroke.text}",
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
                _add(assessment, f"asymmetry-{key.replace('_', '-').lower()}", "warning",
                     run.run.id, None,
                     f"run {run.run.id}: {label} differs by {difference:.1%} between "
                     f"{a.gear_id} ({_display(assessment, x, kind)}) and {b.gear_id} "
                     f"({_display(assessment, y, kind)}); threshold {threshold:.0%}",
                     difference=difference)


# --------------------------------------------------------------------------- inputs
def check_static_weight_basis(assessment: Assessment) -> None:
    for gear in assessment.campaign.spec.gear_units:
        if gear.static_weight_basis == "assumed":
            _add(assessment, "static-weight-assumed", "warning", None, gear.id,
                 f"{gear.id}: static weight {gear.static_weight.text} is assumed"
                 f"{' (' + gear.static_weight_note.strip() + ')' if gear.static_weight_note else ''}"
                 f"; 23.725(b) defines W for a main unit as the static weight in the level "
                 f"attitude with the nose wheel clear")


def check_synthetic_data(assessment: Assessment) -> None:
    """Synthetic histories are never test evidence: in a certification campaign no value is
    computed from them; in a planning campaign every value is, as a prediction."""
    for run in assessment.campaign.spec.runs:
        if run.data is None or run.data.origin != "synthetic":
            continue
        if assessment.planning:
            _add(assessment, "synthetic-data", "info", run.id, None,
                 f"run {run.id}: the time histories in {run.data.file} are synthetic "
                 f"(simulated, origin: synthetic); this is a planning campaign, so the values "
                 f"are computed from them as predictions for the planned drop, not as test "
                 f"evidence")
        else:
            _add(assessment, "synthetic-data", "warning", run.id, None,
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
        _add(assessment, "instrument-calibration", "warning", None, None,
             "instrumentation.channels lists no transducer, so the calibration of the "
             "channels recorded is not shown")
        return

    def drop(run_id, day) -> str:
        return (f"drop {run_id} on {day.isoformat()}" if run_id
                else f"the test date {day.isoformat()}")

    for channel in channels:
        name = f"channel '{channel.name}'"
        if channel.calibration_date is None:
            _add(assessment, "instrument-calibration", "warning", None, None,
                 f"{name}: no calibration date stated (instrumentation.channels"
                 f"[].calibration_date), so its calibration at the test dates is not shown")
            continue
        early = [(r, d) for r, d in dates if d < channel.calibration_date]
        late = [(r, d) for r, d in dates
                if channel.calibration_due is not None and d > channel.calibration_due]
        for run_id, day in early:
            _add(assessment, "instrument-calibration", "error", run_id, None,
                 f"{name}: calibrated on {channel.calibration_date.isoformat()}, after "
                 f"{drop(run_id, day)}: no valid calibration at that drop")
        for run_id, day in late:
            _add(assessment, "instrument-calibration", "error", run_id, None,
                 f"{name}: calibration due {channel.calibration_due.isoformat()}, before "
                 f"{drop(run_id, day)}: its calibration had expired")
        if channel.calibration_due is None:
            _add(assessment, "instrument-calibration", "info", None, None,
                 f"{name}: calibrated on {channel.calibration_date.isoformat()}; no due date "
                 f"stated (calibration_due), so its validity at the test dates rests on the "
                 f"calibration date alone")


def check_data_waivers(assessment: Assessment) -> None:
    for run in assessment.runs:
        if run.series is None:
            continue
        for item in run.series.findings:
            _add(assessment, f"data-{item.check.replace('_', '-')}", "warning", run.run.id, None,
                 f"{item.message} — accepted by waiver: {item.reason}")
        if run.series.layout is not None:
            _add(assessment, "data-layout", "info", run.run.id, None,
                 f"{run.series.file} was read as {run.series.layout} (found from its header "
                 f"line and its numbers; not the comma-separated CSV of RFC 4180)")
        for gear in run.gears:
            if gear.measures is not None and gear.measures.touchdown_time is None:
                _add(assessment, "touchdown-not-observed", "error", run.run.id, gear.gear_id,
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
            _add(assessment, "reported-wing-loading", "warning", None, None,
                 f"stated wing loading {claims.wing_loading.text} disagrees with W/S = "
                 f"{_display(assessment, item.recomputed, 'wing_loading')} computed from "
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
                       f"with h_req = {_display(assessment, h_req, 'length')} ({basis.rules.id})")
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
                            f"{_display(assessment, from_stated, 'length')}")
            _add(assessment, "reported-drop-height", "warning", None, None, message)

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
                _add(assessment, "reported-impact-load-factor", "warning", run.run.id, None,
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
                    _add(assessment, f"reported-{name.replace('_', '-')}", "warning", run.run.id,
                         gear.gear_id,
                         f"run {run.run.id}, {gear.gear_id}: reported {name.replace('_', ' ')} "
                         f"{value.text} differs from the recomputed "
                         f"{_display(assessment, item.recomputed, kind)}{relative}")


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
            _add(assessment, "acceleration-vs-load", "warning", run.run.id, None,
                 f"run {run.run.id}: the drop-mass accelerometer gives n_j = {n_j:.4g}, the "
                 f"platform load gives max ΣF_V/W_drop + L_dev = {from_load:.4g} "
                 f"({n_j / from_load - 1:+.1%}, tolerance ±{tolerance:.0%}): check the "
                 f"accelerometer's reference, sign and calibration, or the drop mass",
                 n_j=n_j, from_load=from_load)


def check_travel_zero_at_touchdown(assessment: Assessment) -> None:
    """Stroke and tyre deflection read zero just before touchdown (else an offset is missing):
    their median over the :data:`~certkit.compliance.measures.ZERO_WINDOW` before the touchdown sample."""
    tolerance = assessment.campaign.spec.audit.zero_travel_tolerance.si
    for run, gear in _gear_items(assessment):
        measures = gear.measures
        if measures is None or measures.touchdown_time is None:
            continue
        for name, value in (("strut stroke", measures.stroke_at_touchdown),
                            ("tyre deflection", measures.tyre_at_touchdown)):
            if value is not None and abs(value) > tolerance:
                _add(assessment, f"{name.split()[0]}-not-zero-at-touchdown", "warning",
                     run.run.id, gear.gear_id,
                     f"run {run.run.id}, {gear.gear_id}: {name} reads "
                     f"{_display(assessment, value, 'length')} just before touchdown (median "
                     f"over {_display(assessment, ZERO_WINDOW, 'time')}), not zero; the "
                     f"maxima and energies are measured from zero, so set the channel's offset",
                     value=value)


def check_energy_method_lift(assessment: Assessment) -> None:
    """The energy method assumes a lift L acting through d; say when the drop simulated another."""
    for basis in assessment.basis:
        if "energy_method_wing_lift_ratio" not in basis.rules.parameters:
            continue
        assumed = basis.rules.number("energy_method_wing_lift_ratio")
        for run, gear in _gear_items(assessment):
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
                _add(assessment, "energy-method-lift", "warning", run.run.id, gear.gear_id, message)


CHECKS = (check_static_weight_basis, check_synthetic_data, check_instrument_calibration,
          check_data_waivers,
          check_energy_bounds,
          check_available_energy, check_implied_drop_weight, check_stroke_trend, check_bottoming,
          check_asymmetry, check_reported_values, check_acceleration_against_load,
          check_travel_zero_at_touchdown, check_energy_method_lift)


def audit(assessment: Assessment) -> None:
    """Run every data-quality check, appending findings and comparisons to ``assessment``."""
    for check in CHECKS:
        check(assessment)
