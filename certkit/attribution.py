"""Which unmodelled effect explains a residual: score (Lagrange-multiplier) tests of each
candidate effect of the library against the calibrated nominal model (issue 5, step 3).

For a candidate k with strength φ_k (0: the effect is absent, so the candidate nests the
nominal model), its signature s_k = ∂r/∂φ_k at φ_k = 0⁺ is a finite difference of the
normalised residuals r (:class:`certkit.calibration.RunResiduals`).  What re-tuning the
nominal parameters can absorb is projected out: P⊥ = I − J(JᵀJ)⁻¹Jᵀ with J = ∂r/∂θ at the
calibrated θ.  The score statistic is LM_k = (s_kᵀP⊥r)²/(σ²·s_kᵀP⊥s_k), σ² the residual
variance; the candidates are ranked by it, and the cosine of their projected signatures is
the a-priori confusability (gap-diagnosis.md §2.7, §3).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from .drop_model import DropModel
from .effects import GasHeatTransfer, LegFlexibility, ReboundOrifice, SealFriction, TyreHysteresis
from .units import STANDARD_GRAVITY


@dataclass(frozen=True)
class Candidate:
    """An effect of the library as a one-parameter family nesting the nominal model."""

    name: str
    unit_size: str                                   # what strength 1 means, in words
    add: Callable[[DropModel, float], DropModel]     # the model with the effect at strength φ
    probe: float = 0.05                              # φ of the finite-difference signature


def _with(model: DropModel, effect) -> DropModel:
    others = tuple(e for e in model.effects if e.name != effect.name)
    return replace(model, effects=others + (effect,))


CANDIDATES = (
    Candidate("seal friction", "Coulomb friction of 5 % of the upper mass's weight",
              lambda m, phi: _with(m, SealFriction(0.05 * m.upper_mass * STANDARD_GRAVITY * phi))),
    Candidate("rebound orifice", "rebound damping 3 times the compression orifice's",
              lambda m, phi: _with(m, ReboundOrifice(3.0 * m.orifice.coefficient * phi))),
    Candidate("tyre hysteresis", "a loop of 5 % of the static tyre curve",
              lambda m, phi: _with(m, TyreHysteresis(0.05 * phi))),
    Candidate("heat transfer", "a thermal time constant of 1 s (γ = the polytropic n)",
              lambda m, phi: _with(m, GasHeatTransfer(1.0 / phi, m.gas.exponent)) if phi > 0
              else m),
    Candidate("leg flexibility", "a leg compliance of 1/(3 kN/mm), half the unsprung mass "
                                 "at the axle",
              lambda m, phi: _with(m, LegFlexibility(0.5 * m.lower_mass, 3.0e6 / phi))
              if phi > 0 else m, probe=0.02),
)


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


def score_candidates(residuals, models: list[DropModel], nominal_jacobian: np.ndarray,
                     candidates=CANDIDATES) -> Attribution:
    """LM statistic of every candidate at the calibrated ``models`` (one per run).

    ``residuals``: a :class:`~certkit.calibration.RunResiduals`; ``nominal_jacobian``:
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


def nominal_jacobian(residuals, calibration, relative: float = 1e-4) -> np.ndarray:
    """∂r/∂θ of a calibration's knobs at its estimate, by central differences in one batch."""
    sets, steps = [], []
    for index, (knob, value) in enumerate(zip(calibration.knobs, calibration.fit.estimate)):
        h = relative * max(abs(float(value)), 1e-12)
        steps.append(h)
        for sign in (+1, -1):
            values = np.array(calibration.fit.estimate, dtype=float)
            values[index] += sign * h
            models = []
            for base in residuals.models:
                model = base
                for k, v in zip(calibration.knobs, values):
                    model = k.write(model, float(v))
                models.append(model)
            sets.append(models)
    values = residuals.evaluate(sets)
    return np.column_stack([(values[2 * i] - values[2 * i + 1]) / (2 * h)
                            for i, h in enumerate(steps)])
