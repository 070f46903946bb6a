"""The report's view of the sim-to-real gap (section 11): the gap map, each step of the
diagnosis as it recorded its decisions, the shrink on the held-out drops and the blind
check's record.

The gap stage and matplotlib are imported inside the functions that draw on them: a report
made without the drop model never loads them (about 0.66 s and 0.26 s of start-up,
``python -X importtime``).
"""

from __future__ import annotations

import math

from markupsafe import Markup

from certkit.display import magnitude, number, percent, pretty, to_display, with_unit
from certkit.evidence.methods import gap_method
from certkit.evidence.model_view import origins
from certkit.evidence.sections import BlindSection, GapSection
from certkit.physics.drops import MIDDLE_FROM
from certkit.spec.blind_record import METRICS, code_fingerprint, template_fingerprint
from certkit.spec.rundata import CHANNEL_LABELS


# --------------------------------------------------------------------------- the gap section
def _channel_kind(channel: str) -> str:
    return "force" if channel == "load" else "length"


def _gap_cells(before, after, units) -> list[dict]:

    later = {(c.run, c.channel, c.phase): c for c in after.cells} if after else {}
    rows = []
    for cell in before.cells:
        kind = _channel_kind(cell.channel)
        remaining = later.get((cell.run, cell.channel, cell.phase))
        rows.append({
            "run": cell.run, "role": "held out" if cell.run in before.held_out else "training",
            "channel": CHANNEL_LABELS[cell.channel], "phase": cell.phase,
            "samples": str(cell.samples), "unit": getattr(units, kind),
            "rms": magnitude(cell.rms, kind, units), "bias": magnitude(cell.bias, kind, units),
            "lag": magnitude(cell.lag, "time", units, 3),
            "normalised": percent(cell.normalised),
            "rms_after": magnitude(remaining.rms, kind, units) if remaining else "—",
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
    from certkit.gap.selection import CANDIDATES, TIE_COST

    diagnosis = gap.diagnosis
    sizes = {c.key: c.unit_size for c in CANDIDATES}
    steps = []
    for index, (attribution, fits) in enumerate(diagnosis.steps):
        beat = diagnosis.step_costs[index]
        profiles = attribution.profiles or {}
        scores = []
        for score, decision in zip(attribution.scores, attribution.decisions):
            profile = profiles.get(score.name)
            scores.append({"effect": score.name, "statistic": number(score.statistic),
                           "explained": f"{score.explained:.3g}", "status": decision.status,
                           "profile": "—" if not profile else
                           f"{number(profile[1])} at strength {profile[0]:g}"})
        pair = ""
        if len(attribution.scores) >= 2:
            a, b = attribution.scores[0].name, attribution.scores[1].name
            cosine = attribution.confusability.get((a, b), attribution.confusability.get((b, a)))
            if cosine is not None:
                pair = (f"Confusability of the leading pair, {a} and {b}: the cosine of their "
                        f"projected signatures is {cosine:.3f} (1: the same signature once "
                        f"re-tuning is projected out; two effects whose refitted training costs "
                        f"lie within a ratio of {TIE_COST:g} count as indistinguishable with "
                        f"these channels).")
        refits = []
        for fit, decision in zip(fits, diagnosis.refit_decisions[index]):
            strengths = "; ".join(
                f"{name}: {value:.4g} ± "
                f"{(f'{error:.2g}' if math.isfinite(error) else 'not determined')} "
                f"(strength 1: {sizes.get(name, 'as defined by the candidate')})"
                for name, value, error in zip(fit.effects, fit.strengths, fit.strength_errors))
            checks = gap.refit_held_out.get((index, fit.effects), {})
            held = "; ".join(f"{run} {CHANNEL_LABELS[channel]} "
                             f"{magnitude(value, _channel_kind(channel), units)} "
                             f"{getattr(units, _channel_kind(channel))}"
                             for (run, channel), value in checks.items())
            refits.append({"effects": " + ".join(fit.effects), "strengths": strengths,
                           "cost": f"{fit.training_cost:.4g}",
                           "change": percent(fit.training_cost / beat - 1, signed=True)
                           if beat else "—",
                           "outcome": decision.status, "held_out": held or "—"})
        title = ("Step 1: candidates against the calibrated nominal model" if index == 0 else
                 f"Step {index + 1}: candidates against the model with "
                 f"{' and '.join(diagnosis.answer[:index])}")
        steps.append({"title": title, "beat": f"{beat:.4g}", "scores": scores, "pair": pair,
                      "refits": refits,
                      "no_refit": attribution.no_refit})
    return steps


def _gap_shrink(gap, units) -> list[dict]:

    rows = []
    for error in gap.held_out_errors:
        kind = _channel_kind(error.channel)
        shrink = error.shrink
        rows.append({"run": error.run, "channel": CHANNEL_LABELS[error.channel],
                     "phase": error.phase, "unit": getattr(units, kind),
                     "samples": str(error.samples), "before": magnitude(error.before, kind, units),
                     "after": magnitude(error.after, kind, units),
                     "shrink": "—" if shrink is None else
                     percent(shrink) + (" (worse)" if shrink < 0 else "")})
    return rows


def _blind_view(campaign, units) -> dict:
    """The blind check's record (model.gap.blind_check) in words and tables, or how to make
    one."""

    command = f"certkit gap --blind-check {campaign.spec_path.name} -o DIR"
    record = campaign.blind_check
    if record is None:
        return BlindSection(**{"recorded": False, "command": command,
                "absent": "The blind check has not been recorded for this campaign, so this "
                          "report gives no measured evidence of how often the diagnosis names "
                          "the right effect. To record it, run the command below and name the "
                          "JSON file it writes in the spec's model.gap.blind_check."})
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
    return BlindSection(**{
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
        "truths": ("The withheld truths were simulated by " + record.truths + "."
                   if record.truths else
                   "The withheld truths were simulated by certkit's own drop model, each "
                   "effect in a form other than its candidate's where the library allows: "
                   "the figures describe the diagnosis on physics it wrote itself, not on "
                   "a real gear's."),
        "settings": settings, "metrics": metrics, "verdict": verdict,
        "curve_figure": curve_figure,
        "curve": [{"ratio": f"{point.ratio:g}", "cases": str(point.cases),
                   "top1": percent(point.top1), "shrink": percent(point.median_shrink)}
                  for point in record.curve],
        "confusion": {"named": list(confusion.named),
                      "rows": [{"truth": truth, "cells": [str(n) for n in row]}
                               for truth, row in zip(confusion.truths, confusion.counts)]},
        "cases": str(len(record.cases)) if record.cases else "not listed",
        "forms": [_form_row(row, units) for row in record.forms]})


def _form_row(row, units) -> dict:
    """One truth form of an independent battery, in words for the by-form table."""
    peak = ("—" if row.median_peak_load_change_N is None else
            f"{with_unit(row.median_peak_load_change_N, 'force', units)} "
            f"({percent(row.median_peak_load_change_share)})")
    return {"label": row.label,
            "effect": row.effect or "outside the library (abstaining is right)",
            "all": f"{row.right} of {row.cases}",
            "scored": f"{row.right_scored} of {row.scored}", "peak": peak}


def gap_view(evidence, campaign, units) -> GapSection:
    """The sim-to-real gap section: per gear unit where, which and how far; the blind check."""
    method = gap_method(units)
    blind = _blind_view(campaign, units)
    if evidence is None or evidence.calibration is None:
        note = ("The gap diagnosis was not run for this report (the drop model was not run)."
                if evidence is None else evidence.note)
        return GapSection(**{"available": False, "note": note, "notes": [], "gears": [],
                             "blind": blind, "time_unit": units.time, **method})
    from certkit.evidence.figures import gap_heatmap, gap_overlay, missing_force_figure

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
                origin=origins(campaign.spec).get(run_id, "measured")))
        remaining = None
        if gap.after is not None:
            remaining = gap_heatmap(
                gap.after, f"{gear_id}: residual map remaining with {answer}",
                "The same statistics with the named effect(s) refitted on the training runs; "
                "the same colour scale as the map before, so the two compare.", top)
        figures = [dict(f, svg=Markup(f["svg"])) for f in figures]
        missing = None
        if gap.missing:
            missing = missing_force_figure(gear_id, gap.missing, units, origins(campaign.spec))
            missing = dict(missing, svg=Markup(missing["svg"]))
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
            "missing": missing, "signatures": _signatures(diagnosis),
            "shrink": _gap_shrink(gap, units),
            "remaining": dict(remaining, svg=Markup(remaining["svg"])) if remaining else None,
            "remaining_largest": _lower_first(f"With {answer} refitted, ",
                                              _gap_largest(gap.after, units))
            if gap.after else "",
            "remaining_note": "" if gap.after else
            "No effect was named, so nothing was added and the residual map above is what "
            "remains."})
    notes = list(evidence.gap_notes) or ([] if gears else ["No gear unit was diagnosed."])
    return GapSection(**{"available": True, "note": evidence.note, "notes": notes,
                         "gears": gears, "blind": blind, "time_unit": units.time, **method})


def _signatures(diagnosis) -> list[dict]:
    """The missing force's shapes at each step, as the diagnosis recorded them."""
    out = []
    for index, step in enumerate(diagnosis.evidence):
        for found in step:
            out.append({"step": index + 1, "force": found.force, "shape": found.shape,
                        "marks": found.effect or "— (absorbed by re-tuning)",
                        "coefficient": f"{found.coefficient:.4g} {found.unit}",
                        "share": percent(found.share, 1), "seen": "yes" if found.seen else ""})
    return out


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
