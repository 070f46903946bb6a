"""Tyre hysteresis: the loading curve above the unloading curve."""

from __future__ import annotations

from dataclasses import dataclass

from certkit.physics import dynamics as dyn
from certkit.physics.drop_model import Term
from certkit.physics.effects.base import Candidate, Effect, Knob, Truth, set_effect
from certkit.units import STANDARD_GRAVITY


@dataclass(frozen=True)
class TyreHysteresis(Term):
    """Tyre hysteresis: loading above unloading (Daniels, NASA CR-201601, 1996: nonlinear
    tyre damping).

    F = (h·f(δ) + H·(1 − e^(−δ/δ_H)))·tanh(δ̇/v_ε): the loop between loading and unloading
    is 2·h·f(δ) wide when it scales with the static curve (a share of about h of the tyre's
    work is lost per cycle), and 2·H wide, once the first δ_H of deflection has built it
    up, when its amplitude is constant (the rate-independent loop of a Bouc-Wen element
    in its saturated state: Wen, J. Eng. Mech. Div. ASCE 102(2), 1976).

    With ``memory`` the loop switches with deflection, not with rate: F = (h·f(δ) + H)·w,
    w' = (δ̇/δ_H)·(1 − w·tanh(δ̇/v_ε)) (Dahl's law, Aerospace Corp. TOR-0158(3107-18)-1,
    1968), so w turns from −1 to +1 over a few δ_H of deflection and keeps its value when
    the tyre comes to rest: a tyre at rest holds part of its load in the loop.
    """

    share: float                      # h [1]
    smoothing_velocity: float = 0.01  # v_ε [m/s]
    constant: float = 0.0             # H [N]
    onset: float = 0.002              # δ_H [m]
    memory: bool = False              # switch with deflection (Dahl) rather than rate
    name = "tyre hysteresis"

    def __post_init__(self):
        if not (self.smoothing_velocity > 0 and self.onset > 0):
            raise ValueError("tyre hysteresis needs a positive smoothing velocity and onset")

    fields = (("share", "1", "half-width h of the loop, share of f(δ)"),
              ("smoothing_velocity", "m/s", "regularisation width v_ε"),
              ("constant", "N", "half-width H of a loop of constant amplitude"),
              ("onset", "m", "deflection δ_H over which the constant loop builds up"),
              ("memory", "1", "1: the loop switches with deflection (Dahl), 0: with rate"))

    def pack(self, p):
        p[dyn.HYSTERESIS], p[dyn.HYSTERESIS_VELOCITY] = self.share, self.smoothing_velocity
        p[dyn.HYSTERESIS_CONSTANT], p[dyn.HYSTERESIS_ONSET] = self.constant, self.onset
        p[dyn.HYSTERESIS_MEMORY] = 1.0 if self.memory else 0.0


#: Where the loop's onset δ_H may lie when a loop with memory is refitted [m]: the deflection
#: over which a tyre's loop switches (a Bouc–Wen element's yield deflection w0) is a
#: property of the tyre that no spec states, from a fraction of a millimetre to several.
ONSET_RANGE = (0.5e-3, 10e-3)
#: The onset fitted with the strength of a loop with memory, and the onsets its profile
#: tries (the first, the candidate's own 2 mm, is the refit's default start) [m].
ONSET = Knob("tyre-loop-onset", "tyre loop onset δ_H", "m",
             lambda m: m.effect("tyre hysteresis").onset,
             lambda m, v: set_effect(m, "tyre hysteresis", onset=v),
             lambda nominal: ONSET_RANGE, needs="tyre hysteresis")
ONSETS = (0.002, 0.001, 0.004)


EFFECT = Effect(
    label="tyre hysteresis", name="tyre-hysteresis", needs=(("tyre", "hysteresis"),),
    build=lambda gear: TyreHysteresis(gear.unit.tyre.hysteresis.si),
    candidates=(
        Candidate("tyre hysteresis", "a loop of 5 % of the static tyre curve",
                  lambda m, phi: m.with_effect(TyreHysteresis(0.05 * phi)),
                  form="a share of the static curve"),
        Candidate("tyre hysteresis", "a loop of constant half-width, 2 % of the unit's weight",
                  lambda m, phi: m.with_effect(TyreHysteresis(
                      0.0, constant=0.02 * m.total_mass * STANDARD_GRAVITY * phi)),
                  form="constant amplitude"),
        Candidate("tyre hysteresis", "a loop of constant half-width, 2 % of the unit's weight, "
                                     "switching over 2 mm of deflection and held at rest",
                  lambda m, phi: m.with_effect(TyreHysteresis(
                      0.0, constant=0.02 * m.total_mass * STANDARD_GRAVITY * phi, memory=True)),
                  form="constant amplitude, with memory", quantities=(("2 mm", 0.002, "m"),),
                  knobs=((ONSET, ONSETS),)),
        Candidate("tyre hysteresis", "a loop of 5 % of the static tyre curve, switching over "
                                     "2 mm of deflection and held at rest",
                  lambda m, phi: m.with_effect(TyreHysteresis(0.05 * phi, memory=True)),
                  form="a share of the static curve, with memory",
                  quantities=(("2 mm", 0.002, "m"),), knobs=((ONSET, ONSETS),))),
    truth=Truth("tyre hysteresis", "a tyre hysteresis loop switching within 5 mm/s (the "
                                   "candidate: 10 mm/s)", (0.02, 20.0),
                mechanics=lambda m, s: m.with_effect(
                    TyreHysteresis(0.05 * s, smoothing_velocity=0.005))))
