"""Which effect(s) to name: the greedy choice among the library's candidate effects, with
its rules stated once here and every decision recorded where it is taken (forms, ties,
harm and the floor).

Every refit is judged against a calibration of the nominal model that no first-step
refit's bare parameters (its effect left out) beat by more than :data:`RECALIBRATE`: when
one does, the calibration did not reach the best fit of the bare parameters, and it is done
again from them before the first step is judged (:func:`_calibrated_again`; when a better
fit remains after :data:`RESTARTS` of them, no effect is named at that step).

At each of at most two steps the candidates (every form of every effect not yet named)
are scored and profiled (:mod:`certkit.gap.attribution`); the best form of each of the
:data:`LEADING` relevant effects with the best profiles is refitted with the nominal
parameters; the refit that cuts the training cost most, by :data:`GAIN` at least, leaves
no training channel worse beyond its noise (:func:`certkit.gap.residuals.harmed`) and
removes at least :data:`DETECTABLE` noise variances from the training records is named
(an error of one recorded channel, a load-cell gain, is refitted with that channel's skew
and named only if its correction, skew included, fits the channel's residual at the same
instant: :data:`TIMING_SHARE`; what a gain with a skew cannot explain, a share of the load
tens of milliseconds earlier, is refused as another timing error), unless another effect's
refit comes within :data:`TIE_COST` of it: then the two
cannot be told apart by their fits, and the model-free missing force
(:mod:`certkit.gap.missing_force`, on the training runs) decides when it shows the mark of
one of them and not of the other; otherwise neither is named (a tie).  When a step beside
named effects names nothing, an effect whose refit fails only the harm rule is stated
undecided (:attr:`Diagnosis.undecided`): the records cannot say whether it is present too.
The held-out runs are
only evaluated: their errors before and after, the share of their gap beyond the noise that
the named effects close and the share that stays unexplained
(:func:`certkit.gap.residuals.gap_shares`), and a caveat for every held-out channel the
named effects make worse beyond its noise.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from certkit.gap import statements
from certkit.gap.attribution import (Attribution, Decision, Refit, central_jacobian, configured,
                                     nominal_jacobian, profiles, refit, score_candidates)
from certkit.gap.holdout import split_for
from certkit.gap.missing_force import campaign_missing_forces, pointed_effects, signatures
from certkit.gap.residuals import gap_shares, harmed, noise_level, shifted_fit
from certkit.physics.calibration import (GearCalibration, RunResiduals, aligned_records,
                                         calibrate_gear)
from certkit.physics.drop_model import DropModel
from certkit.physics.effects import CANDIDATES, Candidate
from certkit.physics.effects.base import set_effect
from certkit.threads import one_blas_thread

__all__ = ["CANDIDATES", "DETECTABLE", "GAIN", "LEADING", "RECALIBRATE", "RELEVANT", "RESTARTS",
           "TIE_COST", "TIMING_SHARE",
           "Diagnosis", "diagnose", "judge", "refit_decisions"]

#: A candidate is considered only if it would remove at least this RMS (in noise units).
RELEVANT = 0.3
#: Refits of two effects whose training costs lie within this ratio cannot be told apart.
TIE_COST = 1.05
#: A candidate must cut the training cost by at least this share to be named.
GAIN = 0.10
#: A refit must remove from the training records at least this many noise variances, summed
#: over the channels (Σ_c (RMSE_before,c² − RMSE_after,c²)/σ_c², a channel made worse counting
#: against it): the half of what an effect of twice the noise, fully removed from one
#: channel, would remove.  Below it, what the refit removes is no larger than the floor a
#: nominal model's own imperfection leaves, and it is not named.
DETECTABLE = 2.0
#: How many relevant effects are refitted at each step (the best form of each, those with
#: the best profiles): two, so that the tie rule can compare the best pair.
LEADING = 2
#: An error of one recorded channel (a load cell's gain) changes each sample of it at its own
#: instant, up to the channel's skew behind the others (a fraction of a millisecond), which
#: the gain's refit fits with it (:mod:`certkit.physics.effects.load_cell_gain`).  When
#: the refit's correction, skew included, shifted further in time (up to
#: :data:`certkit.gap.residuals.TIMING_LAG`), would remove this share or more of the mean
#: square that stays on that channel, what is missing changes the record's timing beyond a
#: skew (crosstalk through a frame, a share of the load tens of milliseconds earlier) and
#: the form is not named.  A gain's own refit, with its skew, leaves at most a few per cent
#: to a shift (the floor of the nominal model and the noise).
TIMING_SHARE = 0.10
#: The load pulse, over which a named gain with a skew is compared with the crosstalk that
#: reads the same: the samples where the load is at least this share of its peak.
PULSE_SHARE = 0.05
#: A refit is judged against a calibration that no first-step refit's bare parameters (its
#: effect left out) beat by more than this share of its cost (the calibration's own
#: tolerance is 1e-6): when one does, the calibration did not reach the best fit of the
#: bare parameters, and it is done again from them (:func:`_calibrated_again`), at most
#: :data:`RESTARTS` times; a better fit remaining after that names no effect at the step.
RECALIBRATE = 0.02
RESTARTS = 2
#: The nominal model is calibrated from the spec's values and from this many further
#: starts spread over the knobs' bounds (:mod:`certkit.physics.starts`), the best kept: a
#: calibration stopped in a basin far from the best fit leaves a "gap" that is the
#: optimiser's, not physics (on a rig whose stiff top-out pad the fit could not soften,
#: every effect's refit then looked better than it was).  16 since the fits' step became
#: :data:`~certkit.physics.calibration.FIT_STEP` (8 before): docs/drop-model.md says on
#: which cases the count was chosen.
NOMINAL_STARTS = 16
#: The channel whose held-out gap the statement's closed and unexplained shares are of.
FLOOR_CHANNEL = "load"


def nominal_calibration(campaign, gear_id: str, training) -> GearCalibration:
    """The nominal model (no effect) of ``gear_id`` calibrated on the runs ``training``,
    from the spec's values and :data:`NOMINAL_STARTS` further starts."""
    return calibrate_gear(campaign, gear_id, effects=[], run_ids=list(training),
                          starts=NOMINAL_STARTS)


@dataclass
class Diagnosis:
    gear_id: str
    training: tuple[str, ...]
    held_out: tuple[str, ...]
    answer: tuple[str, ...]        # the effect(s) named; empty: abstained
    statement: str                 # the answer in words
    steps: list                    # (Attribution, [Refit ...]) per greedy step
    held_out_rmse: dict            # (label, run, channel) -> RMSE before/after [SI]
    calibration: object = None     # certkit.physics.calibration.GearCalibration, nominal, training runs
    refit: Refit | None = None     # the named effects' refit (None: abstained)
    chosen: tuple = ()             # the named effects' Candidates (forms), in the refit's order
    step_costs: tuple = ()         # training cost each step had to beat (before its refits)
    refit_decisions: tuple = ()    # per step, a Decision for each of its refits
    forms: tuple = ()              # the form of each named effect ("" for a one-form effect)
    noise: dict | None = None      # channel -> noise σ of the held-out records [SI]
    shares: dict | None = None     # channel -> (closed, unexplained) of the held-out gap
    caveats: tuple = ()            # held-out channels the named effects make worse, in words
    tie: tuple = ()                # the effects that could not be told apart (a tie)
    #: per step, the shapes of the force the model of that step misses on the training runs
    #: (:mod:`certkit.gap.missing_force`), model-free evidence for "which"
    evidence: tuple = ()
    #: effects beside the named ones whose refit fails the harm rule only: not named, and
    #: the records cannot say whether they are present too
    undecided: tuple = ()
    #: the nominal model calibrated again from a first-step refit's bare parameters (a
    #: Decision each, rule "calibrated again"), or found not settled (the last, rule "not
    #: settled": no effect named at the first step)
    recalibrated: tuple = ()

    def configure(self, model: DropModel) -> DropModel:
        """``model`` (nominal, of this gear, any run) as the diagnosis leaves it: the
        calibrated nominal parameters, or the refit with the named effects."""
        if self.refit is None:
            return self.calibration.apply(model)
        return self.refit.apply(self.calibration.knobs, model, self.chosen)


def _held_out(campaign, gear_id, held, configure) -> tuple[dict, dict]:
    """RMSE from touchdown of every channel of the held-out runs, (run, channel) -> [SI],
    and each channel's measured records from touchdown, channel -> [arrays]."""

    rmse, measured_records = {}, {}
    for run_id, record in aligned_records(campaign, gear_id, configure, list(held),
                                          effects=[]).items():
        for channel, measured in record.measured.items():
            difference = record.simulated[channel][record.after] - measured[record.after]
            rmse[(run_id, channel)] = float(np.sqrt(np.mean(difference ** 2)))
            measured_records.setdefault(channel, []).append(measured[record.after])
    return rmse, measured_records


def pooled(rmse: dict) -> dict:
    """Channel -> RMS over the runs of (run, channel) -> RMSE."""
    out: dict[str, list[float]] = {}
    for (_, channel), value in rmse.items():
        out.setdefault(channel, []).append(value * value)
    return {channel: float(np.sqrt(np.mean(values))) for channel, values in out.items()}


def _best_scored(attribution: Attribution) -> list[str]:
    """The :data:`LEADING` effects whose best forms score highest."""
    effects: list[str] = []
    for score in attribution.scores:
        if score.effect not in effects:
            effects.append(score.effect)
    return effects[:LEADING]


def _leading(profile: dict, relevant: set, names: dict) -> list[str]:
    """The best-profiled form of each relevant effect, for the :data:`LEADING` effects with
    the best profiles."""
    best: dict[str, str] = {}
    for key in sorted(relevant, key=lambda k: (profile[k][1], k)):
        best.setdefault(names[key].name, key)
    return list(best.values())[:LEADING]


def _training_harm(residuals: RunResiduals, base: np.ndarray, fitted: np.ndarray,
                   noise: dict) -> list[str]:
    """Training channels a refit makes worse beyond their noise."""
    before, after = residuals.channel_rmse(base), residuals.channel_rmse(fitted)
    return [channel for channel in before
            if harmed(before[channel], after[channel], noise.get(channel, 0.0))]


def _removed(residuals: RunResiduals, base: np.ndarray, fitted: np.ndarray,
             noise: dict) -> float:
    """What a refit removes from the training records, in noise variances summed over the
    channels (the measure :data:`DETECTABLE` bounds); a channel without noise is left out."""
    before, after = residuals.channel_rmse(base), residuals.channel_rmse(fitted)
    return float(sum((before[c] ** 2 - after[c] ** 2) / noise[c] ** 2
                     for c in before if noise.get(c, 0.0) > 0.0))


def _mistimed(residuals: RunResiduals, base: np.ndarray, fitted: np.ndarray,
              candidate: Candidate) -> tuple[str, float, float] | None:
    """(channel, shift [s], share) when ``candidate`` is memoryless on a recorded channel and
    its refit's correction fits that channel's residual better shifted in time, by
    :data:`TIMING_SHARE` or more of what stays (:func:`certkit.gap.residuals.shifted_fit`,
    on the training runs); None otherwise."""
    channel = candidate.memoryless_on
    rows = [(part, scale) for _, name, part, scale in residuals.segments() if name == channel]
    if not rows:
        return None
    shift, share = shifted_fit([base[part] * scale for part, scale in rows],
                               [(fitted[part] - base[part]) * scale for part, scale in rows],
                               1.0 / residuals.rate)
    return (channel, shift, share) if share >= TIMING_SHARE else None


@one_blas_thread
def diagnose(campaign, gear_id: str, split=None, candidates=CANDIDATES,
             calibration=None) -> Diagnosis:
    """Which effect(s) of the library explain the gap of ``gear_id``'s nominal model (the
    rules: this module's docstring).

    ``split``: (training, held-out) run ids (default: :func:`certkit.gap.holdout.split_for`);
    ``calibration``: the nominal model already calibrated on the training runs (saves
    doing it again)."""

    training, held = split or split_for(campaign, gear_id)[:2]
    if calibration is None:
        calibration = nominal_calibration(campaign, gear_id, training)
    residuals = RunResiduals(campaign, gear_id, list(training), effects=[])
    training_noise = {channel: noise_level(records)
                      for channel, records in residuals.measured().items()}
    chosen: list[Candidate] = []
    current: Refit | None = None
    cost = calibration.fit.cost
    steps, statement, step_costs, refit_notes, tie, evidence = [], "", [], [], (), []
    undecided: tuple = ()
    names = {c.key: c for c in candidates}
    recalibrated: list[Decision] = []
    while len(step_costs) < 2:
        x = list(current.values) + list(current.strengths) if current else None
        models = (configured(residuals, calibration.knobs, chosen, x) if current
                  else [calibration.apply(m) for m in residuals.models])
        jacobian = nominal_jacobian(residuals, calibration) if current is None else \
            central_jacobian(residuals, current.fit.parameters, x,
                             lambda v: configured(residuals, calibration.knobs, chosen, v))
        named_effects = {c.name for c in chosen}
        remaining = [c for c in candidates if c.name not in named_effects]
        # a form that cannot be added to this model (its family is empty there) is not
        # scored, and the reason is recorded: it would only fail to build
        unfit = {c.key: c.why_not(models[0]) for c in remaining}
        skipped = tuple(Decision(key, "cannot be added", {"why": why})
                        for key, why in unfit.items() if why)
        remaining = [c for c in remaining if not unfit[c.key]]
        attribution = replace(score_candidates(residuals, models, jacobian, remaining),
                              skipped=skipped)
        profile = profiles(residuals, calibration, chosen, remaining, current, jacobian)
        attribution = replace(attribution, profiles={n: (float(v[-1]), c)
                                                     for n, (v, c) in profile.items()})
        relevant = {s.name for s in attribution.scores
                    if s.effect in _best_scored(attribution) and s.explained >= RELEVANT}
        relevant |= {n for n in profile if profile[n][1] <= (1 - GAIN) * cost}
        leading = _leading(profile, relevant, names)
        fits = [refit(residuals, calibration, chosen + [names[n]], start=profile[n][0])
                for n in leading]
        if current is None:
            again, decision = _calibrated_again(campaign, gear_id, training, residuals,
                                                calibration, fits, len(recalibrated))
            if decision is not None:
                recalibrated.append(decision)
            if again is not None:
                # the step again, against the nominal model calibrated from where a refit's
                # bare parameters lay
                calibration, cost = again, again.fit.cost
                continue
        step_costs.append(cost)
        attribution = replace(attribution, relevant=tuple(sorted(relevant)),
                              decisions=_decisions(attribution, relevant, leading, names),
                              no_refit=None if fits else Decision(
                                  "", "none refitted", {"relevant": RELEVANT, "gain": GAIN}))
        steps.append((attribution, fits))
        base = residuals.evaluate([models])[0]
        fitted = residuals.evaluate([configured(residuals, calibration.knobs,
                                                 [names[k] for k in f.effects],
                                                 list(f.values) + list(f.strengths))
                                     for f in fits]) if fits else []
        harm = {f.effects: _training_harm(residuals, base, r, training_noise)
                for f, r in zip(fits, fitted)}
        removed = {f.effects: _removed(residuals, base, r, training_noise)
                   for f, r in zip(fits, fitted)}
        mistimed = {f.effects: _mistimed(residuals, base, r, names[f.effects[-1]])
                    for f, r in zip(fits, fitted)}
        # each refit is judged once; the filter and the record both read the judgement
        refused = {f.effects: judge(f, cost, harm[f.effects], removed[f.effects],
                                    mistimed[f.effects]) for f in fits}
        if unsettled(recalibrated) and current is None:
            # the bare parameters still fit better than the calibration: every refit would
            # be credited with some of what they can do, so none is named
            refused = {f.effects: refused[f.effects] or Decision(
                _joined(f), "not settled", dict(recalibrated[-1].figures)) for f in fits}
        useful = sorted((f for f in fits if refused[f.effects] is None),
                        key=lambda f: f.training_cost)
        evidence.append(tuple(signatures(campaign_missing_forces(
            campaign, gear_id, training,
            lambda m: current.apply(calibration.knobs, m, chosen) if current
            else calibration.apply(m)))))
        best = useful[0] if useful else None
        broken = {}
        if best is not None and len(useful) > 1 and \
                useful[1].training_cost <= TIE_COST * best.training_cost:
            best, broken = _break_tie(best, useful[1], names, evidence[-1])
            if best is None:
                tie = (names[useful[0].effects[-1]].name, names[useful[1].effects[-1]].name)
                statement = _tie_statement(chosen, useful[0], useful[1], names, attribution)
        refit_notes.append(refit_decisions(fits, refused, best if not tie else None, tie,
                                           names, broken, cost))
        if best is None and chosen and not tie:
            # beside the named effects, a refit that fails the harm rule only is undecided
            undecided = tuple((names[f.effects[-1]], refused[f.effects]) for f in fits
                              if refused[f.effects] is not None
                              and refused[f.effects].rule == "harm"
                              and refused[f.effects].figures["alone"])
        if tie:
            break
        if best is None:
            break
        chosen.append(names[best.effects[-1]])
        current, cost = best, best.training_cost
    answer = tuple(c.name for c in chosen)
    if not statement:
        statement = statements.answer_words(chosen, not unsettled(recalibrated))
    statement = statements.recalibrated_words(recalibrated) + statement
    if any(c.name == "load-cell gain" for c in chosen):
        gain = current.apply(calibration.knobs, residuals.models[0],
                             chosen).effect("load-cell gain")
        delay = _crosstalk_alike(campaign, gear_id, training, gain,
                                 lambda m: current.apply(calibration.knobs, m, chosen),
                                 training_noise.get("load", 0.0))
        if delay is not None:
            statement += statements.crosstalk_words(gain.gain, delay)
    if undecided:
        statement += statements.undecided_words(chosen, undecided)
    before, measured = _held_out(campaign, gear_id, held, calibration.apply)
    rmse = {("nominal",) + key: value for key, value in before.items()}
    noise = {channel: noise_level(records) for channel, records in measured.items()}
    shares, caveats = None, ()
    if current is not None:
        after, _ = _held_out(campaign, gear_id, held,
                             lambda m: current.apply(calibration.knobs, m, chosen))
        rmse.update({("with " + " and ".join(answer),) + key: value
                     for key, value in after.items()})
        pooled_before, pooled_after = pooled(before), pooled(after)
        shares = {channel: gap_shares(pooled_before[channel], pooled_after[channel],
                                      noise[channel]) for channel in pooled_before}
        caveats = tuple(channel for channel in pooled_before
                        if harmed(pooled_before[channel], pooled_after[channel], noise[channel]))
        statement += statements.held_out_words(shares, caveats, len(answer), FLOOR_CHANNEL)
    return Diagnosis(gear_id, tuple(training), tuple(held), answer, statement, steps, rmse,
                     calibration, current, tuple(chosen), tuple(step_costs),
                     tuple(refit_notes), tuple(c.form for c in chosen), noise, shares,
                     caveats, tie, tuple(evidence),
                     tuple(candidate.name for candidate, _ in undecided),
                     tuple(recalibrated))


def unsettled(recalibrated) -> bool:
    """Whether the last record of :func:`_calibrated_again` says the nominal calibration
    did not settle (a better fit of the bare parameters remained after :data:`RESTARTS`)."""
    return bool(recalibrated) and recalibrated[-1].rule == "not settled"


def _calibrated_again(campaign, gear_id: str, training, residuals: RunResiduals,
                      calibration, fits: list, done: int) -> tuple:
    """(the nominal model calibrated again or None, the Decision that records what was
    found or None), after ``done`` earlier restarts.

    Nothing happens (None, None) unless the bare parameters of one of the first step's
    refits, its effect left out, fit the training runs better than the calibration by more
    than :data:`RECALIBRATE` of its cost: the calibration did not reach the best fit of the
    bare parameters, and an effect's refit would be credited with what they can do.  Then
    the nominal model is calibrated again from the refit's bare parameters that fit best
    (rule "calibrated again"), and kept when it too beats the first by more than
    :data:`RECALIBRATE`.  When it does not, or :data:`RESTARTS` calibrations were done
    already, the calibration is recorded as not settled (rule "not settled") and no effect
    is named at this step."""
    if not fits:
        return None, None
    count = len(calibration.knobs)
    vectors = residuals.evaluate([configured(residuals, calibration.knobs, [],
                                             list(f.values[:count])) for f in fits])
    costs = [float(np.sqrt(np.mean(v ** 2))) for v in vectors]
    best = int(np.argmin(costs))
    limit = (1.0 - RECALIBRATE) * calibration.fit.cost
    if not costs[best] < limit:
        return None, None
    start = list(fits[best].values[:count])
    figures = {"from": _joined(fits[best]), "cost_before": float(calibration.fit.cost), "start_cost": costs[best],
               "recalibrate": RECALIBRATE, "restarts": RESTARTS, "done": done,
               "estimate_before": {k.name: float(v) for k, v in
                                   zip(calibration.knobs, calibration.fit.estimate)},
               "start": {k.name: float(v) for k, v in zip(calibration.knobs, start)}}
    if done >= RESTARTS:
        return None, Decision(_joined(fits[best]), "not settled", figures)
    again = calibrate_gear(campaign, gear_id, knobs=[k.name for k in calibration.knobs],
                           effects=[], run_ids=list(training), start=start)
    figures["cost_after"] = float(again.fit.cost)
    if not again.fit.cost < limit:
        return None, Decision(_joined(fits[best]), "not settled", figures)
    # the record of the first calibration's further starts goes with the calibration
    return (replace(again, search=calibration.search),
            Decision(_joined(fits[best]), "calibrated again", figures))


def _crosstalk_alike(campaign, gear_id: str, training, gain, configure,
                     noise: float) -> float | None:
    """The delay d [s] of the crosstalk F(t) + ε·F(t − d) that records the training runs'
    load as the named gain ε with its skew τ does, (1 + ε)·F(t − τ), to within the load's
    noise (to first order d = τ·(1 + ε)/ε, for ε·τ > 0; F: the load the named effects'
    model simulates without the recorder's gain and skew); None when there is no such
    crosstalk or the two records differ by the noise or more.  The difference is taken
    over the load pulse only (the samples where F is at least :data:`PULSE_SHARE` of its
    peak), so that a long quiet tail cannot dilute it."""
    if not gain.gain * gain.skew > 0:
        return None
    delay = gain.skew * (1.0 + gain.gain) / gain.gain
    squares, count = 0.0, 0
    for record in aligned_records(campaign, gear_id,
                                  lambda m: set_effect(configure(m), "load-cell gain",
                                                       gain=0.0, skew=0.0),
                                  list(training), effects=[]).values():
        time, force = record.time, record.simulated["load"]
        skewed = (1.0 + gain.gain) * np.interp(time - gain.skew, time, force, left=0.0)
        crosstalk = force + gain.gain * np.interp(time - delay, time, force, left=0.0)
        pulse = record.after & (np.abs(force) >= PULSE_SHARE * np.max(np.abs(force)))
        squares += float(np.sum((skewed - crosstalk)[pulse] ** 2))
        count += int(np.count_nonzero(pulse))
    return delay if count and np.sqrt(squares / count) < noise else None


def _break_tie(best: Refit, other: Refit, names: dict, evidence) -> tuple:
    """(the refit to name, or None for a tie; {effects: Decision} for the two refits when the
    tie was broken): the model-free missing force decides a near-tie when it shows the mark
    of one of the two effects and not of the other, whichever has the lower training cost."""
    pointed = pointed_effects(list(evidence))
    a, b = names[best.effects[-1]].name, names[other.effects[-1]].name
    if (a in pointed) == (b in pointed):
        return None, {}
    (winner, marked), (loser, unmarked) = ((best, a), (other, b)) if a in pointed \
        else ((other, b), (best, a))
    figures = {"marked": marked, "unmarked": unmarked, "share": float(pointed[marked]),
               "tie_cost": TIE_COST}
    return winner, {
        winner.effects: Decision(_joined(winner), "tie broken",
                                 {**figures, "named": True, "other": unmarked}),
        loser.effects: Decision(_joined(loser), "tie broken",
                                {**figures, "named": False, "other": marked})}


def _tie_statement(chosen, best: Refit, other: Refit, names: dict,
                   attribution: Attribution) -> str:
    a, b = best.effects[-1], other.effects[-1]
    cosine = attribution.confusability.get((a, b), attribution.confusability.get((b, a), 0.0))
    return statements.tie_words(chosen, names[a].name, names[b].name,
                                (best.training_cost, other.training_cost), cosine, TIE_COST)


def _joined(refitted: Refit) -> str:
    return " + ".join(refitted.effects)


def _decisions(attribution: Attribution, relevant: set, leading: list, names: dict) -> tuple:
    """What became of each scored candidate form at one step: refitted (the best form of
    one of the :data:`LEADING` relevant effects with the best profiles), relevant but not
    refitted, or not relevant (and why)."""
    decisions = []
    for score in attribution.scores:
        if score.name in leading:
            decision = Decision(score.name, "refitted")
        elif score.name in relevant and any(names[k].name == names[score.name].name
                                            for k in leading):
            decision = Decision(score.name, "other form refitted")
        elif score.name in relevant:
            decision = Decision(score.name, "not leading", {"leading": LEADING})
        elif score.direction < 0:
            decision = Decision(score.name, "points the other way", {"gain": GAIN})
        else:
            decision = Decision(score.name, "not relevant",
                                {"relevant": RELEVANT, "leading": LEADING, "gain": GAIN})
        decisions.append(decision)
    return tuple(decisions)


def judge(refitted: Refit, cost: float, harm: list, removed: float,
          mistimed: tuple | None) -> Decision | None:
    """Why a refit cannot be named, by the first rule it fails (None: it can be): it must
    cut the training cost by :data:`GAIN`, harm no training channel beyond its noise,
    remove :data:`DETECTABLE` noise variances, and, for an error of a recorded channel, fit
    the residual at the same instant (:data:`TIMING_SHARE`)."""
    name = _joined(refitted)
    cut = 1.0 - refitted.training_cost / cost if cost > 0 else 0.0
    if refitted.training_cost > (1 - GAIN) * cost:
        return Decision(name, "gain", {"cut": float(cut), "gain": GAIN})
    if harm:
        # "alone": harm is the only rule it fails; beside a named effect that makes it
        # undecided (:func:`diagnose`): the records cannot say whether it is present too
        alone = removed >= DETECTABLE and mistimed is None
        return Decision(name, "harm", {"channels": list(harm), "cut": float(cut),
                                       "alone": bool(alone)})
    if removed < DETECTABLE:
        return Decision(name, "detectable", {"removed": float(removed), "detectable": DETECTABLE})
    if mistimed is not None:
        channel, shift, share = mistimed
        return Decision(name, "timing", {"channel": channel, "shift_s": float(shift),
                                         "share": float(share), "timing_share": TIMING_SHARE})
    return None


def refit_decisions(fits: list, refused: dict, named: Refit | None, tie: tuple, names: dict,
                    broken: dict, cost: float) -> tuple:
    """What became of each refit of one step: refused by a rule (``refused``, from
    :func:`judge`), broken out of a near-tie by the missing force (``broken``), named, one of
    a tie, or admissible with a higher training cost than the named refit."""
    decisions = []
    for refitted in fits:
        effect = names[refitted.effects[-1]].name
        name = _joined(refitted)
        if refitted.effects in broken:
            decision = broken[refitted.effects]
        elif refused[refitted.effects] is not None:
            decision = refused[refitted.effects]
        elif named is not None and refitted is named:
            decision = Decision(name, "named",
                                {"cut": float(1.0 - refitted.training_cost / cost)})
        elif effect in tie:
            other = tie[1] if effect == tie[0] else tie[0]
            decision = Decision(name, "tie", {"other": other, "tie_cost": TIE_COST})
        elif named is not None:
            decision = Decision(name, "outranked",
                                {"cost": float(refitted.training_cost),
                                 "named": names[named.effects[-1]].name,
                                 "named_cost": float(named.training_cost)})
        else:
            decision = Decision(name, "after a tie", {"tie": list(tie)})
        decisions.append(decision)
    return tuple(decisions)
