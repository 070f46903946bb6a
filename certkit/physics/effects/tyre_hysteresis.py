"""Tyre hysteresis: the loading curve above the unloading curve."""

from __future__ import annotations

from dataclasses import dataclass

from certkit.physics import dynamics as dyn
from certkit.physics.drop_model import Term
from certkit.physics.effects.base import Candidate, Effect, Truth


@dataclass(frozen=True)
class TyreHysteresis(Term):
    """Tyre hysteresis: loading above unloading by a share of the static curve (Daniels, NASA CR-201601, 1996:
    nonlinear tyre damping).

    F = h·f(δ)·tanh(δ̇/v_ε): the loop between loading and unloading is 2·h·f(δ) wide, so a
    share of about h of the tyre's work is lost per cycle.
    """

    share: float                      # h [1]
    smoothing_velocity: float = 0.01  # v_ε [m/s]
    name = "tyre hysteresis"

    def __post_init__(self):
        if not self.smoothing_velocity > 0:
            raise ValueError("tyre hysteresis needs a positive smoothing velocity")

    fields = (("share", "1", "half-width h of the loop, share of f(δ)"),
              ("smoothing_velocity", "m/s", "regularisation width v_ε"))

    def pack(self, p):
        p[dyn.HYSTERESIS], p[dyn.HYSTERESIS_VELOCITY] = self.share, self.smoothing_velocity


EFFECT = Effect(
    label="tyre hysteresis", name="tyre-hysteresis", needs=(("tyre", "hysteresis"),),
    build=lambda gear: TyreHysteresis(gear.unit.tyre.hysteresis.si),
    candidate=Candidate("tyre hysteresis", "a loop of 5 % of the static tyre curve",
                        lambda m, phi: m.with_effect(TyreHysteresis(0.05 * phi))),
    truth=Truth("tyre hysteresis", "a tyre hysteresis loop switching within 5 mm/s (the "
                                   "candidate: 10 mm/s)", (0.02, 20.0),
                mechanics=lambda m, s: m.with_effect(
                    TyreHysteresis(0.05 * s, smoothing_velocity=0.005))))
