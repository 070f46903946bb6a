"""The sim-to-real gap of a gear unit's drop model: where it lies, which unmodelled effect
explains it and how far it shrinks once that effect is added.

1. The nominal model (no optional effects) is calibrated on the training runs; the
   held-out runs (:func:`certkit.gap.holdout.split_for`: the spec's ``model.gap.held_out``, by
   default every drop at the highest drop height) are used for nothing else.
2. Where: the residual (measured − calibrated nominal) of every channel is cut by the
   measured run's phases and summarised per channel × phase × run
   (:mod:`certkit.gap.residuals`): RMS, bias, timing error and energy in frequency bands; the
   largest disagreement on the training runs is named in words.
3. Which: :func:`certkit.gap.selection.diagnose` scores the library's candidate effects
   (every form of each), refits the leading ones and names one or two effects, declares a
   tie, or abstains; when a first-step refit's bare parameters fit better than the
   calibration of step 1, the nominal model is calibrated again from them, and steps 2
   and 4 use that calibration.
4. How far: the held-out RMSE before (calibrated nominal) and after (refit with the named
   effects), per channel over the whole record from touchdown and per channel and phase,
   with the shrink 1 − after/before; and the residual map that remains with the named
   effects, on every run.

:func:`gap_diagnosis` does all four; the CLI and the report call it.  The blind check
(benchmarks/blindcheck, outside the package) calls :func:`certkit.gap.selection.diagnose`,
the choice and its held-out errors, which is what it scores.
Data flow: this module uses :mod:`certkit.gap.selection` and :mod:`certkit.gap.holdout`, never
the reverse.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from certkit.gap.holdout import split_for
from certkit.gap.missing_force import campaign_missing_forces
from certkit.gap.phases import segment
from certkit.gap.residuals import BANDS, Cell, band_shares, describe, largest, residual_cells
from certkit.gap.selection import (CANDIDATES, DETECTABLE, GAIN, LEADING, NOMINAL_STARTS,
                                   PULSE_SHARE, RECALIBRATE, RELEVANT, RESTARTS, TIE_COST,
                                   TIMING_SHARE, Diagnosis, diagnose, nominal_calibration)
from certkit.gap.statements import decision_words
from certkit.physics.calibration import CHANNEL_UNITS, GearCalibration, aligned_records
from certkit.physics.drops import MIDDLE_FROM
from certkit.physics.starts import KEEP_MARGIN, START_EVALUATIONS, starts_document
from certkit.spec.campaign import Campaign
from certkit.threads import one_blas_thread

CHANNELS = ("load", "stroke", "tyre")
#: The phase label of an error over the whole record from touchdown.
WHOLE = "whole record from touchdown"


@dataclass
class GapMap:
    gear_id: str
    training: tuple[str, ...]
    held_out: tuple[str, ...]
    calibration: GearCalibration
    cells: list            # Cell, every run (training and held out)
    bands: dict            # (run, channel) -> {band: share of the residual's energy}
    largest: Cell | None
    summary: str
    records: dict = field(default_factory=dict)   # run -> calibration.AlignedRecord
    phases: dict = field(default_factory=dict)    # run -> [phases.Phase] of the measured run


def _summary(cell: Cell | None) -> str:
    units = {"load": (1.0, "N"), "stroke": (1e3, "mm"), "tyre": (1e3, "mm")}
    return describe(cell, *units[cell.channel]) if cell else "No residual to map."


def _map(campaign: Campaign, gear_id: str, training, held, calibration: GearCalibration,
         configure) -> GapMap:
    """The residual map of every run with the model ``configure`` gives."""
    runs = list(training) + list(held)
    records = aligned_records(campaign, gear_id, configure, runs, effects=[])
    weight = campaign.gear_units[gear_id].static_weight.si
    cells, bands, phases = [], {}, {}
    for run_id in runs:
        record = records[run_id]
        stroke = record.measured.get("stroke", np.zeros(record.time.size))
        phases[run_id] = segment(record.time, record.measured["load"], stroke, weight)
        cells += residual_cells(run_id, record.time, record.measured, record.simulated,
                                phases[run_id])
        step = float(np.median(np.diff(record.time)))
        for channel, measured in record.measured.items():
            residual = measured[record.after] - record.simulated[channel][record.after]
            bands[(run_id, channel)] = band_shares(residual, step)
    worst = largest([c for c in cells if c.run in training])
    return GapMap(gear_id, tuple(training), tuple(held), calibration, cells, bands, worst,
                  _summary(worst), records, phases)


def residual_map(campaign: Campaign, gear_id: str,
                 split: tuple[list[str], list[str]] | None = None,
                 calibration: GearCalibration | None = None) -> GapMap:
    """Steps 1-2 for one gear unit (``split`` default: :func:`split_for`)."""
    training, held = split or split_for(campaign, gear_id)[:2]
    if calibration is None:
        calibration = nominal_calibration(campaign, gear_id, training)
    return _map(campaign, gear_id, training, held, calibration, calibration.apply)


# --------------------------------------------------------------------------- how far
@dataclass(frozen=True)
class HeldOutError:
    """RMSE of one channel of a held-out run over one phase (or :data:`WHOLE`), before and
    after the named effects are added (SI, the channel's unit)."""

    run: str
    channel: str
    phase: str
    samples: int
    before: float
    after: float | None    # None: no effect named

    @property
    def shrink(self) -> float | None:
        """1 − after/before (0.6: the error shrank by 60 %; negative: it grew)."""
        if self.after is None or not self.before > 0:
            return None
        return 1.0 - self.after / self.before


def _rmse(values: np.ndarray) -> float:
    return float(np.sqrt(np.mean(values ** 2)))


def held_out_errors(before: dict, after: dict | None, phases: dict) -> list[HeldOutError]:
    """Per held-out run and channel: the RMSE over the whole record from touchdown, then per
    phase of the measured run.

    ``before``, ``after``: run -> :class:`~certkit.physics.calibration.AlignedRecord` with the
    calibrated nominal model and with the named effects (``after`` None: none named);
    ``phases``: run -> phases of the measured run."""
    rows = []
    for run_id, record in before.items():
        later = after[run_id] if after is not None else None
        for channel, measured in record.measured.items():
            parts = [(WHOLE, record.after)] + [(p.name, slice(p.start, p.stop))
                                                for p in phases[run_id]]
            for name, part in parts:
                residual = measured[part] - record.simulated[channel][part]
                if residual.size == 0:
                    continue
                rows.append(HeldOutError(
                    run_id, channel, name, int(residual.size), _rmse(residual),
                    None if later is None else
                    _rmse(measured[part] - later.simulated[channel][part])))
    return rows


@dataclass
class GapDiagnosis:
    """Where, which and how far, for one gear unit."""

    gear_id: str
    training: tuple[str, ...]
    held_out: tuple[str, ...]
    declared: bool                 # the split is the spec's model.gap.held_out
    before: GapMap                 # residual map of the calibrated nominal model
    diagnosis: Diagnosis
    after: GapMap | None           # what remains with the named effects (None: none named)
    held_out_errors: list          # HeldOutError
    refit_held_out: dict = field(default_factory=dict)
    # (step index, effects) -> {(run, channel): RMSE from touchdown [SI]} of every refit;
    # evaluated only, never used to choose
    missing: list = field(default_factory=list)
    # certkit.gap.missing_force.MissingForce of every run under the calibrated nominal model


@one_blas_thread
def gap_diagnosis(campaign: Campaign, gear_id: str) -> GapDiagnosis:
    """The whole gap diagnosis of ``gear_id`` on its training/held-out split.

    Raises
    ------
    CertkitInputError
        When the gear's drops allow no diagnosis (:func:`certkit.gap.holdout.split_for`).
    """
    training, held, declared = split_for(campaign, gear_id)
    before = residual_map(campaign, gear_id, (training, held))
    calibration = before.calibration
    diagnosis = diagnose(campaign, gear_id, (training, held), calibration=calibration)
    if diagnosis.calibration is not calibration:
        # calibrated again (a refit's bare parameters fitted better): the gap is the one
        # of that calibration
        calibration = diagnosis.calibration
        before = _map(campaign, gear_id, training, held, calibration, calibration.apply)
    after = None
    if diagnosis.refit is not None:
        after = _map(campaign, gear_id, training, held, calibration, diagnosis.configure)
    errors = held_out_errors({r: before.records[r] for r in held},
                             {r: after.records[r] for r in held} if after else None,
                             before.phases)
    names = {c.key: c for c in CANDIDATES}
    checks = {}
    for index, (_, fits) in enumerate(diagnosis.steps):
        for fit in fits:
            chosen = [names[e] for e in fit.effects]
            records = aligned_records(
                campaign, gear_id, lambda m, fit=fit, chosen=chosen:
                fit.apply(calibration.knobs, m, chosen), list(held), effects=[])
            checks[(index, fit.effects)] = {
                (run_id, channel): _rmse(measured[record.after]
                                         - record.simulated[channel][record.after])
                for run_id, record in records.items()
                for channel, measured in record.measured.items()}
    missing = campaign_missing_forces(campaign, gear_id, list(training) + list(held),
                                      calibration.apply)
    return GapDiagnosis(gear_id, tuple(training), tuple(held), declared, before, diagnosis,
                        after, errors, checks, missing)


# --------------------------------------------------------------------------- results.json
#: The thresholds the diagnosis applies (certkit.gap.attribution), as results.json states them.
THRESHOLDS = {
    "relevant_explained_rms_noise_units": RELEVANT,
    "leading_candidates_refitted": LEADING,
    "gain_training_cost_share": GAIN,
    "tie_training_cost_ratio": TIE_COST,
    "detectable_noise_variances_removed": DETECTABLE,
    "timing_share_of_channel_mean_square": TIMING_SHARE,
    "load_pulse_share_of_peak": PULSE_SHARE,
    "recalibrate_training_cost_share": RECALIBRATE,
    "calibrations_again_at_most": RESTARTS,
    "nominal_calibration_further_starts": NOMINAL_STARTS,
    "further_start_evaluations_at_most": START_EVALUATIONS,
    "further_start_keep_margin_share": KEEP_MARGIN,
    "middle_height_held_out_from_heights": MIDDLE_FROM,
}


def _cell_document(cell: Cell) -> dict:
    return {"run": cell.run, "channel": cell.channel, "phase": cell.phase,
            "unit": CHANNEL_UNITS[cell.channel], "samples": cell.samples, "rms": cell.rms,
            "bias": cell.bias, "lag_s": cell.lag, "channel_rms": cell.scale,
            "normalised_rms": cell.normalised if np.isfinite(cell.normalised) else None}


def _map_document(gap: GapMap | None) -> dict | None:
    if gap is None:
        return None
    return {"summary": gap.summary,
            "largest": _cell_document(gap.largest) if gap.largest else None,
            "cells": [_cell_document(c) for c in gap.cells],
            "bands": [{"run": run, "channel": channel, "shares": shares}
                      for (run, channel), shares in gap.bands.items()],
            "band_limits_hz": [{"band": name, "low": low,
                                "high": high if np.isfinite(high) else None}
                               for name, low, high in BANDS]}


def _decision_document(decision) -> dict:
    """One recorded decision: the rule that made it, the figures it compared, in words."""
    return {"candidate": decision.name, "rule": decision.rule, "figures": decision.figures,
            "words": decision_words(decision)}


def gap_document(gap: GapDiagnosis) -> dict:
    """Plain, JSON-ready account of one gear unit's gap diagnosis (SI)."""
    diagnosis = gap.diagnosis
    calibration = gap.before.calibration
    nominal = calibration.nominal_model
    steps = []
    for index, (attribution, fits) in enumerate(diagnosis.steps):
        steps.append({
            "training_cost_to_beat": diagnosis.step_costs[index]
            if index < len(diagnosis.step_costs) else None,
            "noise_variance_normalised": attribution.sigma2,
            "scores": [{"effect": s.name, "lm_statistic": s.statistic,
                        "direction": s.direction, "projected_norm": s.projected_norm,
                        "explained_rms_noise_units": s.explained} for s in attribution.scores],
            "decisions": [_decision_document(d) for d in
                          attribution.decisions + attribution.skipped
                          + ((attribution.no_refit,) if attribution.no_refit else ())],
            "refit_decisions": [_decision_document(d) for d in diagnosis.refit_decisions[index]]
            if index < len(diagnosis.refit_decisions) else [],
            "confusability": [{"a": a, "b": b, "cosine": c}
                              for (a, b), c in attribution.confusability.items()],
            "refits": [{"effects": list(f.effects), "strengths": list(f.strengths),
                        "strength_standard_errors": [e if np.isfinite(e) else None
                                                     for e in f.strength_errors],
                        "nominal_parameters": {p.name: v for p, v in
                                               zip(f.fit.parameters, f.values)},
                        "training_cost": f.training_cost,
                        "held_out_rmse": [{"run": run, "channel": channel,
                                           "unit": CHANNEL_UNITS[channel], "value": v}
                                          for (run, channel), v in
                                          gap.refit_held_out.get((index, f.effects), {}).items()]}
                       for f in fits]})
    return {
        "gear_unit": gap.gear_id, "training": list(gap.training),
        "held_out": list(gap.held_out),
        "split": "declared (model.gap.held_out)" if gap.declared else "default",
        "calibration": {"parameters": [{"name": p.name, "unit": p.unit,
                                        "nominal": knob.read(nominal), "estimate": float(e)}
                                       for knob, p, e in zip(calibration.knobs,
                                                             calibration.fit.parameters,
                                                             calibration.fit.estimate)],
                        "training_cost": calibration.fit.cost,
                        "further_starts": starts_document(calibration.search)},
        "before": _map_document(gap.before),
        "steps": steps,
        "answer": list(diagnosis.answer), "forms": list(diagnosis.forms),
        "tie": list(diagnosis.tie), "undecided": list(diagnosis.undecided),
        "calibrated_again": [_decision_document(d) for d in diagnosis.recalibrated],
        "statement": diagnosis.statement,
        "held_out_noise": diagnosis.noise,
        "held_out_gap_shares": None if diagnosis.shares is None else {
            channel: None if share is None else {"closed": share[0], "unexplained": share[1]}
            for channel, share in diagnosis.shares.items()},
        "held_out_caveats": list(diagnosis.caveats),
        "missing_force_signatures": [
            [{"force": g.force, "shape": g.shape, "marks": g.effect,
              "coefficient": g.coefficient, "unit": g.unit, "partial_r2": g.share,
              "seen": g.seen} for g in step] for step in diagnosis.evidence],
        "held_out_errors": [{"run": e.run, "channel": e.channel, "phase": e.phase,
                             "unit": CHANNEL_UNITS[e.channel], "samples": e.samples,
                             "rmse_before": e.before, "rmse_after": e.after,
                             "shrink": e.shrink} for e in gap.held_out_errors],
        "after": _map_document(gap.after),
    }
