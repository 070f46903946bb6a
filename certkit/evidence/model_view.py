"""The report's views of the drop model: calibration (appendix A) and identification
(appendix B), every number formatted in the campaign's display units.

The identification stage and matplotlib are imported inside the functions that need them:
a report without the drop model never loads them (about 0.66 s and 0.26 s of start-up,
``python -X importtime``).
"""

from __future__ import annotations

import math
import re

from markupsafe import Markup

from certkit.display import (display, magnitude, number, parameter, percent, pretty, typed,
                             with_unit)
from certkit.evidence.methods import held_out_drops, identification_method, model_method
from certkit.evidence.sections import IdentificationSection, ModelSection
from certkit.units import convert


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


def failures_view(evidence, stage: str) -> list[str]:
    """The gear units a stage could not be computed for, one sentence each: why, and what
    to change."""
    return [f"{f.gear}: not computed. {f.reason[:1].upper() + f.reason[1:].rstrip('.')}. "
            f"To change: {f.remedy}." for f in evidence.failed(stage)]


def synthetic_warning(evidence) -> str:
    """The warning every model appendix carries when the campaign's histories are synthetic."""
    if not evidence.synthetic_runs:
        return ""
    return (f"The time histories of run(s) {', '.join(evidence.synthetic_runs)} are SYNTHETIC "
            f"(simulated, declared origin: synthetic), not measured: the model is compared "
            f"here with simulated data, which shows the method, not the real gear's behaviour.")


def _tabulated_marks(tabulated: dict, gear_id: str, run: str) -> dict:
    """What the results table (section 5) gives for this run and gear, in SI, when its
    basis is not the record drawn (the source's reported values): channel -> value."""
    shown = (tabulated or {}).get((run, gear_id))
    if not shown or shown["basis"] != "reported values":
        return {}
    return {channel: shown[key] for channel, key in (("load", "F_peak"), ("stroke", "d_s"),
                                                     ("tyre", "d_t"))
            if shown.get(key) is not None}


def model_view(evidence, units, reference=None, origins=None, effects=(),
               tabulated=None) -> ModelSection:
    """The calibration appendix: per gear unit the calibrated parameters, the fit on the
    training runs and the prediction of the held-out ones, or why not computed."""
    from certkit.evidence.figures import model_figure
    from certkit.evidence.model_evidence import CALIBRATION
    from certkit.spec.rundata import CHANNEL_LABELS

    calibration = evidence.calibration
    declared = ", ".join(effects) or "none"
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
        rmse = []
        for e in gear.errors:
            kind = "force" if e.channel == "load" else "length"
            before, unit = display(e.nominal, kind, units)
            after, _ = display(e.calibrated, kind, units)
            change = (e.calibrated / e.nominal - 1) if e.nominal else float("nan")
            rmse.append({"run": e.run, "role": e.role, "channel": CHANNEL_LABELS[e.channel],
                         "unit": unit, "nominal": before, "calibrated": after,
                         "change": percent(change, 1, signed=True)})
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
        worse = [f"the {CHANNEL_LABELS[e.channel]} of {e.run} "
                 f"({percent(e.calibrated / e.nominal - 1, 1, signed=True)})"
                 for e in gear.errors if e.role == "held out" and e.calibrated > e.nominal]
        held_out_words = (
            "On the held-out runs, calibration made " + ", ".join(worse) + " worse than the "
            "nominal model: what it fitted on the training runs does not carry to that drop."
            if worse else ("On the held-out runs, calibration made no channel worse than the "
                           "nominal model." if gear.held_out else ""))
        # the drops the model did not see: where a reader judges it
        shown_runs = list(gear.held_out) or list(gear.runs[-1:])
        figures = [model_figure(gear.gear_id, run, [t for t in gear.traces if t.run == run],
                                units, origin=(origins or {}).get(run, "measured"),
                                held_out=run in gear.held_out,
                                tabulated=_tabulated_marks(tabulated, gear.gear_id, run))
                   for run in shown_runs]
        figures = [dict(f, svg=Markup(f["svg"])) for f in figures]
        velocities = "; ".join(f"{run}: {with_unit(v, 'velocity', units)} ({source})"
                               for run, (v, source) in gear.contact_velocities.items())
        gears.append({
            "id": gear.gear_id, "runs": ", ".join(gear.runs),
            "held_out": ", ".join(gear.held_out) or "none",
            "parameters": parameters, "warnings": [_bound_words(w, gear, units)
                                                   for w in fit.warnings],
            "message": fit.message,
            "evaluations": f"{fit.evaluations} model evaluations"
                           + (" by the fits that finished, further starts included (a fit "
                              "that failed is not counted)" if gear.search else ""),
            "starts": starts_words(gear.search),
            "cost": f"{number(fit.cost_nominal)} → {number(fit.cost)}", "rmse": rmse,
            "figures": figures, "velocities": velocities, "held_out_words": held_out_words,
            "step": with_unit(gear.step, "time", units)})
    intro = (f"This appendix is not compliance evidence: no verdict rests on it. It compares "
             f"each gear unit's drop model with its drops. The model is the two-mass governing "
             f"equations of a gear drop with the spec's nominal parameters and the optional "
             f"effects the spec declares ({declared}); it is calibrated on the training runs "
             f"and then simulated on the held-out runs, which it has not seen, so their errors "
             f"show how well it predicts. This is the calibrated model of the whole report: "
             f"the identification's 'governing equation, calibrated' is the same model.")
    return ModelSection(method=model_method(evidence.calibration_starts), intro=intro,
                        synthetic=synthetic_warning(evidence),
                        note=evidence.note, failures=failures_view(evidence, CALIBRATION),
                        gears=gears, effects=declared, reference_rows=reference_rows,
                        reference=_reference_view(reference, units))


def starts_words(search, again_cost: float | None = None) -> str:
    """What a calibration's further starts found, as recorded (empty when it had none).
    ``again_cost``: the training cost of a calibration done again afterwards from a
    refit's parameters (the gap diagnosis), which is then the calibration used."""
    if search is None:
        return ""
    from certkit.physics.starts import KEEP_MARGIN, START_EVALUATIONS
    margin, costs = percent(KEEP_MARGIN, 1), search.start_costs
    done = [(c, i) for i, c in enumerate(costs) if c is not None]
    words = (f"The fit from the spec's values reached a training cost (normalised RMS "
             f"residual) of {number(search.first_cost)}. It was also tried from "
             f"{len(search.points)} further starts spread over the parameters' bounds, each "
             f"fitted with forward differences within {START_EVALUATIONS} evaluations of the "
             f"residuals (finite-difference points not counted)")
    if search.kept is not None:
        words += (f"; start {search.kept + 1} reached {number(costs[search.kept])} and, "
                  f"fitted again from where it stopped, came more than {margin} lower: that "
                  f"calibration is kept.")
    elif not done:
        words += "; none of them could be fitted, so the fit from the spec's values is kept."
    elif len(search.failures) > len(costs) - len(done):
        # the last failure is the best start's fit done again (it names that start)
        words += (f"; the best of them (the earliest within {margin} of the lowest, "
                  f"{number(min(done)[0])}) could not be fitted again, so the fit from the "
                  f"spec's values is kept.")
    else:
        words += (f"; the lowest reached {number(min(done)[0])} and, fitted again, came no "
                  f"more than {margin} below the fit from the spec's values, which is kept.")
    if search.failures:
        words += (f" Fits that failed and were passed over (values in SI): "
                  f"{'; '.join(search.failures)}.")
    if again_cost is not None:
        words += (f" The model was then calibrated again from a refit's parameters (training "
                  f"cost {number(again_cost)}), and that calibration is the one used.")
    return words


def _bound_words(warning: str, gear, units) -> str:
    """A fit's warning in the display units: "x ended on its lower bound (1e-05 m): …" quotes
    the value in SI (:func:`certkit.physics.fitting.fit`)."""
    found = re.match(r"(\S+) ended on its (lower|upper) bound \(([^ )]+) ?([^)]*)\)(.*)",
                     warning, re.S)
    if not found:
        return warning
    name, side, value, unit, rest = found.groups()
    labels = {p.name: knob.label for knob, p in zip(gear.knobs, gear.fit.parameters)}
    shown, shown_unit = parameter(float(value), unit or "1", units)
    return (f"{labels.get(name, name)} ended on its {side} bound "
            f"({' '.join(filter(None, (shown, shown_unit)))}){rest}")


_MODEL_ORDER = ("governing equation, nominal", "governing equation, calibrated", "Hammerstein",
                "Wiener (small-signal)", "Wiener (BLA)", "NARX")


#: Fields of the spec's reference_results that correspond to certkit's models.
_REFERENCE_MODELS = {"governing equation, nominal": "governing_equation",
                     "Hammerstein": "hammerstein", "Wiener (small-signal)": "wiener",
                     "NARX": "narx"}


def _mm(value_mm: float, units) -> str:
    """An identification error (computed in mm) in the display length unit, with the unit."""
    return f"{magnitude(value_mm * 1e-3, 'length', units)} {units.length}"


def _ranking_sentence(scores, output: str, protocol: str, run: str, units) -> str:
    chosen = sorted((s for s in scores if s.output == output and s.protocol == protocol
                     and s.run == run), key=lambda s: s.rmse)
    return ", ".join(f"{s.model} {_mm(s.rmse, units)}" for s in chosen)


def _discussion(gear, reference, units) -> list[str]:
    """Where the ranking of the models the campaign's reference results rank differs from
    what the data say here (nothing when the campaign has no reference results)."""
    from certkit.gear_identification import (OUTPUT_LABELS, PAPER_TRAINING,
                                             PAPER_TRAINING_DURATION)

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
                     f"{with_unit(PAPER_TRAINING_DURATION, 'time', units)}) of the very drop it "
                     f"then simulates, the best model reaches {_mm(best_paper.rmse, units)} "
                     f"({best_paper.model}); trained on other drop heights, "
                     f"{_mm(best_held.rmse, units)} ({best_held.model}).")
        sentences.append(text)
    return sentences


def identification_view(evidence, settings, units, reference=None, origins=None,
                        heights=None) -> dict:
    """The identification section: RMSE tables (beside the campaign's reference results when
    it has some), linear blocks, figures.

    ``settings``: the spec's ``model.identification``; ``reference``: its reference_results."""
    from certkit.gear_identification import (MODEL_RATE, PAPER_TRAINING,
                                             PAPER_TRAINING_DURATION, PROTOCOL_NAMES,
                                             WHITENESS_CONFIDENCE, WHITENESS_LAGS, WINDOW,
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
    from certkit.evidence.model_evidence import IDENTIFICATION

    identification = getattr(evidence, "identification", None)
    method["intro"] = (
        "This appendix is not compliance evidence: no verdict rests on it. From each gear "
        "unit's drops it identifies models that predict the strut stroke and the tyre "
        "deflection from the vertical load alone (Hammerstein, Wiener and NARX models with "
        "LS-SVM nonlinearities, beside the calibrated drop model of appendix A), fits and "
        "tunes them on the training runs and simulates the held-out runs in free run.")
    method["failures"] = failures_view(evidence, IDENTIFICATION)
    heights = heights or {}
    at_middle = any(len({heights.get(run) for run in gear.held_out}) > 1
                    for gear in getattr(identification, "gears", None) or [])
    method["protocols"] = identification_method(
        method["window"], method["paper_samples"], method["force_unit"], method["length_unit"],
        held_out_drops(at_middle, bool(settings.held_out)))
    if identification is None or not identification.gears:
        skipped = list(getattr(identification, "skipped", []) or [])
        return IdentificationSection(**{"available": False, "gears": [], "plant_note": "",
                "note":
                "Not run: it needs time histories of at least two drops of a gear unit "
                "whose drop model can be built from the spec, each recorded for "
                f"{with_unit(WINDOW_DURATION, 'time', units)} after touchdown."
                + (" " + "; ".join(skipped) + "." if skipped else ""), **method})
    from certkit.evidence.figures import identification_figures
    from certkit.gear_identification import OUTPUT_LABELS

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
                                 else magnitude(score.rmse * 1e-3, "length", units))
                if with_reference:
                    quantity = published(model, output)
                    cells.append("—" if quantity is None
                                 else typed(quantity.text, quantity.si, "length", units)[0])
            table.append({"model": model, "cells": cells})
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
        one_step = {(m, o): _mm(v, units) for m, o, r, v in gear.one_step}
        whiteness = [{"model": m, "output": OUTPUT_LABELS[o],
                      "one_step": one_step.get((m, o), "—"),
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
                      "with_reference": with_reference,
                      "blocks": blocks, "steps": steps,
                      "whiteness": whiteness, "rankings": rankings, "figures": figures,
                      "discussion": _discussion(gear, reference, units),
                      "ratios": ", ".join(f"{OUTPUT_LABELS[o]} {r:.3g}"
                                          for o, r in gear.hammerstein_ratio.items()),
                      "notes": list(gear.notes)})
    return IdentificationSection(**{"available": True, "gears": gears,
                                    "plant_note": identification.plant_note,
                                    "note": "".join(f"{why}. " for why in identification.skipped),
                                    **method})


def origins(spec) -> dict[str, str]:
    """run id -> declared origin of its time histories (measured / synthetic)."""
    return {run.id: run.data.origin for run in spec.runs if run.data is not None}
