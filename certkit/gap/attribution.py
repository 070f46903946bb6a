"""Which unmodelled effect explains a residual: score (Lagrange-multiplier) tests of each
candidate effect of the library against the calibrated nominal model (issue 5, step 3).

For a candidate k with strength φ_k (0: the effect is absent, so the candidate nests the
nominal model), its signature s_k = ∂r/∂φ_k at φ_k = 0⁺ is a finite difference of the
normalised residuals r (:class:`certkit.physics.calibration.RunResiduals`).  What re-tuning the
nominal parameters can absorb is projected out: P⊥ = I − J(JᵀJ)⁻¹Jᵀ with J = ∂r/∂θ at the
calibrated θ.  The score statistic is LM_k = (s_kᵀP⊥r)²/(σ²·s_kᵀP⊥s_k), σ² the residual
variance; the candidates are ranked by it, and the cosine of their projected signatures is
the a-priori confusability.  The score test is Rao's (Proc. Cambridge Philos. Soc. 44,
1948); for its use against a nested alternative see Engle, "Wald, likelihood ratio and
Lagrange multiplier tests in econometrics", Handbook of Econometrics II, ch. 13, 1984.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from certkit.display import percent
from certkit.gap.holdout import split_for
from certkit.physics.calibration import RunResiduals, aligned_records, calibrate_gear
from certkit.physics.drop_model import DropModel
from certkit.physics.effects import CANDIDATES, Candidate
from certkit.physics.fitting import FitParameter, fit


@dataclass(frozen=True)
class Score:
    name: str
    statistic: float       # LM_k
    direction: float       # sign of the best strength: +1 the effect, −1 its opposite
    projected_norm: float  # ‖P⊥s_k‖: how much of the signature re-tuning cannot absorb
    explained: float       # RMS of the residual the effect would remove, in units of σ

    # With thousands of samples a systematic misfit far below the noise is already
    # "significant" (LM ≫ χ²₁); whether it matters is ``explained``: √(LM/N).


@dataclass(frozen=True)
class Attribution:
    scores: tuple          # Score, best first
    confusability: dict    # (name, name) -> |cos| of the projected signatures
    sigma2: float
    profiles: dict | None = None   # name -> (best strength of STARTS, its profile cost)
    relevant: tuple = ()           # the names that qualified for a refit (see diagnose)
    #: what became of each candidate at this step, in score order (see :func:`_decisions`)
    decisions: tuple = ()
    #: why no candidate was refitted at this step ("" when some were)
    no_refit: str = ""


@dataclass(frozen=True)
class Decision:
    """What the diagnosis decided about one candidate, or one refit, and why: recorded where
    the rule is applied, so the report states it and never re-derives it."""

    name: str        # the candidate, or the refit's effects joined by " + "
    status: str      # the decision in words, with the thresholds that made it


def score_candidates(residuals, models: list[DropModel], nominal_jacobian: np.ndarray,
                     candidates=CANDIDATES) -> Attribution:
    """LM statistic of every candidate at the calibrated ``models`` (one per run).

    ``residuals``: a :class:`~certkit.physics.calibration.RunResiduals`; ``nominal_jacobian``:
    ∂r/∂θ of the calibrated nominal parameters (columns), at the same models.
    """
    sets = [models] + [[c.add(m, c.probe) for m in models] for c in candidates]
    values = residuals.evaluate(sets)
    r = values[0]
    signatures = (values[1:] - r) / np.array([c.probe for c in candidates])[:, None]
    q, _ = np.linalg.qr(nominal_jacobian)
    def project(v):
        return v - q @ (q.T @ v)
    dof = max(r.size - nominal_jacobian.shape[1], 1)
    projected_r = project(r)
    sigma2 = float(projected_r @ projected_r) / dof
    scores, projected = [], {}
    for candidate, s in zip(candidates, signatures):
        p = project(s)
        projected[candidate.name] = p
        norm2 = float(p @ p)
        # r = measured − … is simulated − measured here: adding the effect changes the
        # residual by φ·s, so the strength that reduces it has the sign of −sᵀP⊥r
        inner = float(p @ projected_r)
        statistic = inner * inner / (sigma2 * norm2) if norm2 > 0 and sigma2 > 0 else 0.0
        direction = -float(np.sign(inner))
        # an effect acts with a positive strength only: explaining the residual with the
        # effect reversed is no explanation
        statistic = statistic if direction > 0 else 0.0
        scores.append(Score(candidate.name, statistic, direction, float(np.sqrt(norm2)),
                            float(np.sqrt(statistic / r.size))))
    scores.sort(key=lambda s: -s.statistic)
    names = [c.name for c in candidates]
    confusability = {}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            pa, pb = projected[a], projected[b]
            denominator = float(np.linalg.norm(pa) * np.linalg.norm(pb))
            confusability[(a, b)] = abs(float(pa @ pb)) / denominator if denominator else 0.0
    return Attribution(tuple(scores), confusability, sigma2)


def _central_jacobian(residuals, values, models_at, relative: float = 1e-4) -> np.ndarray:
    """∂r/∂x at ``values`` by central differences, every stencil point in one batch;
    ``models_at(x)`` gives the models (one per run) at parameter vector x."""
    values = np.asarray(values, dtype=float)
    sets, steps = [], []
    for index in range(values.size):
        h = relative * max(abs(values[index]), 1e-3)
        steps.append(h)
        for sign in (+1, -1):
            x = values.copy()
            x[index] += sign * h
            sets.append(models_at(x))
    r = residuals.evaluate(sets)
    return np.column_stack([(r[2 * i] - r[2 * i + 1]) / (2 * h) for i, h in enumerate(steps)])


def _configured(residuals, knobs, candidates, x) -> list[DropModel]:
    """The runs' models with the knobs at x[:k] and the candidates at strengths x[k:]."""
    models = []
    for base in residuals.models:
        model = base
        for knob, value in zip(knobs, x[:len(knobs)]):
            model = knob.write(model, float(value))
        for candidate, strength in zip(candidates, x[len(knobs):]):
            model = candidate.add(model, float(strength))
        models.append(model)
    return models


def nominal_jacobian(residuals, calibration) -> np.ndarray:
    """∂r/∂θ of a calibration's knobs at its estimate."""
    return _central_jacobian(residuals, calibration.fit.estimate,
                             lambda x: _configured(residuals, calibration.knobs, [], x))


# --------------------------------------------------------------------------- refits
@dataclass(frozen=True)
class Refit:
    """The nominal parameters and some candidate effects' strengths fitted together."""

    effects: tuple[str, ...]
    strengths: tuple[float, ...]
    strength_errors: tuple[float, ...]
    values: tuple[float, ...]          # nominal knobs, calibrated again
    training_cost: float               # RMS normalised residual on the training runs
    fit: object                        # certkit.physics.fitting.FitResult

    def apply(self, knobs, model: DropModel, candidates) -> DropModel:
        for knob, value in zip(knobs, self.values):
            model = knob.write(model, float(value))
        for candidate, strength in zip(candidates, self.strengths):
            model = candidate.add(model, float(strength))
        return model


#: Strengths (in units of a candidate's unit size) at which every candidate is profiled,
#: and from the best of which it is refitted: the effects are nonlinear in their strength
#: (a thermal time constant, a leg stiffness), so one start at the probe can stall far
#: from the optimum.
STARTS = (0.05, 0.2, 0.8, 3.2, 12.8)
MAX_STRENGTH = 20.0
#: Relative tolerance of the refits (scipy's ftol, xtol, gtol): they compare candidates
#: whose training costs differ by GAIN = 10 % or more, so 1e-4 is ample.
REFIT_TOLERANCE = 1e-4


def profiles(residuals, calibration, chosen: list[Candidate], candidates: list[Candidate],
             current: Refit | None, jacobian: np.ndarray) -> dict:
    """Each candidate's training cost at every strength of :data:`STARTS`, the knobs and
    chosen strengths held where they are (the calibration, or the current refit), less
    what re-tuning them absorbs to first order (the residual projected off ``jacobian``'s
    columns, ∂r/∂ of the knobs and chosen strengths).  Returns
    name -> (the best point: knobs, chosen strengths, its strength; its cost, an RMS
    normalised residual comparable with :attr:`Refit.training_cost`).

    The score test looks at an effect's first-order signature at zero strength; an effect
    that is strongly nonlinear in its strength (a gas that exchanges heat fast) can point
    the other way there and still explain the gap at a finite strength.  The profile sees
    it, and gives every refit a starting point near its optimum."""
    values = list(current.values) if current else list(calibration.fit.estimate)
    strengths = list(current.strengths) if current else []
    q, _ = np.linalg.qr(jacobian)
    best = {}
    for candidate in candidates:   # a batch each: a stiff candidate sets only its own step
        points = [np.array(values + strengths + [s]) for s in STARTS]
        vectors = residuals.evaluate([_configured(residuals, calibration.knobs,
                                                  chosen + [candidate], x) for x in points])
        for x, r in zip(points, vectors):
            r = r - q @ (q.T @ r)
            cost = float(np.sqrt(np.mean(r * r)))
            if candidate.name not in best or cost < best[candidate.name][1]:
                best[candidate.name] = (x, cost)
    return best


def refit(residuals, calibration, candidates: list[Candidate],
          max_strength: float = MAX_STRENGTH, start=None) -> Refit:
    """Fit the calibration's knobs and the strengths (bounded to [0, ``max_strength``] of
    each candidate's unit size) on the runs of ``residuals``, from ``start`` (knobs then
    strengths; default: the calibration's estimate and every candidate at its probe)."""

    knobs = calibration.knobs
    if start is None:
        start = list(calibration.fit.estimate) + [c.probe for c in candidates]
    start = [float(v) for v in start]
    parameters = [FitParameter(p.name, p.unit, min(max(v, p.lower), p.upper), p.lower, p.upper)
                  for p, v in zip(calibration.fit.parameters, start)]
    parameters += [FitParameter(f"{c.name} strength", "1", min(max(v, 0.0), max_strength), 0.0,
                                max_strength)
                   for c, v in zip(candidates, start[len(knobs):])]

    def many(matrix):
        return residuals.evaluate([_configured(residuals, knobs, candidates, x)
                                   for x in matrix])

    result = fit(lambda x: many(np.asarray(x)[None, :])[0], parameters, residuals_many=many,
                 max_evaluations=40, tolerance=REFIT_TOLERANCE)
    k = len(knobs)
    return Refit(tuple(c.name for c in candidates), tuple(map(float, result.estimate[k:])),
                 tuple(map(float, result.standard_error[k:])),
                 tuple(map(float, result.estimate[:k])), result.cost, result)


# --------------------------------------------------------------------------- the diagnosis
#: A candidate is considered only if it would remove at least this RMS (in noise units).
RELEVANT = 0.3
#: Refitted candidates whose training costs lie within this ratio and whose projected
#: signatures are this alike cannot be told apart.
TIE_COST, TIE_COSINE = 1.05, 0.9
#: A candidate must cut the training cost by at least this share to be named.
GAIN = 0.10
#: How many relevant candidates are refitted at each step (those with the best profiles):
#: two, so that the tie rule can compare the best pair.
LEADING = 2


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
    chosen: tuple = ()             # the named effects' Candidates, in the refit's order
    step_costs: tuple = ()         # training cost each step had to beat (before its refits)
    refit_decisions: tuple = ()    # per step, a Decision for each of its refits

    def configure(self, model: DropModel) -> DropModel:
        """``model`` (nominal, of this gear, any run) as the diagnosis leaves it: the
        calibrated nominal parameters, or the refit with the named effects."""
        if self.refit is None:
            return self.calibration.apply(model)
        return self.refit.apply(self.calibration.knobs, model, self.chosen)


def _held_out_rmse(campaign, gear_id, held, configure) -> dict:
    """RMSE from touchdown of every channel of the held-out runs: (run, channel) -> [SI]."""

    out = {}
    for run_id, record in aligned_records(campaign, gear_id, configure, list(held),
                                          effects=[]).items():
        for channel, measured in record.measured.items():
            difference = record.simulated[channel][record.after] - measured[record.after]
            out[(run_id, channel)] = float(np.sqrt(np.mean(difference ** 2)))
    return out


def diagnose(campaign, gear_id: str, split=None, candidates=CANDIDATES,
             calibration=None) -> Diagnosis:
    """Which effect(s) of the library explain the gap of ``gear_id``'s nominal model.

    Scores every candidate on the training runs and profiles it (:func:`profiles`);
    refits the :data:`LEADING` relevant ones with the best profiles (relevant: among the
    :data:`LEADING` best scores and explaining at least :data:`RELEVANT` noise RMS, or a
    profile that already cuts the cost by :data:`GAIN`) with the nominal parameters;
    names the one that cuts the training cost most (or abstains), then looks for a
    second one the same way.  The held-out runs are only evaluated.

    ``split``: (training, held-out) run ids (default: :func:`certkit.gap.holdout.split_for`);
    ``calibration``: the nominal model already calibrated on the training runs (saves
    doing it again)."""

    training, held = split or split_for(campaign, gear_id)[:2]
    if calibration is None:
        calibration = calibrate_gear(campaign, gear_id, effects=[], run_ids=list(training))
    residuals = RunResiduals(campaign, gear_id, list(training), effects=[])
    chosen: list[Candidate] = []
    current: Refit | None = None
    cost = calibration.fit.cost
    steps, statement, step_costs = [], "", []
    names = {c.name: c for c in candidates}
    for _ in range(2):
        step_costs.append(cost)
        models = (_configured(residuals, calibration.knobs, chosen,
                              list(current.values) + list(current.strengths))
                  if current else [calibration.apply(m) for m in residuals.models])
        jacobian = nominal_jacobian(residuals, calibration) if current is None else \
            _central_jacobian(residuals, list(current.values) + list(current.strengths),
                              lambda x: _configured(residuals, calibration.knobs, chosen, x))
        remaining = [c for c in candidates if c not in chosen]
        attribution = score_candidates(residuals, models, jacobian, remaining)
        profile = profiles(residuals, calibration, chosen, remaining, current, jacobian)
        attribution = replace(attribution, profiles={n: (float(x[-1]), c)
                                                     for n, (x, c) in profile.items()})
        relevant = {s.name for s in attribution.scores[:LEADING] if s.explained >= RELEVANT}
        relevant |= {n for n in profile if profile[n][1] <= (1 - GAIN) * cost}
        leading = sorted(relevant, key=lambda n: (profile[n][1], n))[:LEADING]
        fits = [refit(residuals, calibration, chosen + [names[n]], start=profile[n][0])
                for n in leading]
        attribution = replace(attribution, relevant=tuple(sorted(relevant)),
                              decisions=_decisions(attribution, relevant, leading),
                              no_refit="" if fits else _NO_REFIT)
        steps.append((attribution, fits))
        useful = sorted((f for f in fits if f.training_cost <= (1 - GAIN) * cost),
                        key=lambda f: f.training_cost)
        if not useful:
            if not chosen:
                statement = "No effect in the library explains the gap."
            break
        best = useful[0]
        if len(useful) > 1:
            other = useful[1]
            a, b = best.effects[-1], other.effects[-1]
            cosine = attribution.confusability.get((a, b), attribution.confusability.get((b, a), 0))
            if other.training_cost <= TIE_COST * best.training_cost and cosine >= TIE_COSINE:
                tie = (f"{a} and {b} cannot be told apart with these channels "
                       f"(training costs {best.training_cost:.4g} and "
                       f"{other.training_cost:.4g}; signature cosine {cosine:.2f}).")
                statement = (tie if not chosen else
                             f"The gap is explained by {' and '.join(c.name for c in chosen)}; "
                             f"as a second effect, {tie}")
                break
        chosen.append(names[best.effects[-1]])
        current, cost = best, best.training_cost
    answer = tuple(c.name for c in chosen)
    if answer and not statement:
        statement = "The gap is explained by " + " and ".join(answer) + "."
    before = _held_out_rmse(campaign, gear_id, held, calibration.apply)
    rmse = {("nominal",) + key: value for key, value in before.items()}
    if current is not None:
        after = _held_out_rmse(campaign, gear_id, held,
                               lambda m: current.apply(calibration.knobs, m, chosen))
        rmse.update({("with " + " and ".join(answer),) + key: value
                     for key, value in after.items()})
    return Diagnosis(gear_id, tuple(training), tuple(held), answer, statement, steps, rmse,
                     calibration, current, tuple(chosen), tuple(step_costs),
                     _refit_decisions(steps, answer, step_costs))


_NO_REFIT = (f"No candidate would remove {RELEVANT:g} σ or more, nor cut the training cost "
             f"by {percent(GAIN, 0)} in its profile: none was refitted.")


def _decisions(attribution: Attribution, relevant: set, leading: list) -> tuple:
    """What became of each scored candidate at one step: refitted (relevant and among the
    :data:`LEADING` best profiles), relevant but not refitted, or not relevant (and why)."""
    decisions = []
    for score in attribution.scores:
        if score.name in leading:
            status = "refitted"
        elif score.name in relevant:
            status = f"relevant, not among the {LEADING} best profiles"
        elif score.direction < 0:
            status = ("its score points the other way and its profile cuts the training "
                      f"cost by less than {percent(GAIN, 0)}: not relevant")
        else:
            status = (f"not among the {LEADING} best scores with {RELEVANT:g} σ or more, "
                      f"and its profile cuts the training cost by less than "
                      f"{percent(GAIN, 0)}: not relevant")
        decisions.append(Decision(score.name, status))
    return tuple(decisions)


def _refit_decisions(steps: list, answer: tuple, step_costs: list) -> tuple:
    """Per step, what became of each refit: named, or not named and why."""
    out = []
    for index, (_, fits) in enumerate(steps):
        named = tuple(answer[:index + 1])
        decisions = []
        for refitted in fits:
            if refitted.effects == named and len(named) == index + 1:
                status = "named"
            elif refitted.training_cost > (1 - GAIN) * step_costs[index]:
                status = f"cuts the training cost by less than {percent(GAIN, 0)}: not named"
            else:
                status = (f"cuts the training cost by {percent(GAIN, 0)} or more; not named "
                          f"(see the statement)")
            decisions.append(Decision(" + ".join(refitted.effects), status))
        out.append(tuple(decisions))
    return tuple(out)
