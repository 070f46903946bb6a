"""Rendering the evidence: results.json, CSV tables, self-contained HTML and PDF/A-3b.

Python prepares plain data (strings already formatted with their display units);
the Jinja2 templates only lay it out.  Outputs are written into a temporary folder
beside the target and moved into place at the end, so a failed or interrupted run
leaves no partial report.
"""

from __future__ import annotations

import contextlib
import csv
import datetime as dt
import importlib.util
import io
import json
import math
import os
from pathlib import Path

from jinja2 import Environment, FileSystemLoader, StrictUndefined, select_autoescape
from markupsafe import Markup

from certkit.version import VERSION
from certkit.compliance.assessment import Assessment
from certkit.compliance.criteria import at_least
from certkit.display import (DISPLAY_RULE, SIGNIFICANT, display, margin, number, parameter, percent,
                      pretty, to_display, typed, with_unit)
from certkit.compliance.equations import EQUATIONS, GRAVITY_NOTE
from certkit.outputs import staged_folder
from certkit.evidence.provenance import provenance
from certkit.results import PASS, RESULTS_FORMAT, Value
from certkit.units import convert

def templates_dir() -> Path:
    """The Jinja2 templates: packaged copy in a wheel, the repository's templates/ otherwise."""
    package = Path(__file__).resolve().parent.parent
    packaged = package / "_templates"
    return packaged if packaged.is_dir() else package.parent / "templates"


def fonts_dir() -> Path:
    """DejaVu fonts shipped with matplotlib (a core dependency): embedded in every PDF.

    Located without importing matplotlib (a report without figures does not need it)."""
    spec = importlib.util.find_spec("matplotlib")
    return Path(spec.submodule_search_locations[0]) / "mpl-data" / "fonts" / "ttf"


# --------------------------------------------------------------------------- formatting
def _value_row(value: Value, units) -> dict:
    number, unit = typed(value.typed, value.value, value.kind, units)
    return {"label": value.label, "symbol": value.symbol, "value": number, "unit": unit,
            "source": value.source, "formula": value.formula,
            "inputs": "; ".join(f"{k}: {v}" for k, v in value.inputs.items()),
            "note": value.note or ""}


# --------------------------------------------------------------------------- view model
def build_view(assessment: Assessment, record: dict, model=None) -> dict:
    """Plain data for the templates: every string already formatted.

    ``model`` is the :class:`~certkit.evidence.model_evidence.ModelEvidence` of the governing-equation
    section (None: the section says the model was not run)."""
    campaign = assessment.campaign
    spec = campaign.spec
    units = spec.report.units
    doc = spec.document

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
                    fields.append((label, getattr(value, "text", value)))
        gear_rows.append({"id": gear.id, "fields": fields})

    instrumentation = None
    if spec.instrumentation:
        inst = spec.instrumentation
        instrumentation = {
            "sampling_rate": inst.sampling_rate.text, "logger": inst.logger or "not stated",
            "channels": [{"name": c.name, "measures": c.measures,
                          "transducer": c.transducer or "—", "range": c.range or "—",
                          "filter": c.filter or "—",
                          "calibration": (f"{c.calibration_date.isoformat()}"
                                          f"{' (' + c.calibration_reference + ')' if c.calibration_reference else ''}"
                                          if c.calibration_date else "not stated")}
                         for c in inst.channels]}

    matrix = []
    for run in assessment.runs:
        spec_run = run.run
        matrix.append({
            "id": spec_run.id, "type": spec_run.test_type,
            "gears": ", ".join(spec_run.gear_units), "height": spec_run.drop_height.text,
            "mass": spec_run.drop_mass.text,
            "lift": spec_run.lift.method + (f", L = {spec_run.lift.ratio.text}"
                                            if spec_run.lift.ratio else ""),
            "data": spec_run.data.file if spec_run.data else "none (reported values)",
            "date": spec_run.date.isoformat() if spec_run.date else "—"})
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

    results_rows = []
    for run in assessment.runs:
        for gear in run.gears:
            def cell(key, kind, gear=gear):
                value = gear.values.get(key)
                return ("—" if value is None
                        else typed(value.typed, value.value, kind, units)[0])
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
    results_units = {kind: pretty(getattr(units, kind))
                     for kind in ("length", "force", "energy")}
    load_factors, load_factor_statement = _load_factor_view(assessment)

    runs = []
    for run in assessment.runs:
        gears = []
        for gear in run.gears:
            gears.append({"id": gear.gear_id, "basis": gear.basis,
                          "value_rows": [_value_row(v, units) for v in gear.values.values()]})
        figures = []
        if run.series is not None:
            from certkit.evidence.figures import run_figures  # matplotlib only when there is something to plot

            touchdowns = [g.get("t0") for g in run.gears if g.get("t0") is not None]
            figures = [dict(f, svg=Markup(f["svg"])) for f in run_figures(
                run.run.id, run.series.time,
                {g.gear_id: (run.series.gears[g.gear_id], g.measures) for g in run.gears
                 if g.measures is not None},
                min(touchdowns) if touchdowns else None, units)]
        inspection = run.run.inspection
        runs.append({
            "id": run.run.id, "type": run.run.test_type,
            "value_rows": [_value_row(v, units) for v in run.values.values()],
            "gears": gears, "figures": figures,
            "deviations": list(run.run.deviations),
            "inspection": None if inspection is None else {
                "failure": {True: "yes", False: "no", None: "not recorded"}[inspection.failure],
                "yielding": {True: "yes", False: "no", None: "not recorded"}[inspection.yielding],
                "permanent_set": inspection.permanent_set.text if inspection.permanent_set
                else "not recorded", "notes": inspection.notes or ""},
            "notes": run.run.notes or ""})

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
            "to_confirm": verdict.to_confirm})

    findings = [{"id": f.id, "severity": f.severity, "message": f.message}
                for f in sorted(assessment.findings,
                                key=lambda f: ("error", "warning", "info").index(f.severity))]
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

    counts = assessment.counts()
    finding_counts = assessment.finding_counts()
    signatories = [{"role": s.role, "name": s.name, "organisation": s.organisation or "",
                    "date": s.date.isoformat() if s.date else ""} for s in doc.signatories]
    return {
        "lang": "en",
        "title": f"{doc.report_number} rev {doc.revision}: {spec.campaign.title}",
        "campaign": {"id": spec.campaign.id, "title": spec.campaign.title,
                     "description": (spec.campaign.description or "").strip()},
        "document": {"report_number": doc.report_number, "revision": doc.revision,
                     "date": doc.date.isoformat(), "applicant": doc.applicant,
                     "facility": doc.facility,
                     "test_dates": ", ".join(d.isoformat() for d in doc.test_dates),
                     "checklist": doc.compliance_checklist_item or "—",
                     "signatories": signatories,
                     "revisions": [{"revision": r.revision, "date": r.date.isoformat(),
                                    "description": r.description} for r in doc.revisions]},
        "created": f"{doc.date.isoformat()}T00:00:00Z",
        "outcome": assessment.outcome,
        "outcome_css": ("planning" if assessment.planning
                        else assessment.outcome.replace(" ", "-").lower()),
        "planning": assessment.planning,
        "outcome_reasons": assessment.outcome_reasons(),
        "counts": counts, "finding_counts": finding_counts,
        "aircraft": {"model": spec.aircraft.model, "notes": (spec.aircraft.notes or "").strip()},
        "design": [_value_row(v, units) for v in assessment.design.values()],
        "basis": basis, "any_to_confirm": any(b["to_confirm"] for b in basis),
        "gear_units": gear_rows, "instrumentation": instrumentation,
        "matrix": matrix, "completeness": completeness,
        "results_rows": results_rows, "results_units": results_units,
        "load_factors": load_factors, "load_factor_statement": load_factor_statement,
        # a column only where some run has something in it (a single-gear rig has no ΣF_peak)
        "load_factor_columns": {column: any(r[column] not in ("", "—") for r in load_factors)
                                for column in ("stated", "combined", "n_j", "n", "n_energy")},
        "runs": runs, "verdicts": verdicts, "findings": findings, "comparisons": comparisons,
        "equations": sorted(EQUATIONS.items()), "gravity_note": GRAVITY_NOTE,
        "display_rule": DISPLAY_RULE,
        "assumptions": [a.strip() for a in spec.assumptions],
        "audit": _audit_settings(spec.audit, units),
        "provenance": record, "version": VERSION,
        "model": _model_view(model, units, spec.reference_results, _origins(spec),
                             spec.model.effects),
        "identification": _identification_view(model, spec.model.identification, units,
                                               spec.reference_results, _origins(spec)),
        "gap": _gap_view(model, campaign, units),
    }


def _reference_error(reference, gear_id: str, channel: str, model: str, run: str):
    """A published RMSE (the spec's quantity) of the campaign's reference_results for this
    gear unit, run, channel and model (a field of
    :class:`~certkit.spec.schema.ReferenceModelErrors`), None when it has none."""
    if reference is None or (reference.gear is not None and reference.gear != gear_id) or (
            reference.run is not None and reference.run != run):
        return None
    errors = getattr(reference, channel, None) if channel in ("stroke", "tyre") else None
    return getattr(errors, model, None) if errors is not None else None


def _reference_view(reference, units) -> dict | None:
    """How the report names the campaign's published reference results (None: it has none)."""
    if reference is None:
        return None
    return {"source": reference.source, "gear": reference.gear or "not stated",
            "run": reference.run or "not stated",
            "window": with_unit(reference.window.si, "time", units),
            "note": (reference.note or "").strip()}


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


def _origins(spec) -> dict[str, str]:
    """run id -> declared origin of its time histories (measured / synthetic)."""
    return {run.id: run.data.origin for run in spec.runs if run.data is not None}


#: What the model sections say when the report was made without the drop model.
NO_MODEL = ("The drop model was not run for this report (certkit report --no-model, or "
            "render_report without a model evidence): the governing-equation, identification "
            "and gap sections are left out of it.")


def _model_view(evidence, units, reference=None, origins=None, effects=()) -> dict:
    """The governing-equation model section: calibration per gear unit, or why none."""
    if evidence is None:
        return {"available": False, "note": NO_MODEL, "synthetic": "", "gears": [],
                "effects": ", ".join(effects) or "none", "reference_rows": [],
                "reference": None}
    synthetic = ""
    if evidence.synthetic_runs:
        synthetic = (f"The time histories of run(s) {', '.join(evidence.synthetic_runs)} are "
                     f"SYNTHETIC (simulated, declared origin: synthetic), not measured: the "
                     f"model is compared here with simulated data, which shows the method, "
                     f"not the real gear's behaviour.")
    calibration = evidence.calibration
    if calibration is None:
        return {"available": False, "note": evidence.note, "synthetic": synthetic, "gears": [],
                "effects": "—", "reference_rows": [], "reference": None}
    from certkit.spec.rundata import CHANNEL_LABELS
    from certkit.evidence.figures import model_figure

    gears, reference_rows = [], []
    for gear in calibration.gears:
        fit = gear.fit
        parameters = []
        for knob, p, estimate, error in zip(gear.knobs, fit.parameters, fit.estimate,
                                            fit.standard_error):
            nominal, unit = parameter(p.nominal, p.unit, units)
            value = parameter(float(estimate), p.unit, units)[0]
            se = ("not determined" if not math.isfinite(error)
                  else parameter(float(error), p.unit, units)[0])
            bounds = (f"{parameter(p.lower, p.unit, units)[0]} to "
                      f"{parameter(p.upper, p.unit, units)[0]}")
            parameters.append({"name": knob.label, "unit": unit, "nominal": nominal,
                               "estimate": value, "error": se, "bounds": bounds})
        names = [p.name for p in fit.parameters]
        correlation = [{"name": f"({i}) {name}",
                        "cells": ["—" if not math.isfinite(c) else f"{c:+.2f}" for c in row]}
                       for i, (name, row) in enumerate(zip(names, fit.correlation), start=1)]
        rmse = []
        for e in gear.errors:
            kind = "force" if e.channel == "load" else "length"
            before, unit = display(e.nominal, kind, units)
            after, _ = display(e.calibrated, kind, units)
            change = (e.calibrated / e.nominal - 1) if e.nominal else float("nan")
            rmse.append({"run": e.run, "channel": CHANNEL_LABELS[e.channel], "unit": unit,
                         "nominal": before, "calibrated": after,
                         "change": f"{change:+.1%}" if math.isfinite(change) else "—"})
        for trace in gear.traces:
            published = _reference_error(reference, gear.gear_id, trace.channel,
                                         "governing_equation", trace.run)
            if published is None:
                continue
            first = trace.time <= reference.window.si
            nominal = math.sqrt(float(((trace.nominal - trace.measured)[first] ** 2).mean()))
            fitted = math.sqrt(float(((trace.calibrated - trace.measured)[first] ** 2).mean()))
            reference_rows.append({
                "gear": gear.gear_id, "run": trace.run,
                "channel": CHANNEL_LABELS[trace.channel],
                "reference": " ".join(typed(published.text, published.si, "length", units)),
                "nominal": with_unit(nominal, "length", units),
                "calibrated": with_unit(fitted, "length", units)})
        figures = [model_figure(gear.gear_id, run, [t for t in gear.traces if t.run == run], units,
                                origin=(origins or {}).get(run, "measured"))
                   for run in gear.runs]
        figures = [dict(f, svg=Markup(f["svg"])) for f in figures]
        velocities = "; ".join(f"{run}: {with_unit(v, 'velocity', units)} ({source})"
                               for run, (v, source) in gear.contact_velocities.items())
        gears.append({
            "id": gear.gear_id, "runs": ", ".join(gear.runs), "parameters": parameters,
            "correlation_header": [f"({i})" for i in range(1, len(names) + 1)],
            "correlation": correlation, "warnings": list(fit.warnings),
            "converged": fit.success, "message": fit.message, "evaluations": fit.evaluations,
            "cost": f"{fit.cost_nominal:.4g} → {fit.cost:.4g}", "rmse": rmse,
            "figures": figures, "velocities": velocities, "step": with_unit(gear.step, "time", units)})
    return {"available": True, "note": evidence.note, "synthetic": synthetic, "gears": gears,
            "effects": ", ".join(calibration.effects) or "none", "reference_rows": reference_rows,
            "reference": _reference_view(reference, units)}


_MODEL_ORDER = ("governing equation, nominal", "governing equation, calibrated", "Hammerstein",
                "Wiener (small-signal)", "Wiener (BLA)", "NARX")


#: Fields of the spec's reference_results that correspond to certkit's models.
_REFERENCE_MODELS = {"governing equation, nominal": "governing_equation",
                     "Hammerstein": "hammerstein", "Wiener (small-signal)": "wiener",
                     "NARX": "narx"}


def _mm(value_mm: float, units) -> str:
    """An identification error (computed in mm) in the display length unit, with the unit."""
    return f"{_short(value_mm * 1e-3, 'length', units)} {units.length}"


def _ranking_sentence(scores, output: str, protocol: str, run: str, units) -> str:
    chosen = sorted((s for s in scores if s.output == output and s.protocol == protocol
                     and s.run == run), key=lambda s: s.rmse)
    return ", ".join(f"{s.model} {_mm(s.rmse, units)}" for s in chosen)


def _discussion(gear, reference, units) -> list[str]:
    """Where the ranking of the models the campaign's reference results rank differs from
    what the data say here (nothing when the campaign has no reference results)."""
    from certkit.ident.protocol import OUTPUT_LABELS, PAPER_TRAINING, PAPER_TRAINING_DURATION

    run = gear.held_out[0]
    sentences = []
    for output in ("stroke", "tyre"):
        published = {model: _reference_error(reference, gear.gear_id, output, field, run)
                     for model, field in _REFERENCE_MODELS.items()}
        published = {model: value.si for model, value in published.items() if value is not None}
        if len(published) < 2:
            continue
        chosen = [x for x in gear.scores if x.output == output and x.protocol == "held-out"
                  and x.run == run and x.model in published]
        held = [x.model for x in sorted(chosen, key=lambda x: x.rmse)]
        ranked = sorted(published, key=published.get)
        text = (f"{OUTPUT_LABELS[output].capitalize()}: the reference results "
                f"({reference.source}) rank {' < '.join(ranked)} (RMSE). On the held-out drop "
                f"{run} the order here is {' < '.join(held) or 'not available'}")
        text += ("; the same." if held == ranked else "; it differs.")
        paper_full = [x for x in gear.scores if x.output == output and x.protocol == "paper"]
        held_full = [x for x in gear.scores if x.output == output and x.protocol == "held-out"
                     and x.run == run]
        if paper_full and held_full:
            best_paper = min(paper_full, key=lambda x: x.rmse)
            best_held = min(held_full, key=lambda x: x.rmse)
            text += (f" Trained on the first {PAPER_TRAINING} samples ("
                     f"{with_unit(PAPER_TRAINING_DURATION, 'time', units)}) of the very drop it then "
                     f"simulates, the best model reaches {_mm(best_paper.rmse, units)} "
                     f"({best_paper.model}); trained on other drop heights, "
                     f"{_mm(best_held.rmse, units)} ({best_held.model}).")
        sentences.append(text)
    return sentences


def _identification_view(evidence, settings, units, reference=None, origins=None) -> dict:
    """The identification section: RMSE tables (beside the campaign's reference results when
    it has some), linear blocks, figures.

    ``settings``: the spec's ``model.identification``; ``reference``: its reference_results."""
    from certkit.ident.protocol import (MODEL_RATE, PAPER_TRAINING, PAPER_TRAINING_DURATION,
                                 PROTOCOL_NAMES, WHITENESS_CONFIDENCE, WHITENESS_LAGS, WINDOW,
                                 WINDOW_DURATION)

    method = {"window": (f"{with_unit(WINDOW_DURATION, 'time', units)} ({WINDOW} samples at "
                         f"the identification rate of {MODEL_RATE:g} Hz; a record logged at "
                         f"another rate is low-passed and resampled to it)"),
              "paper_samples": f"{with_unit(PAPER_TRAINING_DURATION, 'time', units)} "
                               f"({PAPER_TRAINING} samples)",
              "gain": settings.small_signal.gain.text,
              "tolerance": settings.small_signal.tolerance.text,
              "whiteness": f"{WHITENESS_CONFIDENCE:.0%} bounds, {WHITENESS_LAGS} lags",
              "force_unit": pretty(units.force), "length_unit": pretty(units.length),
              "reference": _reference_view(reference, units)}
    identification = getattr(evidence, "identification", None)
    if identification is None or not identification.gears:
        skipped = list(getattr(identification, "skipped", []) or [])
        return {"available": False, "gears": [], "plant_note": "",
                "note": NO_MODEL if evidence is None else
                "Not run: it needs time histories of at least two drops of a gear unit "
                "whose drop model can be built from the spec, each recorded for "
                f"{with_unit(WINDOW_DURATION, 'time', units)} after touchdown."
                + (" " + "; ".join(skipped) + "." if skipped else ""), **method}
    from certkit.evidence.figures import identification_figures
    from certkit.ident.protocol import OUTPUT_LABELS

    # the static gain of a linear block, mm/kN, in display units per display unit
    gain_scale = convert(1e-6, "m", units.length) / convert(1.0, "N", units.force)
    gears = []
    for gear in identification.gears:
        run = gear.held_out[0]

        def published(model: str, output: str):
            return _reference_error(reference, gear.gear_id, output,
                                    _REFERENCE_MODELS.get(model, ""), run)

        # the reference column only where the campaign has such figures for this gear
        with_reference = any(published(m, o) for m in _MODEL_ORDER for o in ("stroke", "tyre"))
        table = []
        for model in _MODEL_ORDER:
            cells = []
            for output in ("stroke", "tyre"):
                for protocol in ("paper", "held-out"):
                    score = next((x for x in gear.scores if (x.model, x.output, x.protocol, x.run)
                                  == (model, output, protocol, run)), None)
                    cells.append("—" if score is None
                                 else _short(score.rmse * 1e-3, "length", units))
                if with_reference:
                    quantity = published(model, output)
                    cells.append("—" if quantity is None
                                 else typed(quantity.text, quantity.si, "length", units)[0])
            table.append({"model": model, "cells": cells})
        details = [{"model": x.model, "protocol": PROTOCOL_NAMES[x.protocol],
                    "output": OUTPUT_LABELS[x.output], "run": x.run,
                    "rmse": _short(x.rmse * 1e-3, "length", units), "nrmse": f"{x.nrmse:.4g}",
                    "fit": f"{x.fit:.1f}", "max": _short(x.max_error * 1e-3, "length", units)}
                   for x in sorted(gear.scores, key=lambda x: (x.output, x.protocol,
                                                               _MODEL_ORDER.index(x.model)))]
        blocks = []
        for (route, output), arx in gear.linear_blocks.items():
            blocks.append({"route": route, "output": OUTPUT_LABELS[output],
                           "a": ", ".join(number(v, 6) for v in arx.a_),
                           "b": ", ".join(number(v * gain_scale, 6) for v in arx.b_),
                           "gain": (f"{number(arx.static_gain_ * gain_scale, 4)} "
                                    f"{units.length}/{units.force}"
                                    if math.isfinite(arx.static_gain_) else "not determined"),
                           "stable": "yes" if arx.stable_ else "NO"})
        steps = [{"output": OUTPUT_LABELS[output],
                  "amplitude": with_unit(step.amplitude, "force", units, 4),
                  "mismatch": percent(step.mismatch[output]),
                  "accepted": "accepted" if step.accepted else "not linear: shrink"}
                 for output, recorded in gear.small_signal.items() for step in recorded]
        one_step = [{"model": m, "output": OUTPUT_LABELS[o], "run": r,
                     "rmse": _mm(v, units)} for m, o, r, v in gear.one_step]
        whiteness = [{"model": m, "output": OUTPUT_LABELS[o],
                      "auto": f"{int(a.autocorrelation_ok.sum())}/{a.autocorrelation_ok.size}",
                      "cross": (f"{int(a.cross_correlation_ok.sum())}/{a.cross_correlation_ok.size}"
                                if a.cross_correlation_ok is not None else "—"),
                      "white": "yes" if a.white else "no"} for m, o, a in gear.whiteness]
        rankings = [f"{OUTPUT_LABELS[o]}, {PROTOCOL_NAMES[p]} protocol, run {gear.held_out[0]}: "
                    f"{_ranking_sentence(gear.scores, o, p, gear.held_out[0], units)}"
                    for o in ("stroke", "tyre") for p in ("held-out", "paper")]
        origin = (origins or {}).get(gear.held_out[0], "measured")
        figures = [dict(f, svg=Markup(f["svg"]))
                   for f in identification_figures(gear, units, origin)]
        gears.append({"id": gear.gear_id, "training": ", ".join(gear.training),
                      "held_out": ", ".join(gear.held_out), "table": table,
                      "with_reference": with_reference, "details": details,
                      "blocks": blocks, "steps": steps, "one_step": one_step,
                      "whiteness": whiteness, "rankings": rankings, "figures": figures,
                      "discussion": _discussion(gear, reference, units),
                      "ratios": ", ".join(f"{OUTPUT_LABELS[o]} {r:.3g}"
                                          for o, r in gear.hammerstein_ratio.items()),
                      "notes": list(gear.notes)})
    return {"available": True, "gears": gears, "plant_note": identification.plant_note,
            "note": "", **method}


# --------------------------------------------------------------------------- the gap section
def _short(value: float | None, kind: str, units, digits: int = SIGNIFICANT) -> str:
    """A number in display units, without its unit ("—" when None)."""
    return display(value, kind, units, digits)[0]


def _channel_kind(channel: str) -> str:
    return "force" if channel == "load" else "length"


def _gap_method(units) -> dict:
    """The method in words, every threshold taken from the code that applies it."""
    from certkit.gap.attribution import CANDIDATES, GAIN, LEADING, RELEVANT, STARTS, TIE_COSINE, TIE_COST
    from certkit.gap.holdout import MIDDLE_FROM
    from certkit.gap.phases import BREAKOUT_TRAVEL, BREAKOUT_WINDOW, REBOUND_DROP
    from certkit.gap.residuals import BANDS, MAX_LAG

    bands = ", ".join(f"{name} ({low:g}-{high:g} Hz)" if math.isfinite(high)
                      else f"{name}" for name, low, high in BANDS)
    return {
        "split": (f"The nominal drop model (no optional effects) is calibrated on the training "
                  f"runs only. The held-out runs are used for nothing but the errors reported "
                  f"as held out: by default every drop at the highest drop height (the "
                  f"certification case is extrapolation), and the middle height's drops too "
                  f"when there are {MIDDLE_FROM} heights or more; the spec's model.gap.held_out "
                  f"overrides the default."),
        "where": (f"Where: the residual (measured − model) of each channel is cut by the "
                  f"measured run's phases: free fall; tyre-only contact from touchdown; strut "
                  f"breakout, the first {with_unit(BREAKOUT_WINDOW, 'time', units)} after the "
                  f"stroke exceeds {with_unit(BREAKOUT_TRAVEL, 'length', units)}; compression "
                  f"to peak load; rebound to the end of the extension (the first stroke "
                  f"minimum once the stroke has come down {percent(REBOUND_DROP, 0)} of its "
                  f"travel); settling. Per channel, "
                  f"phase and run: RMS, bias (mean of measured − model) and timing lag (the "
                  f"cross-correlation peak within ±{with_unit(MAX_LAG, 'time', units)}; "
                  f"positive: the model is late). The residual's energy from touchdown is split "
                  f"into bands: {bands}."),
        "which": (f"Which: each candidate effect is a one-parameter family that nests the "
                  f"nominal model (strength 0: the effect is absent). Its score "
                  f"(Lagrange-multiplier) statistic LM is computed on the training runs after "
                  f"projecting out what re-tuning the nominal parameters can absorb, and "
                  f"converted into the RMS of the residual it would remove, √(LM/N), in units "
                  f"of the noise σ. Because the test looks only at zero strength, each "
                  f"candidate is also profiled: its training cost at the strengths "
                  f"{', '.join(f'{v:g}' for v in STARTS)}, with what re-tuning the nominal "
                  f"parameters absorbs projected out (an effect strongly nonlinear in its "
                  f"strength can point the wrong way at zero and still explain the gap). "
                  f"A candidate is relevant when it is among the {LEADING} best scores and "
                  f"would remove at least {RELEVANT:g} σ, or when its profile already cuts the "
                  f"training cost by {percent(GAIN, 0)}; the {LEADING} relevant ones with the "
                  f"best profiles are refitted together with the nominal parameters on the "
                  f"training runs, each from its profile's best strength. The refit that cuts the "
                  f"training cost (RMS of the residuals divided by each channel's range) most, "
                  f"by at least {percent(GAIN, 0)}, is named. When the two best refits' training costs "
                  f"lie within a ratio of {TIE_COST:g} and the cosine of their projected "
                  f"signatures is at least {TIE_COSINE:g}, the two cannot be told apart and "
                  f"the diagnosis says so instead of naming one. A second effect is then looked "
                  f"for the same way. The held-out errors are computed after the choice and "
                  f"play no part in it."),
        "candidates": [{"name": c.name, "unit_size": c.unit_size} for c in CANDIDATES],
    }


def _gap_cells(before, after, units) -> list[dict]:
    from certkit.spec.rundata import CHANNEL_LABELS

    later = {(c.run, c.channel, c.phase): c for c in after.cells} if after else {}
    rows = []
    for cell in before.cells:
        kind = _channel_kind(cell.channel)
        remaining = later.get((cell.run, cell.channel, cell.phase))
        rows.append({
            "run": cell.run, "role": "held out" if cell.run in before.held_out else "training",
            "channel": CHANNEL_LABELS[cell.channel], "phase": cell.phase,
            "samples": str(cell.samples), "unit": getattr(units, kind),
            "rms": _short(cell.rms, kind, units), "bias": _short(cell.bias, kind, units),
            "lag": _short(cell.lag, "time", units, 3),
            "normalised": percent(cell.normalised),
            "rms_after": _short(remaining.rms, kind, units) if remaining else "—",
            "normalised_after": percent(remaining.normalised) if remaining else "—"})
    return rows


def largest_disagreement(cell, units) -> str:
    """A residual map's largest cell in words, in the display units (report and terminal)."""
    from certkit.gap.residuals import describe

    if cell is None:
        return "No residual to map."
    kind = _channel_kind(cell.channel)
    return describe(cell, to_display(1.0, kind, units), pretty(getattr(units, kind)))


def _gap_largest(gap_map, units) -> str:
    """The largest disagreement (training runs) in words, in display units, with its bands."""
    from certkit.gap.residuals import BANDS

    cell = gap_map.largest
    if cell is None:
        return "No residual to map."
    text = largest_disagreement(cell, units)
    shares = gap_map.bands.get((cell.run, cell.channel))
    if shares:
        parts = [f"{percent(shares[name], 0)} in the {name} band"
                 + (f" ({low:g}-{high:g} Hz)" if math.isfinite(high) else "")
                 for name, low, high in BANDS]
        text += (f" Of the {cell.channel} residual's energy in run {cell.run} from touchdown, "
                 + ", ".join(parts[:-1]) + " and " + parts[-1] + ".")
    return text


def _gap_steps(gap, units) -> list[dict]:
    from certkit.gap.attribution import CANDIDATES, GAIN, LEADING, RELEVANT, TIE_COSINE, TIE_COST
    from certkit.spec.rundata import CHANNEL_LABELS

    diagnosis = gap.diagnosis
    sizes = {c.name: c.unit_size for c in CANDIDATES}
    steps = []
    for index, (attribution, fits) in enumerate(diagnosis.steps):
        beat = diagnosis.step_costs[index]
        refitted = {f.effects[-1] for f in fits}
        scores = []
        for score in attribution.scores:
            profile = (attribution.profiles or {}).get(score.name)
            if score.name in refitted:
                status = "refitted"
            elif score.name in attribution.relevant:
                status = f"relevant, not among the {LEADING} best profiles"
            elif score.direction < 0:
                status = ("its score points the other way and its profile cuts the training "
                          f"cost by less than {percent(GAIN, 0)}: not relevant")
            else:
                status = (f"not among the {LEADING} best scores with {RELEVANT:g} σ or more, "
                          f"and its profile cuts the training cost by less than "
                          f"{percent(GAIN, 0)}: not relevant")
            scores.append({"effect": score.name, "statistic": f"{score.statistic:.4g}",
                           "explained": f"{score.explained:.3g}", "status": status,
                           "profile": "—" if not profile else
                           f"{profile[1]:.4g} at strength {profile[0]:g}"})
        pair = ""
        if len(attribution.scores) >= 2:
            a, b = attribution.scores[0].name, attribution.scores[1].name
            cosine = attribution.confusability.get((a, b), attribution.confusability.get((b, a)))
            if cosine is not None:
                pair = (f"Confusability of the leading pair, {a} and {b}: the cosine of their "
                        f"projected signatures is {cosine:.3f} (at {TIE_COSINE:g} or more, with "
                        f"refitted training costs within a ratio of {TIE_COST:g}, they count as "
                        f"indistinguishable with these channels).")
        named = tuple(diagnosis.answer[:index + 1])
        refits = []
        for fit in fits:
            strengths = "; ".join(
                f"{name}: {value:.4g} ± "
                f"{(f'{error:.2g}' if math.isfinite(error) else 'not determined')} "
                f"(strength 1: {sizes.get(name, 'as defined by the candidate')})"
                for name, value, error in zip(fit.effects, fit.strengths, fit.strength_errors))
            if fit.effects == named and len(named) == index + 1:
                outcome = "named"
            elif fit.training_cost > (1 - GAIN) * beat:
                outcome = f"cuts the training cost by less than {percent(GAIN, 0)}: not named"
            else:
                outcome = (f"cuts the training cost by {percent(GAIN, 0)} or more; not named "
                           f"(see the statement)")
            checks = gap.refit_held_out.get((index, fit.effects), {})
            held = "; ".join(f"{run} {CHANNEL_LABELS[channel]} "
                             f"{_short(value, _channel_kind(channel), units)} "
                             f"{getattr(units, _channel_kind(channel))}"
                             for (run, channel), value in checks.items())
            refits.append({"effects": " + ".join(fit.effects), "strengths": strengths,
                           "cost": f"{fit.training_cost:.4g}",
                           "change": percent(fit.training_cost / beat - 1, signed=True)
                           if beat else "—",
                           "outcome": outcome, "held_out": held or "—"})
        title = ("Step 1: candidates against the calibrated nominal model" if index == 0 else
                 f"Step {index + 1}: candidates against the model with "
                 f"{' and '.join(diagnosis.answer[:index])}")
        steps.append({"title": title, "beat": f"{beat:.4g}", "scores": scores, "pair": pair,
                      "refits": refits,
                      "no_refit": "" if refits else
                      f"No candidate would remove {RELEVANT:g} σ or more: none was refitted."})
    return steps


def _gap_shrink(gap, units) -> list[dict]:
    from certkit.spec.rundata import CHANNEL_LABELS

    rows = []
    for error in gap.held_out_errors:
        kind = _channel_kind(error.channel)
        shrink = error.shrink
        rows.append({"run": error.run, "channel": CHANNEL_LABELS[error.channel],
                     "phase": error.phase, "unit": getattr(units, kind),
                     "samples": str(error.samples), "before": _short(error.before, kind, units),
                     "after": _short(error.after, kind, units),
                     "shrink": "—" if shrink is None else
                     percent(shrink) + (" (worse)" if shrink < 0 else "")})
    return rows


def _blind_view(campaign) -> dict:
    """The blind check's record (model.gap.blind_check) in words and tables, or how to make
    one."""
    from certkit.spec.blind_record import METRICS

    command = f"certkit gap --blind-check {campaign.spec_path.name} -o DIR"
    record = campaign.blind_check
    if record is None:
        return {"recorded": False, "command": command,
                "absent": "The blind check has not been recorded for this campaign, so this "
                          "report gives no measured evidence of how often the diagnosis names "
                          "the right effect. To record it, run the command below and name the "
                          "JSON file it writes in the spec's model.gap.blind_check."}
    from certkit.spec.blind_record import code_fingerprint, template_fingerprint
    from certkit.evidence.figures import blind_curve

    now, code = template_fingerprint(campaign), code_fingerprint()
    name = campaign.spec.model.gap.blind_check
    resolved = (campaign.root / name).resolve()
    item = next((i for i in campaign.inputs if i.path == resolved), None)
    metrics, short = [], []
    keys = [k for k in METRICS if k in record.metrics] + [k for k in record.metrics
                                                          if k not in METRICS]
    for key in keys:
        metric = record.metrics[key]
        label, definition = METRICS.get(key, (key.replace("_", " "), "as recorded"))
        value = "not measured" if metric.value is None else percent(metric.value)
        judged = metric.judged
        target = "no target" if metric.target is None else \
            f"{metric.direction} {percent(metric.target)}"
        verdict = {True: "met", False: "NOT met", None: "—"}[judged]
        if judged is False:
            short.append(f"{label} {value} against a target of {target}")
        counted = (f"{metric.count} of {metric.cases} cases" if metric.count is not None
                   else f"{metric.cases} cases")
        if metric.interval:
            low, high = metric.interval
            counted += f" (95 % interval {percent(low)}–{percent(high)})"
        metrics.append({"label": label, "definition": definition, "value": value,
                        "cases": counted, "target": target, "verdict": verdict,
                        "css": {True: "pass", False: "fail", None: ""}[judged]})
    if short:
        verdict = ("Short of target: " + "; ".join(short) + ". The diagnosis falls short there, "
                   "and its answers for this campaign should be weighed with that in mind.")
    elif any(m.judged is not None for m in record.metrics.values()):
        verdict = "Every metric with a target meets it."
    else:
        verdict = "No metric of the record has a target."
    def plain(value, depth=0) -> str:
        if isinstance(value, dict):
            return "; ".join(f"{k}: {plain(v, depth + 1)}" for k, v in value.items())
        if isinstance(value, list):
            return (" + " if depth else ", ").join(plain(v, depth + 1) for v in value)
        return f"{value:g}" if isinstance(value, float) else str(value)

    settings = [(key.replace("_", " "), plain(value)) for key, value in record.settings.items()]
    confusion = record.confusion
    curve_figure = None
    if record.curve:
        targets = [record.metrics[k].target if k in record.metrics else None
                   for k in ("top1", "median_shrink")]
        curve_figure = blind_curve(record.curve, *targets,
                                   scored_from=record.settings.get("scored_from"))
        curve_figure = dict(curve_figure, svg=Markup(curve_figure["svg"]))
    return {
        "recorded": True, "command": record.command, "file": name,
        "sha256": item.sha256 if item else "",
        "template": (f"Run by certkit {record.certkit} on gear unit {record.template.gear} of "
                     f"{record.template.spec} (content fingerprint {record.template.sha256}"
                     + ("; it matches this campaign's spec)." if record.template.sha256 == now
                        else f"; this campaign's spec now has {now}: the record was made "
                             f"from another version of it).")
                     + (" Its diagnosis code (fingerprint of the simulation and diagnosis "
                        "modules) is this certkit's." if record.template.code == code
                        else " It was made by other diagnosis code than this certkit's "
                             "(other thresholds or simulation), so it describes that code: "
                             "run the command again.")),
        "settings": settings, "metrics": metrics, "verdict": verdict,
        "curve_figure": curve_figure,
        "curve": [{"ratio": f"{point.ratio:g}", "cases": str(point.cases),
                   "top1": percent(point.top1), "shrink": percent(point.median_shrink)}
                  for point in record.curve],
        "confusion": {"named": list(confusion.named),
                      "rows": [{"truth": truth, "cells": [str(n) for n in row]}
                               for truth, row in zip(confusion.truths, confusion.counts)]},
        "cases": str(len(record.cases)) if record.cases else "not listed"}


def _gap_view(evidence, campaign, units) -> dict:
    """The sim-to-real gap section: per gear unit where, which and how far; the blind check."""
    method = _gap_method(units)
    blind = _blind_view(campaign)
    if evidence is None or evidence.calibration is None:
        note = ("The gap diagnosis was not run for this report (the drop model was not run)."
                if evidence is None else evidence.note)
        return {"available": False, "note": note, "notes": [], "gears": [], "blind": blind,
                "time_unit": units.time, **method}
    from certkit.evidence.figures import gap_heatmap, gap_overlay
    from certkit.gap.holdout import MIDDLE_FROM

    gears = []
    for gear_id, gap in evidence.gap.items():
        diagnosis = gap.diagnosis
        answer = " and ".join(diagnosis.answer)
        finite = [c.normalised for c in gap.before.cells if math.isfinite(c.normalised)]
        top = max(finite) if finite else None
        figures = [gap_heatmap(
            gap.before, f"{gear_id}: residual map of the calibrated nominal model",
            "Residual RMS over the channel's RMS over the whole run, per channel and phase "
            "(rows) and run (columns), in %. Training runs were fitted; held-out runs were "
            "not.", top)]
        for run_id in gap.held_out:
            figures.append(gap_overlay(
                gear_id, run_id, gap.before.records[run_id],
                gap.after.records[run_id] if gap.after else None, gap.before.phases[run_id],
                answer or None, units, window=_overlay_window(gap.before, run_id),
                origin=_origins(campaign.spec).get(run_id, "measured")))
        remaining = None
        if gap.after is not None:
            remaining = gap_heatmap(
                gap.after, f"{gear_id}: residual map remaining with {answer}",
                "The same statistics with the named effect(s) refitted on the training runs; "
                "the same colour scale as the map before, so the two compare.", top)
        figures = [dict(f, svg=Markup(f["svg"])) for f in figures]
        gears.append({
            "id": gear_id, "training": ", ".join(gap.training),
            "held_out": ", ".join(gap.held_out),
            "split": ("declared in the spec (model.gap.held_out)" if gap.declared else
                      f"the default (every drop at the highest drop height held out, and at "
                      f"the middle one from {MIDDLE_FROM} heights up)"),
            "calibration_cost": f"{gap.before.calibration.fit.cost:.4g}",
            "largest": _gap_largest(gap.before, units),
            "heatmap": figures[0], "overlays": figures[1:],
            "cells": _gap_cells(gap.before, gap.after, units),
            "steps": _gap_steps(gap, units), "statement": diagnosis.statement,
            "shrink": _gap_shrink(gap, units),
            "remaining": dict(remaining, svg=Markup(remaining["svg"])) if remaining else None,
            "remaining_largest": _lower_first(f"With {answer} refitted, ",
                                              _gap_largest(gap.after, units))
            if gap.after else "",
            "remaining_note": "" if gap.after else
            "No effect was named, so nothing was added and the residual map above is what "
            "remains."})
    notes = list(evidence.gap_notes) or ([] if gears else ["No gear unit was diagnosed."])
    return {"available": True, "note": evidence.note, "notes": notes,
            "gears": gears, "blind": blind, "time_unit": units.time, **method}


def _lower_first(prefix: str, sentence: str) -> str:
    return prefix + sentence[:1].lower() + sentence[1:]


def _overlay_window(gap_map, run_id: str) -> float:
    """From touchdown to twice the start of the last phase drawn (at least 0.25 s): every
    phase boundary of the run is in view."""
    record = gap_map.records[run_id]
    touchdown = float(record.time[record.after][0])
    last = max((float(record.time[p.start]) - touchdown for p in gap_map.phases[run_id]),
               default=0.0)
    return min(float(record.time[-1]) - touchdown, max(0.25, 2.0 * last))


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


# --------------------------------------------------------------------------- results.json and CSV
def _finite(value):
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError("internal error: a non-finite number reached the results")
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value


def _gap_results(model, campaign) -> dict:
    """results.json's gap part: per gear unit where, which and how far (SI), the thresholds
    applied, the units not diagnosed and why, and the blind check's metrics."""
    from certkit.gap.diagnosis import THRESHOLDS, gap_document

    record = campaign.blind_check
    blind = None
    if record is not None:
        blind = {"file": campaign.spec.model.gap.blind_check, "command": record.command,
                 "template": record.template.model_dump(),
                 "metrics": {key: dict(metric.model_dump(), met=metric.judged)
                             for key, metric in record.metrics.items()}}
    return {"thresholds": THRESHOLDS, "notes": list(model.gap_notes),
            "gear_units": [gap_document(g) for g in model.gap.values()],
            "blind_check": blind}


def results_document(assessment: Assessment, record: dict, model=None) -> dict:
    """Every computed number with its SI unit, source and inputs."""
    spec = assessment.campaign.spec
    model_part = None
    if model is not None:
        from certkit.physics.calibration import calibration_document
        from certkit.ident.protocol import identification_document

        model_part = {"note": model.note, "synthetic_runs": list(model.synthetic_runs),
                      "calibration": (calibration_document(model.calibration)
                                      if model.calibration is not None else None),
                      "identification": identification_document(model.identification),
                      "gap": _gap_results(model, assessment.campaign)}
    return _finite({
        "format": RESULTS_FORMAT,
        "campaign": {"id": spec.campaign.id, "title": spec.campaign.title,
                     "report_number": spec.document.report_number,
                     "revision": spec.document.revision, "date": spec.document.date.isoformat()},
        "outcome": assessment.outcome,
        "outcome_reasons": assessment.outcome_reasons(),
        "counts": assessment.counts(),
        "finding_counts": assessment.finding_counts(),
        "design": [v.as_dict() for v in assessment.design.values()],
        "requirement_sets": [{"id": b.rules.id, "title": b.rules.title,
                              "edition": b.rules.edition, "stated_edition": b.entry.edition,
                              "status": b.rules.status, "status_note": b.rules.status_note,
                              "values": [v.as_dict() for v in b.values.values()]}
                             for b in assessment.basis],
        "runs": [{"id": r.run.id, "test_type": r.run.test_type,
                  "values": [v.as_dict() for v in r.values.values()],
                  "gears": [{"gear": g.gear_id, "basis": g.basis,
                             "values": [v.as_dict() for v in g.values.values()]}
                            for g in r.gears]} for r in assessment.runs],
        "verdicts": [v.as_dict() for v in assessment.verdicts],
        "findings": [f.as_dict() for f in assessment.findings],
        "comparisons": [c.as_dict() for c in assessment.comparisons],
        "equations": EQUATIONS,
        "model": model_part,
        "provenance": record,
    })


def _write_csv(path: Path, header: list[str], rows: list[list]) -> None:
    with path.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(header)
        for row in rows:
            writer.writerow(["" if cell is None else repr(cell) if isinstance(cell, float)
                             else cell for cell in row])


def write_tables(assessment: Assessment, folder: Path, model=None) -> None:
    """tables/*.csv: the audit tables a CI job or a spreadsheet reads."""
    folder.mkdir()
    calibration = model.calibration if model is not None else None
    _write_csv(folder / "model.csv",
               ["gear", "run", "channel", "unit", "rmse_nominal", "rmse_calibrated"],
               [[g.gear_id, e.run, e.channel, e.unit, e.nominal, e.calibrated]
                for g in (calibration.gears if calibration else ()) for e in g.errors])
    identification = model.identification if model is not None else None
    _write_csv(folder / "identification.csv",
               ["gear", "model", "protocol", "output", "run", "rmse_mm", "nrmse", "fit_percent",
                "max_error_mm"],
               [[g.gear_id, x.model, x.protocol, x.output, x.run, x.rmse, x.nrmse, x.fit,
                 x.max_error] for g in (identification.gears if identification else ())
                for x in g.scores])
    gaps = list(model.gap.values()) if model is not None else []
    channel_units: dict[str, str] = {}
    if gaps:   # (only then: calibration loads the compiled model, a second of import)
        from certkit.physics.calibration import CHANNEL_UNITS as channel_units
    rows = []
    for gap in gaps:
        later = ({(c.run, c.channel, c.phase): c for c in gap.after.cells}
                 if gap.after is not None else {})
        for c in gap.before.cells:
            a = later.get((c.run, c.channel, c.phase))
            rows.append([gap.gear_id, c.run, "held out" if c.run in gap.held_out else "training",
                         c.channel, c.phase, c.samples, channel_units[c.channel], c.scale,
                         c.rms, c.bias, c.lag, a.rms if a else None, a.bias if a else None,
                         a.lag if a else None])
    _write_csv(folder / "gap.csv",
               ["gear", "run", "role", "channel", "phase", "samples", "unit", "channel_rms",
                "rms_before", "bias_before", "lag_before_s", "rms_after", "bias_after",
                "lag_after_s"], rows)
    _write_csv(folder / "gap_shrink.csv",
               ["gear", "run", "channel", "phase", "samples", "unit", "rmse_before",
                "rmse_after", "shrink_percent"],
               [[gap.gear_id, e.run, e.channel, e.phase, e.samples, channel_units[e.channel],
                 e.before, e.after, None if e.shrink is None else 100.0 * e.shrink]
                for gap in gaps for e in gap.held_out_errors])
    _write_csv(folder / "verdicts.csv",
               ["id", "requirement_set", "criterion", "clause", "run", "gear", "verdict", "value",
                "limit", "margin", "unit", "comparison", "to_confirm", "reason"],
               [[v.id, v.requirement_set, v.criterion, v.clause, v.run, v.gear, v.verdict,
                 v.value, v.limit, v.margin, v.unit, v.comparison, v.to_confirm, v.reason]
                for v in assessment.verdicts])
    _write_csv(folder / "findings.csv", ["id", "check", "severity", "run", "gear", "message"],
               [[f.id, f.check, f.severity, f.run, f.gear, f.message]
                for f in assessment.findings])
    rows = []
    for value in assessment.design.values():
        rows.append(["design", None, None, value])
    for item in assessment.basis:
        for value in item.values.values():
            rows.append([item.rules.id, None, None, value])
    for run in assessment.runs:
        for value in run.values.values():
            rows.append(["run", run.run.id, None, value])
        for gear in run.gears:
            for value in gear.values.values():
                rows.append(["gear", run.run.id, gear.gear_id, value])
    _write_csv(folder / "values.csv",
               ["scope", "run", "gear", "key", "label", "value", "unit", "source", "formula",
                "note"],
               [[scope, run, gear, v.key, v.label, v.value, v.unit, v.source, v.formula, v.note]
                for scope, run, gear, v in rows])
    _write_csv(folder / "comparisons.csv",
               ["run", "gear", "quantity", "reported_text", "reported_si", "recomputed_si",
                "unit", "difference_si", "tolerance_si", "agrees", "basis"],
               [[c.run, c.gear, c.quantity, c.reported_text, c.reported, c.recomputed, c.unit,
                 c.difference, c.tolerance, c.agrees, c.basis] for c in assessment.comparisons])


# --------------------------------------------------------------------------- HTML and PDF
def _environment() -> Environment:
    return Environment(loader=FileSystemLoader(str(templates_dir())),
                       autoescape=select_autoescape(default=True, default_for_string=True),
                       undefined=StrictUndefined, trim_blocks=True, lstrip_blocks=True,
                       keep_trailing_newline=True)


def render_html(view: dict) -> str:
    """The self-contained report HTML (inline CSS and SVG, nothing fetched)."""
    css = (templates_dir() / "report.css").read_text(encoding="utf-8")
    return _environment().get_template("report.html.j2").render(view=view, css=Markup(css))


class _LocalOnlyFetcher:
    """URL fetcher for WeasyPrint that serves only the templates and the font folder."""

    def __init__(self, roots: list[Path]):
        from weasyprint.urls import URLFetcher
        self._fetcher = URLFetcher(allowed_protocols=("file", "data"))
        self._fail_on_errors = True
        self.roots = [root.resolve() for root in roots]

    def __call__(self, url: str):
        from urllib.parse import unquote, urlparse

        from weasyprint.urls import FatalURLFetchingError
        parsed = urlparse(url)
        if parsed.scheme == "file":
            path = Path(unquote(parsed.path)).resolve()
            if not any(path.is_relative_to(root) for root in self.roots):
                raise FatalURLFetchingError(f"refused to fetch {url}: outside the report's folders")
        elif parsed.scheme != "data":
            raise FatalURLFetchingError(f"refused to fetch {url}: only local files are used")
        return self._fetcher.fetch(url)


def _font_css() -> str:
    faces = []
    for name, weight, style in (("DejaVuSans.ttf", "normal", "normal"),
                                ("DejaVuSans-Bold.ttf", "bold", "normal"),
                                ("DejaVuSans-Oblique.ttf", "normal", "italic"),
                                ("DejaVuSansMono.ttf", "normal", "normal")):
        family = "DejaVu Sans Mono" if "Mono" in name else "DejaVu Sans"
        faces.append(f"@font-face {{ font-family: '{family}'; src: url('{(fonts_dir() / name).as_uri()}');"
                     f" font-weight: {weight}; font-style: {style}; }}")
    return "\n".join(faces)


@contextlib.contextmanager
def _source_date_epoch(epoch: int):
    """fontTools stamps subset fonts with the current time unless SOURCE_DATE_EPOCH is set."""
    previous = os.environ.get("SOURCE_DATE_EPOCH")
    os.environ["SOURCE_DATE_EPOCH"] = str(epoch)
    try:
        yield
    finally:
        if previous is None:
            del os.environ["SOURCE_DATE_EPOCH"]
        else:
            os.environ["SOURCE_DATE_EPOCH"] = previous


def render_pdf(html: str, attachments: list[tuple[str, bytes, str]], date: dt.date) -> bytes:
    """PDF/A-3b of the report with ``attachments`` (name, bytes, relationship) embedded."""
    from weasyprint import CSS, HTML, Attachment
    from weasyprint.text.fonts import FontConfiguration

    stamp = dt.datetime(date.year, date.month, date.day, tzinfo=dt.timezone.utc)
    fetcher = _LocalOnlyFetcher([templates_dir(), fonts_dir()])
    fonts = FontConfiguration()
    files = [Attachment(file_obj=io.BytesIO(content), name=name, created=stamp, modified=stamp,
                        relationship=relationship, url_fetcher=fetcher)
             for name, content, relationship in attachments]
    document = HTML(string=html, base_url=str(templates_dir()) + "/", url_fetcher=fetcher)
    with _source_date_epoch(int(stamp.timestamp())):
        return document.write_pdf(
            stylesheets=[CSS(string=_font_css(), font_config=fonts, url_fetcher=fetcher)],
            font_config=fonts, pdf_variant="pdf/a-3b", attachments=files,
            uncompressed_pdf=False)


# --------------------------------------------------------------------------- writing
def results_json(assessment: Assessment, model=None, record: dict | None = None) -> bytes:
    """results.json as written: the results document, with its provenance (``record``,
    made here when not given), as UTF-8."""
    record = provenance(assessment.campaign.inputs) if record is None else record
    results = results_document(assessment, record, model)
    return (json.dumps(results, indent=2, ensure_ascii=False, allow_nan=False)
            + "\n").encode("utf-8")


def _write_outputs(assessment: Assessment, folder: Path, progress, model) -> None:
    campaign = assessment.campaign
    record = provenance(campaign.inputs)
    progress("computing results")
    results_bytes = results_json(assessment, model, record)
    (folder / "results.json").write_bytes(results_bytes)
    write_tables(assessment, folder / "tables", model)
    progress("drawing figures and laying out HTML")
    html = render_html(build_view(assessment, record, model))
    (folder / "report.html").write_text(html, encoding="utf-8")
    progress("writing PDF/A-3b")
    attachments = [(f"inputs/{item.name}", item.path.read_bytes(), "Source")
                   for item in campaign.inputs]
    attachments.append(("results.json", results_bytes, "Data"))
    (folder / "report.pdf").write_bytes(render_pdf(html, attachments, campaign.spec.document.date))


#: What render_report writes; an existing folder holding anything else is not replaced.
TABLES = ("verdicts", "findings", "values", "comparisons", "model", "identification", "gap",
          "gap_shrink")
REPORT_FILES = {"report.html", "report.pdf", "results.json"} | {f"tables/{name}.csv"
                                                                for name in TABLES}


def render_report(assessment: Assessment, out_dir: str | Path, progress=None,
                  model=None) -> Path:
    """Write report.html, report.pdf, results.json and tables/*.csv into ``out_dir``.

    ``model``: the governing-equation model evidence
    (:func:`certkit.evidence.model_evidence.model_evidence`); without it the section says the model
    was not run.

    Everything is written into a temporary sibling folder and moved into place at
    the end; on any failure (or interruption) nothing is left behind and an
    existing ``out_dir`` is untouched.  A target that holds the campaign's inputs,
    the current folder or files certkit did not write is refused (CertkitInputError).
    """
    progress = progress or (lambda message: None)
    inputs = [item.path for item in assessment.campaign.inputs]
    with staged_folder(out_dir, inputs, REPORT_FILES) as staging:
        _write_outputs(assessment, staging, progress, model)
    return Path(out_dir)
