"""The report's view: plain data for the templates, every string already formatted in the
campaign's display units; the templates only lay it out.

matplotlib is imported only where a run's figures are drawn (about 0.26 s of start-up,
``python -X importtime``; a campaign of reported values draws none).
"""

from __future__ import annotations

from markupsafe import Markup

from certkit.compliance.assessment import Assessment
from certkit.compliance.criteria import at_least
from certkit.compliance.equations import EQUATIONS, GRAVITY_NOTE
from certkit.display import DISPLAY_RULE, display, margin, number, pretty, typed, with_unit
from certkit.evidence.gap_view import gap_view
from certkit.evidence.limits import assumed_mark, cover_reasons, results_assumptions
from certkit.evidence.model_view import identification_view, model_view, origins
from certkit.evidence.sections import (AircraftSection, CampaignSection, DocumentSection,
                                       InstrumentationSection, ReportView)
from certkit.evidence.uncertainty_view import uncertainty_view, verdict_cells
from certkit.physics.drops import drop_heights
from certkit.results import PASS, Value
from certkit.version import VERSION


# --------------------------------------------------------------------------- formatting
def _value_row(value: Value, units) -> dict:
    number, unit = typed(value.typed, value.value, value.kind, units)
    return {"label": value.label, "symbol": value.symbol, "value": number, "unit": unit,
            "source": value.source, "formula": value.formula,
            "inputs": "; ".join(f"{k}: {v}" for k, v in value.inputs.items()),
            "note": value.note or ""}


# --------------------------------------------------------------------------- view model
def build_view(assessment: Assessment, record: dict, model=None) -> ReportView:
    """Plain data for the templates: every string already formatted.

    ``model`` is the :class:`~certkit.evidence.model_evidence.ModelEvidence` of the governing-equation
    section (None: the section says the model was not run)."""
    campaign = assessment.campaign
    spec = campaign.spec
    units = spec.report.units
    doc = spec.document

    basis = _basis_view(assessment, units)

    gear_rows = _gear_unit_rows(assessment, units)

    instrumentation = _instrumentation(assessment, units)

    matrix = _matrix_rows(assessment, units)

    completeness = _completeness_rows(assessment, units)

    results_rows = _results_rows(assessment, units)

    results_units = {kind: pretty(getattr(units, kind))
                     for kind in ("length", "force", "energy")}
    load_factors, load_factor_statement = _load_factor_view(assessment)

    runs = _run_views(assessment, units)

    verdicts = _verdict_rows(assessment, units)

    findings = [{"id": f.id, "severity": f.severity, "message": f.message}
                for f in sorted(assessment.findings,
                                key=lambda f: ("error", "warning", "info").index(f.severity))]
    comparisons = _comparison_rows(assessment, units)

    counts = assessment.counts()
    finding_counts = assessment.finding_counts()
    appendices = model is not None and model.calibration is not None
    left_out = "" if appendices else (
        NO_MODEL_LINE if model is None else f"No drop-model appendices: {model.note}")
    signatories = [{"role": s.role, "name": s.name, "organisation": s.organisation or "",
                    "date": s.date.isoformat() if s.date else ""} for s in doc.signatories]
    # the sign-off blocks a reviewer expects are there even when the spec names nobody
    signatories += [{"role": role, "name": NOT_STATED, "organisation": "", "date": ""}
                    for role in SIGN_OFF if role not in {s.role for s in doc.signatories}]
    return ReportView(**{
        "lang": "en",
        "title": f"{doc.report_number} rev {doc.revision}: {spec.campaign.title}",
        "campaign": CampaignSection(spec.campaign.id, spec.campaign.title,
                                    (spec.campaign.description or "").strip()),
        "document": DocumentSection(**{"report_number": doc.report_number, "revision": doc.revision,
                     "date": doc.date.isoformat(), "applicant": doc.applicant,
                     "facility": doc.facility,
                     "test_dates": ", ".join(d.isoformat() for d in doc.test_dates),
                     "checklist": doc.compliance_checklist_item or "—",
                     "signatories": signatories,
                     "revisions": [{"revision": r.revision, "date": r.date.isoformat(),
                                    "description": r.description} for r in doc.revisions]}),
        "created": f"{doc.date.isoformat()}T00:00:00Z",
        "outcome": assessment.outcome,
        "outcome_css": ("planning" if assessment.planning
                        else assessment.outcome.replace(" ", "-").lower()),
        "planning": assessment.planning,
        "headings": _headings(assessment.planning, appendices),
        "contents": list(_headings(assessment.planning, appendices).items()),
        "cover_reasons": cover_reasons(assessment),
        "cover_reasons_title": ("Why not every predicted verdict is PASS" if assessment.planning
                                else "Why not every criterion passes"),
        "model_left_out": left_out,
        "conclusions": _conclusions(assessment, _setup_rows(spec), gear_rows, signatories),
        "references": _references(assessment),
        "outcome_reasons": assessment.outcome_reasons(),
        "counts": counts, "finding_counts": finding_counts,
        "aircraft": AircraftSection(spec.aircraft.model, (spec.aircraft.notes or "").strip()),
        "design": [_value_row(v, units) for v in assessment.design.values()],
        "basis": basis, "any_to_confirm": any(b["to_confirm"] for b in basis),
        "gear_units": gear_rows, "setup": _setup_rows(spec), "instrumentation": instrumentation,
        "matrix": matrix, "completeness": completeness,
        "results_rows": results_rows, "results_units": results_units,
        "results_assumptions": results_assumptions(assessment),
        "load_factors": load_factors, "load_factor_statement": load_factor_statement,
        # a column only where some run has something in it (a single-gear rig has no ΣF_peak)
        "load_factor_columns": {column: any(r[column] not in ("", "—") for r in load_factors)
                                for column in ("stated", "combined", "n_j", "n", "n_energy")},
        "runs": runs, "verdicts": verdicts, "findings": findings, "comparisons": comparisons,
        "uncertainty": uncertainty_view(assessment, units),
        "not_checked": [{"check": u.check, "where": u.where or "the campaign",
                         "reason": u.reason} for u in assessment.unchecked],
        "equations": sorted(EQUATIONS.items()), "gravity_note": GRAVITY_NOTE,
        "display_rule": DISPLAY_RULE,
        "assumptions": [a.strip() for a in spec.assumptions],
        "audit": _audit_settings(spec.audit, units),
        "provenance": record, "version": VERSION,
        "model": model_view(model, units, spec.reference_results, origins(spec),
                             spec.model.effects, _results_by_run(assessment))
        if appendices else None,
        "identification": identification_view(model, spec.model.identification, units,
                                              spec.reference_results, origins(spec),
                                              drop_heights(campaign)) if appendices else None,
        "gap": gap_view(model, campaign, units) if appendices else None,
    })


#: The one line a report made without the drop model spends on what it left out.
NO_MODEL_LINE = ("The drop model's appendices (calibration, identification, gap diagnosis; "
                 "not compliance evidence) were not made for this report (certkit report "
                 "--no-model).")


def _results_by_run(assessment: Assessment) -> dict:
    """(run, gear) -> the values the results table shows for it and their basis, in SI:
    what a model figure marks when the run's verdicts rest on other values than its trace."""
    shown = {}
    for run in assessment.runs:
        for gear in run.gears:
            shown[(run.run.id, gear.gear_id)] = {
                "basis": gear.basis, "F_peak": gear.get("F_peak"), "d_s": gear.get("d_s"),
                "d_t": gear.get("d_t")}
    return shown


def _basis_view(assessment: Assessment, units) -> list[dict]:
    basis = []
    for item in assessment.basis:
        rules = item.rules
        criteria = []
        for criterion in rules.criteria:
            applicable = not criterion.applies_if or getattr(item.entry, criterion.applies_if)
            criteria.append({"id": criterion.id, "clause": criterion.clause,
                             "title": criterion.title, "formula": criterion.formula,
                             "applicable": "yes" if applicable else
                             "no (strength not shown dynamically)"})
        basis.append({
            "id": rules.id, "title": rules.title, "edition": rules.edition,
            "stated_edition": item.entry.edition or "not stated", "to_confirm": rules.to_confirm,
            "status_note": rules.status_note, "criteria": criteria,
            "derived": [_value_row(v, units) for v in item.values.values()]})
    return basis



NOT_STATED = "not stated"
#: The report's body in order, (anchor, title): the compliance evidence a reviewer signs
#: against; one home for the headings and the table of contents.
SECTIONS = (
    ("basis", "Certification basis"),
    ("design", "Design inputs and derived quantities"),
    ("article", "Test article, configuration and instrumentation"),
    ("matrix", "Test matrix"),
    ("results", "Results per run"),
    ("compliance", "Compliance findings"),
    ("uncertainty", "Measurement uncertainty and decision rule"),
    ("data-quality", "Data-quality findings"),
    ("run-details", "Run details and derivations"),
    ("methods", "Methods: certkit equations"),
    ("conclusions", "Conclusions"),
    ("provenance", "Provenance"),
    ("references", "References"))
#: The appendices on the drop model, (anchor, title), lettered after the body: research on
#: the drops, not compliance evidence.
APPENDICES = (
    ("model", "Drop-model calibration"),
    ("identification", "Identification: Hammerstein, Wiener and NARX models"),
    ("gap", "Sim-to-real gap: where the model disagrees, which effect explains it, how far "
            "it shrinks"))
PLANNING_VERDICTS = "Predicted verdicts (planning on synthetic data: not compliance findings)"


def section_number(anchor: str) -> int:
    """The number of a body section (its place in :data:`SECTIONS`)."""
    return [name for name, _ in SECTIONS].index(anchor) + 1


def _headings(planning: bool, appendices: bool = True) -> dict[str, str]:
    """Anchor -> numbered heading of every section of the body, then (``appendices``)
    lettered headings of the appendices."""
    planned = {"compliance": PLANNING_VERDICTS} if planning else {}
    headings = {anchor: f"{number}. {planned.get(anchor, title)}"
                for number, (anchor, title) in enumerate(SECTIONS, start=1)}
    if appendices:
        headings.update({anchor: f"Appendix {letter}. {title}" for letter, (anchor, title)
                         in zip("ABCDEFGH", APPENDICES)})
    return headings


#: Sign-off blocks every report carries (document.signatories[].role).
SIGN_OFF = ("prepared", "checked", "approved", "witnessed")


def _stated(value) -> str:
    """A spec value as typed, or :data:`NOT_STATED`."""
    if value is None:
        return NOT_STATED
    return getattr(value, "text", value)


def _article_rows(article) -> list[tuple[str, str]]:
    """The test article's identity and servicing (gear_units[].article), each row present
    whether stated or not: a reviewer sees what is missing."""
    return [(label, _stated(getattr(article, name) if article else None)) for name, label in (
        ("part_number", "Test article part number"),
        ("serial_number", "Test article serial number"),
        ("drawing", "Drawing and revision"),
        ("conformity_record", "Conformity record"),
        ("tyre_part_number", "Tyre part number"), ("tyre_ply_rating", "Tyre ply rating"),
        ("oil_volume", "Oil volume as serviced"),
        ("gas_pressure", "Gas pressure as serviced"),
        ("gas_temperature", "Gas charged at (temperature)"))]


def _setup_rows(spec) -> list[tuple[str, str]]:
    """How the drops were set up and conducted (the spec's ``setup``), each row present
    whether stated or not."""
    setup = spec.setup
    return [(label, _stated(getattr(setup, name) if setup else None)) for name, label in (
        ("rig", "Drop rig (drawing or photograph)"),
        ("height_setting", "How the drop height was set and measured"),
        ("height_tolerance", "Drop-height tolerance"),
        ("drop_mass_weighing", "Drop-mass weighing record"),
        ("attitude", "Gear attitude (14 CFR 23.725(c))"),
        ("drag_loads", "Spin-up and drag loads (14 CFR 23.725(c))"),
        ("test_plan", "Test plan"), ("witness", "Witness"))]


def _gear_unit_rows(assessment: Assessment, units) -> list[dict]:
    spec = assessment.campaign.spec
    gear_rows = []
    for gear in spec.gear_units:
        strut = gear.strut
        fields = [("Position", gear.position), ("Static weight W", gear.static_weight.text),
                  ("Basis of W", gear.static_weight_basis + (f" — {gear.static_weight_note.strip()}"
                                                           if gear.static_weight_note else "")),
                  ("Shock absorber", gear.shock_absorber),
                  ("Design stroke", gear.design_stroke.text),
                  ("Tyre", f"{gear.tyre.size}, {gear.tyre.pressure.text} "
                           f"({gear.tyre.pressure_reference})")]
        if gear.wheel_diameter:
            fields.append(("Wheel diameter", gear.wheel_diameter.text))
        fields += _article_rows(gear.article)
        if strut is not None:
            for name, label in (("gas_precharge_pressure", "Gas pre-charge pressure"),
                                ("pressure_reference", "Gas pressure reference"),
                                ("gas_volume", "Gas volume (extended)"),
                                ("pneumatic_area", "Pneumatic area"),
                                ("hydraulic_area", "Hydraulic area"),
                                ("orifice_diameter", "Orifice diameter (compression)"),
                                ("orifice_area", "Orifice area"),
                                ("rebound_orifice_diameter", "Orifice diameter (rebound)"),
                                ("discharge_coefficient", "Discharge coefficient"),
                                ("oil_density", "Oil density"),
                                ("polytropic_exponent", "Polytropic exponent"),
                                ("inclination", "Strut inclination"),
                                ("static_stroke", "Static stroke"),
                                ("minimum_stroke", "Minimum stroke"),
                                ("unsprung_mass", "Unsprung mass"), ("notes", "Notes")):
                value = getattr(strut, name)
                if value is not None:
                    fields.append((label, pretty_typed(getattr(value, "text", value))))
        # the two the energies rest on are listed whether stated or not: a reviewer sees
        # what was assumed (the values they enter say so too)
        shown = {label for label, _ in fields}
        fields += [(label, NOT_STATED) for label in ("Strut inclination", "Unsprung mass")
                   if label not in shown]
        gear_rows.append({"id": gear.id, "fields": fields})
    return gear_rows



def pretty_typed(text):
    """A value typed in the spec as typed, its unit's powers as superscripts (in^3: in³)."""
    if not isinstance(text, str):
        return text
    magnitude, _, unit = text.partition(" ")
    return f"{magnitude} {pretty(unit)}" if unit and "^" in unit else text


def _instrumentation(assessment: Assessment, units) -> InstrumentationSection | None:
    spec = assessment.campaign.spec
    instrumentation = None
    if spec.instrumentation:
        inst = spec.instrumentation
        instrumentation = InstrumentationSection(**{
            "sampling_rate": inst.sampling_rate.text, "logger": inst.logger or "not stated",
            "channels": [{"name": c.name, "measures": c.measures,
                          "transducer": c.transducer or "—", "range": c.range or "—",
                          "filter": c.filter or "—",
                          "calibrated": _stated(c.calibration_date and
                                                c.calibration_date.isoformat()),
                          "due": _stated(c.calibration_due and c.calibration_due.isoformat()),
                          "certificate": _stated(c.calibration_reference)}
                         for c in inst.channels]})
    return instrumentation



def _matrix_rows(assessment: Assessment, units) -> list[dict]:
    matrix = []
    for run in assessment.runs:
        spec_run = run.run
        matrix.append({
            "id": spec_run.id, "type": spec_run.test_type,
            "gears": ", ".join(spec_run.gear_units), "height": spec_run.drop_height.text,
            "mass": spec_run.drop_mass.text,
            "lift": spec_run.lift.method.replace("_", " ")       # reduced_mass: words
                    + (f", L = {spec_run.lift.ratio.text}" if spec_run.lift.ratio else ""),
            "data": spec_run.data.file if spec_run.data else "none (reported values)",
            "date": " ".join(filter(None, (spec_run.date.isoformat() if spec_run.date else
                                           NOT_STATED, spec_run.time))),
            "ambient": _stated(spec_run.ambient_temperature)})
    return matrix



def _completeness_rows(assessment: Assessment, units) -> list[dict]:
    completeness = []
    for item in assessment.basis:
        for key, test_type, what in (("h_req", "limit", "Limit drop at ≥ h_req"),
                                     ("h_reserve", "reserve", "Reserve drop at ≥ 1.44·h_req")):
            if key not in item.values:
                continue
            required = item.values[key].value
            runs = [r.run.id for r in assessment.runs
                    if r.run.test_type == test_type and at_least(r.get("h"), required) == PASS]
            completeness.append({"set": item.rules.id, "requirement": what,
                                 "required": with_unit(required, "length", units),
                                 "runs": ", ".join(runs) or "none",
                                 "status": "present" if runs else "missing"})
    return completeness



def _results_rows(assessment: Assessment, units) -> list[dict]:
    results_rows = []
    for run in assessment.runs:
        for gear in run.gears:
            def cell(key, kind, gear=gear):
                value = gear.values.get(key)
                return ("—" if value is None
                        else typed(value.typed, value.value, kind, units)[0]
                        + assumed_mark(value, gear))
            energy_keys = [k for k in gear.values if k.startswith("n_j_energy[")]
            results_rows.append({
                "run": run.run.id, "gear": gear.gear_id,
                "height": typed(run.run.drop_height.text, run.get("h"), "length", units)[0],
                "d_s": cell("d_s", "length"), "d_t": cell("d_t", "length"),
                "F_peak": cell("F_peak", "force"), "E_s": cell("E_s", "energy"),
                "E_t": cell("E_t", "energy"), "eta_s": cell("eta_s", "ratio"),
                "eta_t": cell("eta_t", "ratio"), "FW": cell("F/W", "ratio"),
                "nE": cell(energy_keys[0], "ratio") if energy_keys else "—",
                "basis": gear.basis})
    return results_rows



def _run_views(assessment: Assessment, units) -> list[dict]:
    runs = []
    for run in assessment.runs:
        gears = []
        for gear in run.gears:
            gears.append({"id": gear.gear_id, "basis": gear.basis,
                          "value_rows": [_value_row(v, units) for v in gear.values.values()]})
        figures = []
        if run.series is not None:
            from certkit.evidence.figures import \
                run_figures  # matplotlib only when there is something to plot

            touchdowns = [g.get("t0") for g in run.gears if g.get("t0") is not None]
            figures = [dict(f, svg=Markup(f["svg"])) for f in run_figures(
                run.run.id, run.series.time,
                {g.gear_id: (run.series.gears[g.gear_id], g.measures) for g in run.gears
                 if g.measures is not None},
                min(touchdowns) if touchdowns else None, units)]
        inspection = run.run.inspection
        data = run.run.data
        figures_note = ""
        if not figures and data is not None and data.origin == "synthetic":
            figures_note = (f"The time histories of this drop ({data.file}) are synthetic, not "
                            f"test evidence: they and the load–stroke loops appear in the "
                            f"governing-equation model section only.")
        elif not figures and data is None:
            figures_note = ("No time histories are recorded for this drop: its values are "
                            "the reported ones.")
        runs.append({
            "id": run.run.id, "type": run.run.test_type,
            "value_rows": [_value_row(v, units) for v in run.values.values()],
            "gears": gears, "figures": figures, "figures_note": figures_note,
            "deviations": list(run.run.deviations),
            "inspection": None if inspection is None else {
                "before": inspection.before or NOT_STATED,
                "failure": {True: "yes", False: "no", None: "not recorded"}[inspection.failure],
                "yielding": {True: "yes", False: "no", None: "not recorded"}[inspection.yielding],
                "permanent_set": inspection.permanent_set.text if inspection.permanent_set
                else "not recorded", "notes": inspection.notes or ""},
            "notes": run.run.notes or ""})
    return runs



def _verdict_rows(assessment: Assessment, units) -> list[dict]:
    verdicts = []
    for verdict in assessment.verdicts:
        kind = verdict.kind
        verdicts.append({
            "id": verdict.id, "set": verdict.requirement_set, "clause": verdict.clause,
            "title": verdict.title, "scope": " / ".join(p for p in (verdict.run, verdict.gear) if p)
            or "campaign", "value": with_unit(verdict.value, kind, units),
            "limit": (f"{verdict.comparison} {with_unit(verdict.limit, kind, units)}"
                      if verdict.limit is not None else "—"),
            "margin": margin(verdict.margin, verdict.limit, kind, units),
            "verdict": verdict.verdict,
            "css": verdict.verdict.replace(" ", "-").lower(), "reason": verdict.reason,
            "to_confirm": verdict.to_confirm, **verdict_cells(verdict, units)})
    return verdicts



def _comparison_rows(assessment: Assessment, units) -> list[dict]:
    comparisons = []
    for item in assessment.comparisons:
        comparisons.append({
            "scope": " / ".join(p for p in (item.run, item.gear) if p) or "campaign",
            "quantity": item.quantity, "reported": item.reported_text,
            "recomputed": with_unit(item.recomputed, item.kind, units),
            "difference": ("—" if item.difference is None or item.recomputed in (None, 0)
                           else f"{item.difference / item.recomputed:+.2%}"),
            "tolerance": with_unit(item.tolerance, item.kind, units),
            "agrees": {True: "agrees", False: "DISAGREES", None: "—"}[item.agrees],
            "basis": item.basis})
    return comparisons


def _audit_settings(settings, units) -> dict[str, str]:
    """The audit's thresholds: as typed where the spec sets them, else the default in the
    display units (a length) or as a share."""
    shown = {}
    for name in type(settings).model_fields:
        quantity = getattr(settings, name)
        if name in settings.model_fields_set:
            shown[name] = quantity.text
        elif quantity.unit == "m":
            shown[name] = f"{' '.join(typed(quantity.text, quantity.si, 'length', units))} (default)"
        else:
            shown[name] = f"{quantity.text} (default)"
    return shown


def _load_factor_view(assessment: Assessment) -> tuple[list[dict], str]:
    """Every load factor of each run side by side, and what a stated one turned out to be."""
    rows = []
    for run in assessment.runs:
        stated = run.run.reported.impact_load_factor if run.run.reported else None
        for index, gear in enumerate(run.gears):
            energy = [(key.split("[")[1].rstrip("]"), gear.get(key)) for key in gear.values
                      if key.startswith("n_energy[")]
            rows.append({
                "run": run.run.id if index == 0 else "", "gear": gear.gear_id,
                "stated": (stated.text if stated is not None else "—") if index == 0 else "",
                "combined": display(run.get("n_combined"), "ratio", None)[0] if index == 0 else "",
                "n_j": display(run.get("n_j"), "ratio", None)[0] if index == 0 else "",
                "FW": display(gear.get("F/W"), "ratio", None)[0],
                "n": display(gear.get("n"), "ratio", None)[0],
                "n_energy": "; ".join(f"{display(v, 'ratio', None)[0]} ({set_id})"
                                      for set_id, v in energy) or "—"})
    checked = [c for c in assessment.comparisons if c.quantity == "impact load factor"]
    if not checked:
        return rows, ""
    pairs = ", ".join(f"{c.reported_text} → {number(c.recomputed)}" for c in checked)
    if all(c.agrees for c in checked):
        statement = (f"The source's stated impact load factors are reproduced, to the precision "
                     f"stated, by ΣF_peak(main units)/(m_drop·g) (certkit G2): {pairs}. They are "
                     f"the sum of the main-unit peak loads over the weight dropped, whether or "
                     f"not the peaks coincide in time and without the nose unit's load. They are "
                     f"neither the inertia load factor n = n_j·W_e/W + L of 14 CFR 23.725(e) "
                     f"(which needs the drop-mass acceleration) nor a bound on it, nor a per-unit "
                     f"ground-reaction factor F_peak/W; those are listed beside them.")
    else:
        statement = (f"The source's stated impact load factors are not all reproduced by "
                     f"ΣF_peak(main units)/(m_drop·g) (certkit G2): {pairs}; their definition "
                     f"is unknown.")
    return rows, statement


def _conclusions(assessment: Assessment, setup: list, gear_rows: list,
                 signatories: list) -> dict:
    """What the report shows, what it does not, and what stays open, in words: every
    sentence built from the verdicts, the findings and the items the spec leaves unstated."""
    shown, not_shown = {}, []
    for verdict in assessment.verdicts:
        scope = " / ".join(p for p in (verdict.run, verdict.gear) if p) or "campaign"
        if verdict.verdict == PASS:
            shown.setdefault((verdict.clause, verdict.title), []).append(scope)
        else:
            not_shown.append(f"{verdict.clause}, {verdict.title} ({scope}): {verdict.verdict}"
                             + (f" — {verdict.reason}" if verdict.reason else ""))
    counts = assessment.finding_counts()
    errors = [f"{f.id}: {f.message}" for f in assessment.findings if f.severity == "error"]
    unstated = [label for label, value in setup if value == NOT_STATED]
    for gear in gear_rows:
        unstated += [f"{label} ({gear['id']})" for label, value in gear["fields"]
                     if value == NOT_STATED]
    instrumentation = assessment.campaign.spec.instrumentation
    unstated += [f"calibration of channel {c.name}" for c in
                 (instrumentation.channels if instrumentation else []) if c.calibration_date is None]
    unstated += [f"{s['role']} sign-off" for s in signatories if s["name"] == NOT_STATED]
    found = assessment.uncertainty
    unstated += [f"measurement uncertainty of the {source.label} (a verdict depends on it)"
                 for source in (found.unstated if found is not None else [])]
    if found is not None and found.none_stated:
        unstated.append("measurement uncertainties and the decision rule (uncertainty block)")
    planning = assessment.planning
    return {
        "outcome": assessment.outcome,
        "shown_title": "Predicted to pass (planning: nothing is shown)" if planning else "Shown",
        "not_shown_title": ("Predicted not to pass, or not predictable" if planning
                            else "Not shown or failed"),
        "shown": [f"{clause}, {title}: {PASS} ({', '.join(scopes)})"
                  for (clause, title), scopes in shown.items()],
        "not_shown": not_shown,
        "findings": (f"{counts['error']} data-quality error(s), {counts['warning']} "
                     f"warning(s) and {counts['info']} info finding(s) (section "
                     f"{section_number('data-quality')})"),
        "errors": errors,
        "unstated": unstated}


def _references(assessment: Assessment) -> list[str]:
    """The rules and sources the report rests on: each requirement set with its edition and
    the edition the applicant states, and the source of any published results shown."""
    references = []
    for item in assessment.basis:
        rules = item.rules
        references.append(f"{rules.title}, {rules.edition} (certkit set {rules.id}"
                          f"{'; values to be confirmed' if rules.to_confirm else ''}); edition "
                          f"stated by the applicant: {item.entry.edition or NOT_STATED}.")
    published = assessment.campaign.spec.reference_results
    if published is not None:
        references.append(f"Published results shown beside certkit's: {published.source}")
    return references
