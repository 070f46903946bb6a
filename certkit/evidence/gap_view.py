"""The report's view of the sim-to-real gap (appendix C): the gap map, each step of the
diagnosis as it recorded its decisions, the shrink on the held-out drops and the blind
check's record.

The gap stage and matplotlib are imported inside the functions that draw on them: a report
made without the drop model never loads them (about 0.66 s and 0.26 s of start-up,
``python -X importtime``).
"""

from __future__ import annotations

import math

from markupsafe import Markup

from certkit.display import magnitude, number, parameter, percent, with_unit
from certkit.evidence.methods import gap_method, unit_size
from certkit.evidence.model_view import origins, starts_words
from certkit.evidence.sections import BlindSection, GapSection
from certkit.physics.drops import MIDDLE_FROM
from certkit.gap.code import code_fingerprint, differing_files
from certkit.spec.blind_record import METRICS, template_fingerprint
from certkit.spec.rundata import CHANNEL_LABELS


# --------------------------------------------------------------------------- the gap section
def _channel_kind(channel: str) -> str:
    return "force" if channel == "load" else "length"


def largest_disagreement(cell, units, scope: str = "") -> str:
    """A residual map's largest cell in words, in the display units (report and terminal);
    ``scope`` says which runs it is the largest of ("on the training runs")."""
    if cell is None:
        return "No residual to map."
    kind = _channel_kind(cell.channel)
    lag = (f", the model {'late' if cell.lag > 0 else 'early'} by "
           f"{with_unit(abs(cell.lag), 'time', units)}" if abs(cell.lag) >= 0.5e-3 else "")
    where = f" {scope}" if scope else ""
    return (f"The largest disagreement{where} is in the {CHANNEL_LABELS[cell.channel]} "
            f"during {cell.phase} of run {cell.run}: RMS {with_unit(cell.rms, kind, units)} "
            f"({percent(cell.normalised)} of the channel's RMS), bias "
            f"{'+' if cell.bias > 0 else ''}{with_unit(cell.bias, kind, units)}{lag}.")


def _gap_largest(gap_map, units) -> str:
    """The largest disagreement of the training runs and that of the held-out runs, in
    words, in display units, with the bands of the first: every run the map beside it
    shows is covered."""
    from certkit.gap.residuals import BANDS, largest

    if gap_map.largest is None:
        return "No residual to map."
    cell = gap_map.largest
    text = largest_disagreement(cell, units, "on the training runs (fitted)")
    held = largest([c for c in gap_map.cells if c.run in gap_map.held_out])
    if held is not None:
        text += " " + largest_disagreement(held, units, "on the held-out runs (not fitted)")
    shares = gap_map.bands.get((cell.run, cell.channel))
    if shares:
        parts = [f"{percent(shares[name], 0)} in the {name} band"
                 + (f" ({low:g}-{high:g} Hz)" if math.isfinite(high) else "")
                 for name, low, high in BANDS]
        text += (f" Of the {CHANNEL_LABELS[cell.channel]} residual's energy in run {cell.run} "
                 f"from touchdown, " + ", ".join(parts[:-1]) + " and " + parts[-1] + ".")
    return text


def _gap_steps(gap, units) -> list[dict]:
    from certkit.gap.selection import CANDIDATES, TIE_COST
    from certkit.gap.statements import decision_words

    diagnosis = gap.diagnosis
    sizes = {c.key: unit_size(c, units) for c in CANDIDATES}
    steps = []
    for index, (attribution, fits) in enumerate(diagnosis.steps):
        beat = diagnosis.step_costs[index]
        profiles = attribution.profiles or {}
        scores, alike = [], {}
        for score, decision in zip(attribution.scores, attribution.decisions):
            if score.name not in attribution.relevant:
                # forms not relevant for the same reason share a row (every form's numbers
                # are in results.json)
                alike.setdefault(decision_words(decision), []).append(score)
                continue
            profile = profiles.get(score.name)
            scores.append({"effect": score.name, "statistic": number(score.statistic),
                           "explained": number(score.explained, 3),
                           "status": decision_words(decision),
                           "profile": "—" if not profile else
                           f"{number(profile[1])} at strength {number(profile[0], 3)}"})
        for status, group in alike.items():
            bound = "" if len(group) == 1 else "≤ "
            profile = profiles.get(group[0].name) if len(group) == 1 else None
            scores.append({"effect": "; ".join(g.name for g in group),
                           "statistic": bound + number(max(g.statistic for g in group)),
                           "explained": bound + number(max(g.explained for g in group), 3),
                           "profile": "—" if not profile else
                           f"{number(profile[1])} at strength {number(profile[0], 3)}",
                           "status": status})
        scores += [{"effect": skipped.name, "statistic": "—", "explained": "—",
                    "profile": "—", "status": decision_words(skipped)}
                   for skipped in attribution.skipped]
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
                f"{name}: {number(value)} ± "
                f"{(number(error, 2) if math.isfinite(error) else 'not determined')} "
                f"(strength 1: {sizes.get(name, 'as defined by the candidate')})"
                for name, value, error in zip(fit.effects, fit.strengths, fit.strength_errors))
            checks = gap.refit_held_out.get((index, fit.effects), {})
            held = "; ".join(f"{run} {CHANNEL_LABELS[channel]} "
                             f"{magnitude(value, _channel_kind(channel), units)} "
                             f"{getattr(units, _channel_kind(channel))}"
                             for (run, channel), value in checks.items())
            refits.append({"effects": " + ".join(fit.effects), "strengths": strengths,
                           "cost": number(fit.training_cost),
                           "change": percent(fit.training_cost / beat - 1, signed=True)
                           if beat else "—",
                           "outcome": decision_words(decision), "held_out": held or "—"})
        title = ("Step 1: candidates against the calibrated bare model" if index == 0 else
                 f"Step {index + 1}: candidates against the model with "
                 f"{' and '.join(diagnosis.answer[:index])}")
        steps.append({"title": title, "beat": number(beat), "scores": scores, "pair": pair,
                      "refits": refits,
                      "no_refit": decision_words(attribution.no_refit)
                      if attribution.no_refit else ""})
    return steps


def _gap_shrink(gap, units) -> list[dict]:

    from certkit.gap.diagnosis import WHOLE

    rows = []
    for error in gap.held_out_errors:
        if error.phase != WHOLE:
            continue
        kind = _channel_kind(error.channel)
        shrink = error.shrink
        rows.append({"run": error.run, "channel": CHANNEL_LABELS[error.channel],
                     "phase": error.phase, "unit": getattr(units, kind),
                     "samples": str(error.samples), "before": magnitude(error.before, kind, units),
                     "after": magnitude(error.after, kind, units),
                     "shrink": "—" if shrink is None else
                     percent(shrink) + (" (worse)" if shrink < 0 else "")})
    return rows


def _battery_words(battery: str | None) -> str:
    """What the record's battery means for its figures."""
    if battery == "development":
        return (" These cases are the development battery: the diagnosis's rules and "
                "thresholds were set after failures on them, so its figures are in-sample "
                "and overstate what a battery it was not tuned on finds.")
    if battery == "sealed":
        return (" These cases are a sealed battery, drawn from ranges never run before and "
                "run once: its figures are held out.")
    return (" The record does not say whether its cases were a development or a sealed "
            "battery: read its figures as in-sample.")


#: What a reader can do about a record made by other diagnosis code: run it again, or (a
#: sealed set, run once per release) wait for the next sealed set.
RUN_AGAIN = "run the command again to measure this one"
DRAW_ANEW = ("a sealed set is run once, so a new sealed set, drawn for this code, will "
             "measure this one")


def _made_by(step: str, who, code: str, advice: str = RUN_AGAIN) -> str:
    """One sentence on who did a step of the blind check and whether it is this certkit's
    diagnosis code (fingerprint of the simulation and diagnosis modules); ``advice``: what
    to do when it is not."""
    commit = ""
    if who.commit:
        dirty = who.commit.endswith("-dirty")
        commit = f" at commit {who.commit[:12]}" + (
            " (with uncommitted changes in the source tree)" if dirty else "")
    when = (f" on {who.date}" if who.date else "") + commit
    sentence = f"{step} by certkit {who.certkit}{when}"
    if who.code == code:
        return sentence + ", with this certkit's diagnosis code."
    differing = differing_files(who.files)
    which = ("which files differ is not recorded" if differing is None
             else "the files that differ: " + ", ".join(differing))
    return (sentence + ", with other diagnosis code than this certkit's (" + which
            + f"), so the figures describe that code: {advice}.")



def plain_setting(value, depth: int = 0) -> str:
    """A blind-check record's setting in words for its table: a mapping "key: value; …", a
    list joined by commas (by " + " within another), an unset one (None, an empty list or
    mapping: "only" when the battery ran whole) "—"."""
    if value is None or value == [] or value == {}:
        return "—"
    if isinstance(value, dict):
        return "; ".join(f"{k}: {plain_setting(v, depth + 1)}" for k, v in value.items())
    if isinstance(value, list):
        return (" + " if depth else ", ").join(plain_setting(v, depth + 1) for v in value)
    return f"{value:g}" if isinstance(value, float) else str(value)

def _blind_view(campaign, units) -> dict:
    """The blind check's record (model.gap.blind_check) in words and tables, or how to make
    one."""

    command = (f"python benchmarks/blind_independent.py {campaign.spec_path.name} -g GEAR "
               f"-o DIR")
    record, name = campaign.blind_check, campaign.spec.model.gap.blind_check
    sealed = campaign.sealed_blind_check
    if record is None and sealed is not None:       # a sealed record alone is the record
        record, name, sealed = sealed, campaign.spec.model.gap.sealed_blind_check, None
    if record is None:
        return BlindSection(**{"recorded": False, "command": command,
                "absent": "The blind check has not been recorded for this campaign, so this "
                          "report gives no measured evidence of how often the diagnosis names "
                          "the right effect. To record it, run the command below in a checkout of "
                          "certkit's source (the battery machinery lives in its benchmarks "
                          "folder, outside the installed package; about 10 minutes on 2 "
                          "cores) and name the JSON file it writes in the spec's "
                          "model.gap.blind_check."})
    from certkit.evidence.figures import blind_curve

    now, code = template_fingerprint(campaign), code_fingerprint()
    item = _input(campaign, name)
    metrics, short = [], []
    keys = [k for k in METRICS if k in record.metrics] + [k for k in record.metrics
                                                          if k not in METRICS]
    for key in keys:
        metric = record.metrics[key]
        label, definition = METRICS.get(key, (key.replace("_", " "), "as recorded"))
        definition = record.definitions.get(key, definition)
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
    # each metric's target is in the metrics table: a record's words for them are not repeated
    settings = [(key.replace("_", " "), plain_setting(value))
                for key, value in record.settings.items() if key != "targets"]
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
                     + " " + _made_by("Its cases were run", record.cases_run_by, code)
                     + (" " + _made_by("They were scored", record.scored_by, code)
                        if record.scored_by is not None and record.scored_by != record.run_by
                        else "")),
        "truths": ("The withheld truths were simulated by " + record.truths + "."
                   + _battery_words(record.battery)
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
        "forms": [_form_row(row, units) for row in record.forms],
        **_sealed_beside(campaign, record, sealed, now, code)})


def _input(campaign, name: str):
    """The campaign's input item of a record the spec names (None if not among them)."""
    resolved = (campaign.root / name).resolve()
    return next((i for i in campaign.inputs if i.path == resolved), None)


def _measured(metric) -> str:
    """A metric's value with its count and 95 % interval, in words."""
    if metric is None:
        return "not in this record"
    value = "not measured" if metric.value is None else percent(metric.value)
    counted = (f"{metric.count} of {metric.cases}" if metric.count is not None
               else f"{metric.cases} cases")
    if metric.interval:
        low, high = metric.interval
        counted += f"; 95 % interval {percent(low)}–{percent(high)}"
    return f"{value} ({counted})"


def _sealed_beside(campaign, development, sealed, now: str, code: str) -> dict:
    """The sealed battery's figures beside the development battery's, metric by metric, and
    where the sealed record comes from ({} when the spec names no sealed record)."""
    if sealed is None:
        return {}
    name = campaign.spec.model.gap.sealed_blind_check
    item = _input(campaign, name)
    keys = [k for k in METRICS if k in development.metrics or k in sealed.metrics]
    rows = []
    for key in keys:
        label = METRICS[key][0]
        theirs = sealed.metrics.get(key)
        target = "no target" if theirs is None or theirs.target is None else \
            f"{theirs.direction} {percent(theirs.target)}"
        judged = None if theirs is None else theirs.judged
        rows.append({"label": label, "development": _measured(development.metrics.get(key)),
                     "sealed": _measured(theirs), "target": target,
                     "verdict": {True: "met", False: "NOT met", None: "—"}[judged],
                     "css": {True: "pass", False: "fail", None: ""}[judged]})
    origin = (f"Sealed record {name} (SHA-256 {item.sha256 if item else ''}), written by "
              f"{sealed.command}, on gear unit {sealed.template.gear} of "
              f"{sealed.template.spec}"
              + ("" if sealed.template.sha256 == now else
                 " (from another version of this spec)") + ". "
              + _made_by("Its cases were run", sealed.cases_run_by, code, DRAW_ANEW)
              + _battery_words(sealed.battery)
              + " The development figures are in-sample; the sealed ones are the measure "
                "of the diagnosis on cases it was not tuned on, and the verdicts are theirs.")
    return {"sealed": origin, "comparison": rows}


def _form_row(row, units) -> dict:
    """One truth form of an independent battery, in words for the by-form table."""
    peak = ("—" if row.median_peak_load_change_N is None else
            f"{with_unit(row.median_peak_load_change_N, 'force', units)} "
            f"({percent(row.median_peak_load_change_share)})")
    return {"label": row.label,
            "effect": row.effect or "outside the library (abstaining is right)",
            "all": f"{row.right} of {row.cases}",
            "scored": f"{row.right_scored} of {row.scored}", "peak": peak}


def _declared_words(diagnosis, declared: list[str]) -> str:
    """How the diagnosis's answer stands to the effects the spec's model declares, and
    whether an effect it declares not is worth adding: only when it carries to the held-out
    drops (closes part of their load gap and makes no held-out channel worse)."""
    from certkit.gap.selection import FLOOR_CHANNEL
    from certkit.physics.effects import BY_NAME

    answer = diagnosis.answer
    labels = [BY_NAME[name].label for name in declared if name in BY_NAME]
    named = [a for a in answer if a in labels]
    new = [a for a in answer if a not in labels]
    words = (f"The spec's model declares {' and '.join(labels)}. " if labels
             else "The spec's model declares no optional effect. ")
    if not answer:
        return words + ("Starting without them, the diagnosis named no effect: the drops do "
                        "not single out one of the library's effects." if labels else "")
    if named:
        words += (f"Starting without them, the diagnosis named {' and '.join(named)} from the "
                  f"drops alone: the data support {'them' if len(named) > 1 else 'it'}. ")
    if new:
        share = (diagnosis.shares or {}).get(FLOOR_CHANNEL)
        carries = share is not None and share[0] > 0 and not diagnosis.caveats
        words += (f"It also named {' and '.join(new)}, which the spec's model does not "
                  + ("include: worth adding (model.effects)." if carries else
                     "include; on the held-out drops the named effects "
                     + ("make " + " and ".join(diagnosis.caveats) + " worse"
                        if diagnosis.caveats else
                        f"close {percent(share[0], 0)} of the {FLOOR_CHANNEL} gap"
                        if share is not None else "were not measured")
                     + ", so the drops do not show that it carries beyond the training "
                       "runs: no reason to add it on this evidence."))
    return words.strip()


def gap_view(evidence, campaign, units) -> GapSection:
    """The gap appendix: per gear unit where, which and how far; the blind check."""
    from certkit.evidence.figures import gap_heatmap, gap_overlay, missing_force_figure
    from certkit.evidence.model_evidence import GAP
    from certkit.evidence.model_view import failures_view

    method = gap_method(units)
    blind = _blind_view(campaign, units)
    declared = list(campaign.spec.model.effects)
    intro = ("This appendix is not compliance evidence: no verdict rests on it. It asks where "
             "the drop model disagrees with the drops, which unmodelled effect of a library "
             "explains the disagreement, and how far the error on held-out drops shrinks once "
             "that effect is added; its last part says how far the diagnosis can be trusted. "
             "It starts from the bare model (the gear's drop model without any optional "
             "effect, also those the spec declares), calibrated on the same training runs as "
             "appendix A: so every effect, the declared ones too, has to earn its place from "
             "the data.")
    gears = []
    for gear_id, gap in evidence.gap.items():
        diagnosis = gap.diagnosis
        answer = " and ".join(diagnosis.answer)
        finite = [c.normalised for c in gap.before.cells if math.isfinite(c.normalised)]
        top = max(finite) if finite else None
        figures = [gap_heatmap(
            gap.before, f"{gear_id}: residual map of the calibrated bare model",
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
            "calibration_cost": number(gap.before.calibration.fit.cost),
            "calibration_starts": starts_words(
                gap.before.calibration.search,
                gap.before.calibration.fit.cost
                if any(d.rule == "calibrated again" for d in diagnosis.recalibrated) else None),
            "largest": _gap_largest(gap.before, units),
            "heatmap": figures[0], "overlays": figures[1:],
            "steps": _gap_steps(gap, units), "statement": diagnosis.statement,
            "declared": _declared_words(diagnosis, declared),
            "missing": missing, "signatures": _signatures(diagnosis, units),
            "shrink": _gap_shrink(gap, units),
            "remaining": dict(remaining, svg=Markup(remaining["svg"])) if remaining else None,
            "remaining_largest": _lower_first(f"With {answer} refitted, ",
                                              _gap_largest(gap.after, units))
            if gap.after else "",
            "remaining_note": "" if gap.after else
            "No effect was named, so nothing was added and the residual map above is what "
            "remains."})
    notes = list(evidence.gap_notes)
    failures = failures_view(evidence, GAP)
    if not gears and not notes and not failures:
        notes = ["No gear unit was diagnosed."]
    return GapSection(**{"intro": intro, "available": True, "note": evidence.note,
                         "notes": notes, "failures": failures, "gears": gears, "blind": blind,
                         "time_unit": units.time, **method})


def _signatures(diagnosis, units) -> list[dict]:
    """The missing force's shapes at each step, as the diagnosis recorded them."""
    out = []
    for index, step in enumerate(diagnosis.evidence):
        for found in step:
            out.append({"step": index + 1, "force": found.force, "shape": found.shape,
                        "marks": found.effect or "— (absorbed by re-tuning)",
                        "coefficient": " ".join(filter(None, parameter(
                            found.coefficient, found.unit, units))),
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
