"""The machine-readable evidence: results.json (``format: certkit-results/1``, SI and full
precision) and the CSV tables, from the assessment and the model evidence.

The model stage's documents are imported where a model evidence is written: a report without
the drop model does not load that stage (about 0.66 s of start-up, ``python -X importtime``).
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

from certkit.compliance.assessment import Assessment
from certkit.compliance.equations import EQUATIONS
from certkit.compliance.verdict_uncertainty import SEED, value_key
from certkit.evidence.provenance import provenance
from certkit.results import RESULTS_FORMAT


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
    sealed = campaign.sealed_blind_check
    if sealed is not None:
        sealed = {"file": campaign.spec.model.gap.sealed_blind_check, "command": sealed.command,
                  "battery": sealed.battery, "template": sealed.template.model_dump(),
                  "metrics": {key: dict(metric.model_dump(), met=metric.judged)
                              for key, metric in sealed.metrics.items()}}
    if blind is not None:
        blind["battery"] = record.battery
    return {"thresholds": THRESHOLDS, "notes": list(model.gap_notes),
            "gear_units": [gap_document(g) for g in model.gap.values()],
            "blind_check": blind, "sealed_blind_check": sealed}


def _values(found, values: dict, scope: str, *where) -> list[dict]:
    """Each value as a dict, with its standard uncertainty from the stated inputs (SI, the
    value's unit) and the inputs it depends on whose uncertainty is not stated."""
    out = []
    for key, value in values.items():
        item = value.as_dict()
        if value.value is not None and found is not None:
            u, missing = found.values.get(value_key(scope, *where, key), (None, ()))
            item["standard_uncertainty"] = u
            item["uncertainty_not_stated"] = list(missing)
        out.append(item)
    return out


def uncertainty_document(found) -> dict | None:
    """The decision rule, the Monte Carlo settings and every input of the budgets."""
    if found is None:
        return None
    return {"decision_rule": found.rule, "guard_factor": found.guard_factor,
            "required_probability": found.required, "coverage_probability": found.coverage,
            "monte_carlo": {"trials": found.trials, "random_state": SEED,
                            "method": "JCGM 101:2008 §7, probabilistically symmetric "
                                      "interval (§7.7); GUM validated per §8.2"},
            "gum": "JCGM 100:2008 §5.1.2, sensitivities by ±u(x_i) through the engine "
                   "(§5.1.3 note 2)",
            "inputs": [{"key": s.key, "label": s.label, "stated": s.input is not None,
                        "standard_uncertainty": None if s.input is None else s.input.standard,
                        "unit": s.unit,
                        "relative": s.relative, "distribution": None if s.input is None
                        else s.input.distribution, "stated_as": s.stated_as,
                        "basis": s.basis, "source": s.origin}
                       for s in found.sources],
            "not_stated_but_needed": [s.label for s in found.unstated]}


def results_document(assessment: Assessment, record: dict, model=None) -> dict:
    """Every computed number with its SI unit, source and inputs."""
    spec = assessment.campaign.spec
    found = assessment.uncertainty
    model_part = None
    if model is not None:
        from certkit.gear_identification import identification_document
        from certkit.physics.calibration import calibration_document

        model_part = {"note": model.note, "synthetic_runs": list(model.synthetic_runs),
                      # stages not computed for a gear unit: why, and what to change
                      "failures": [{"stage": f.stage, "gear_unit": f.gear, "reason": f.reason,
                                    "remedy": f.remedy, "certkit_error": f.internal}
                                   for f in model.failures],
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
        "design": _values(found, assessment.design, "design"),
        "requirement_sets": [{"id": b.rules.id, "title": b.rules.title,
                              "edition": b.rules.edition, "stated_edition": b.entry.edition,
                              "status": b.rules.status, "status_note": b.rules.status_note,
                              "values": _values(found, b.values, "basis", b.rules.id)}
                             for b in assessment.basis],
        "runs": [{"id": r.run.id, "test_type": r.run.test_type,
                  "values": _values(found, r.values, "run", r.run.id),
                  "gears": [{"gear": g.gear_id, "basis": g.basis,
                             "values": _values(found, g.values, "gear", r.run.id, g.gear_id)}
                            for g in r.gears]} for r in assessment.runs],
        "verdicts": [v.as_dict() for v in assessment.verdicts],
        "uncertainty": uncertainty_document(found),
        "findings": [f.as_dict() for f in assessment.findings],
        "not_checked": [u.as_dict() for u in assessment.unchecked],
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


# --------------------------------------------------------------------------- writing
def results_json(assessment: Assessment, model=None, record: dict | None = None) -> bytes:
    """results.json as written: the results document, with its provenance (``record``,
    made here when not given), as UTF-8."""
    record = provenance(assessment.campaign.inputs) if record is None else record
    results = results_document(assessment, record, model)
    return (json.dumps(results, indent=2, ensure_ascii=False, allow_nan=False)
            + "\n").encode("utf-8")
