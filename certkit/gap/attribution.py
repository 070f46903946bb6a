"""Which unmodelled effect explains a residual: score (Lagrange-multiplier) tests of each
candidate effect of the library against the calibrated nominal model.

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

from dataclasses import dataclass, field, replace

import numpy as np

from certkit.physics.drop_model import DropModel
from certkit.physics.effects import CANDIDATES, Candidate
from certkit.physics.calibration import FIT_STEP
from certkit.physics.fitting import FitParameter, fit, jacobian_at


@dataclass(frozen=True)
class Score:
    name: str              # the candidate form's key (Candidate.key)
    statistic: float       # LM_k
    direction: float       # sign of the best strength: +1 the effect, −1 its opposite
    projected_norm: float  # ‖P⊥s_k‖: how much of the signature re-tuning cannot absorb
    explained: float       # RMS of the residual the effect would remove, in units of σ
    effect: str = ""       # the effect the form belongs to

    # With thousands of samples a systematic misfit far below the noise is already
    # "significant" (LM ≫ χ²₁); whether it matters is ``explained``: √(LM/N).


@dataclass(frozen=True)
class Attribution:
    scores: tuple          # Score, best first
    confusability: dict    # (name, name) -> |cos| of the projected signatures
    sigma2: float
    profiles: dict | None = None   # name -> (best strength of STARTS, its profile cost)
    relevant: tuple = ()           # the names that qualified for a refit (see diagnose)
    #: what became of each candidate at this step, in score order (a Decision each)
    decisions: tuple = ()
    #: why no candidate was refitted at this step (a Decision; None when some were)
    no_refit: object = None
    #: the forms not scored at this step because they cannot be added to the model (a
    #: Decision each, with the form's own reason: :meth:`Candidate.why_not`)
    skipped: tuple = ()


@dataclass(frozen=True)
class Decision:
    """What the diagnosis decided about one candidate, or one refit, and why: recorded where
    the rule is applied (:mod:`certkit.gap.selection`), so the report only puts it in words
    (:func:`certkit.gap.statements.decision_words`) and never re-derives it."""

    name: str        # the candidate, or the refit's effects joined by " + "
    rule: str        # the rule that decided (see certkit.gap.statements.RULES)
    #: the figures and thresholds the rule compared, as it compared them (JSON-ready)
    figures: dict = field(default_factory=dict)


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
        projected[candidate.key] = p
        norm2 = float(p @ p)
        # r = measured − … is simulated − measured here: adding the effect changes the
        # residual by φ·s, so the strength that reduces it has the sign of −sᵀP⊥r
        inner = float(p @ projected_r)
        statistic = inner * inner / (sigma2 * norm2) if norm2 > 0 and sigma2 > 0 else 0.0
        direction = -float(np.sign(inner))
        # an effect acts with a positive strength only: explaining the residual with the
        # effect reversed is no explanation
        statistic = statistic if direction > 0 else 0.0
        scores.append(Score(candidate.key, statistic, direction, float(np.sqrt(norm2)),
                            float(np.sqrt(statistic / r.size)), candidate.name))
    scores.sort(key=lambda s: -s.statistic)
    names = [c.key for c in candidates]
    confusability = {}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            pa, pb = projected[a], projected[b]
            denominator = float(np.linalg.norm(pa) * np.linalg.norm(pb))
            confusability[(a, b)] = abs(float(pa @ pb)) / denominator if denominator else 0.0
    return Attribution(tuple(scores), confusability, sigma2)


def central_jacobian(residuals, parameters, values, models_at) -> np.ndarray:
    """∂r/∂x at ``values`` by the differences of the drop-model fits
    (:func:`certkit.physics.fitting.jacobian_at`: central, one-sided next to a bound, a step
    of :data:`~certkit.physics.calibration.FIT_STEP` of each parameter's size), every
    stencil point in one batch; ``parameters``: the fit's parameters of ``values`` (their
    bounds and sizes); ``models_at(x)`` gives the models (one per run) at x."""
    return jacobian_at(lambda matrix: residuals.evaluate([models_at(x) for x in matrix]),
                       parameters, values, relative_step=FIT_STEP)


def form_knobs(candidates) -> list:
    """The knobs the candidate forms fit with their strengths (:attr:`Candidate.knobs`), in
    order."""
    return [knob for candidate in candidates for knob, _ in candidate.knobs]


def form_starts(candidates) -> list[float]:
    """Where :func:`form_knobs` start (the first of each knob's profile points)."""
    return [float(starts[0]) for candidate in candidates for _, starts in candidate.knobs]


def _own_points(candidate) -> list[list[float]]:
    """Every combination of the profile points of a candidate's own knobs ([[]]: none)."""
    points = [[]]
    for _, starts in candidate.knobs:
        points = [p + [float(s)] for p in points for s in starts]
    return points


def configured(residuals, knobs, candidates, x) -> list[DropModel]:
    """The runs' models at x = [the knobs, the candidates' own knobs (:func:`form_knobs`),
    the candidates' strengths]: the knobs written, the candidates added, then their own
    knobs written (they set parameters of the added terms)."""
    models = []
    extras = form_knobs(candidates)
    n, e = len(knobs), len(extras)
    for base in residuals.models:
        model = base
        for knob, value in zip(knobs, x[:n]):
            model = knob.write(model, float(value))
        for candidate, strength in zip(candidates, x[n + e:]):
            model = candidate.add(model, float(strength))
        for knob, value in zip(extras, x[n:n + e]):
            model = knob.write(model, float(value))
        models.append(model)
    return models


def nominal_jacobian(residuals, calibration) -> np.ndarray:
    """∂r/∂θ of a calibration's knobs at its estimate."""
    return central_jacobian(residuals, calibration.fit.parameters, calibration.fit.estimate,
                            lambda x: configured(residuals, calibration.knobs, [], x))


# --------------------------------------------------------------------------- refits
@dataclass(frozen=True)
class Refit:
    """The nominal parameters and some candidate effects' strengths fitted together."""

    effects: tuple[str, ...]
    strengths: tuple[float, ...]
    strength_errors: tuple[float, ...]
    #: nominal knobs, calibrated again, then the forms' own knobs (:func:`form_knobs`)
    values: tuple[float, ...]
    training_cost: float               # RMS normalised residual on the training runs
    fit: object                        # certkit.physics.fitting.FitResult

    def apply(self, knobs, model: DropModel, candidates) -> DropModel:
        return configured(_One(model), knobs, candidates,
                          list(self.values) + list(self.strengths))[0]


@dataclass(frozen=True)
class _One:
    """One model, as :func:`configured` reads runs' models."""

    model: DropModel

    @property
    def models(self):
        return [self.model]


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
    for candidate in candidates:
        points = [np.array(values + own + strengths + [s]) for own in _own_points(candidate)
                  for s in STARTS]
        # a batch per strength: the stiffest strength of a stiff candidate (a stiff leg, a
        # fast heat exchange) sets only its own integration step
        vectors = [residuals.evaluate([configured(residuals, calibration.knobs,
                                                   chosen + [candidate], x)])[0]
                   for x in points]
        for x, r in zip(points, vectors):
            r = r - q @ (q.T @ r)
            cost = float(np.sqrt(np.mean(r * r)))
            if candidate.key not in best or cost < best[candidate.key][1]:
                best[candidate.key] = (x, cost)
    return best


def refit(residuals, calibration, candidates: list[Candidate],
          max_strength: float = MAX_STRENGTH, start=None) -> Refit:
    """Fit the calibration's knobs and the strengths (bounded to [0, ``max_strength``] of
    each candidate's unit size) on the runs of ``residuals``, from ``start`` (knobs then
    strengths; default: the calibration's estimate and every candidate at its probe).

    Each parameter keeps one size wherever the refit starts (the floor of its
    finite-difference step, :data:`~certkit.physics.calibration.FIT_STEP` of it): a knob
    the calibration's, a form's own knob that of its default start, a strength the
    candidate's probe."""

    knobs = calibration.knobs
    extras = form_knobs(candidates)
    if start is None:
        start = (list(calibration.fit.estimate) + form_starts(candidates)
                 + [c.probe for c in candidates])
    start = [float(v) for v in start]
    parameters = [replace(p, nominal=min(max(v, p.lower), p.upper))
                  for p, v in zip(calibration.fit.parameters, start)]
    for knob, v, default in zip(extras, start[len(knobs):len(knobs) + len(extras)],
                                form_starts(candidates)):
        lower, upper = knob.bounds(0.0)
        sized = FitParameter(knob.name, knob.unit, min(max(default, lower), upper), lower, upper)
        parameters.append(replace(sized, nominal=min(max(v, lower), upper)))
    parameters += [FitParameter(f"{c.key} strength", "1", min(max(v, 0.0), max_strength), 0.0,
                                max_strength, size=c.probe)
                   for c, v in zip(candidates, start[len(knobs) + len(extras):])]

    def many(matrix):
        return residuals.evaluate([configured(residuals, knobs, candidates, x)
                                   for x in matrix])

    # forward differences: refits are compared at GAIN (10 %) apart, far above their
    # truncation error, and cost half the simulations of central ones
    result = fit(lambda x: many(np.asarray(x)[None, :])[0], parameters, residuals_many=many,
                 max_evaluations=40, tolerance=REFIT_TOLERANCE, relative_step=FIT_STEP,
                 differences="forward")
    k = len(knobs) + len(extras)
    return Refit(tuple(c.key for c in candidates), tuple(map(float, result.estimate[k:])),
                 tuple(map(float, result.standard_error[k:])),
                 tuple(map(float, result.estimate[:k])), result.cost, result)
