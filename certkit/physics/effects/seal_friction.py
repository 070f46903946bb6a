"""Seal friction: Coulomb with a pressure-energised part and an optional Stribeck peak."""

from __future__ import annotations

from dataclasses import dataclass

from certkit.physics import dynamics as dyn
from certkit.physics.drop_model import Term
from certkit.physics.effects.base import Candidate, Effect, Knob, Truth, set_effect
from certkit.units import STANDARD_GRAVITY


@dataclass(frozen=True)
class SealFriction(Term):
    """Seal friction, Coulomb with an optional Stribeck peak, regularised (Daniels, NASA CR-201601, 1996: stick-slip seal
    friction; Stribeck form after Armstrong-Hélouvry et al., Automatica 30(7), 1994).

    F_f = (F_C + (F_S − F_C)·exp(−(ṡ/v_s)²))·tanh(ṡ/v_ε),  F_C = F_0 + μ·|F_gas|

    The pressure-energised part μ·|F_gas| scales with the gas force; ``breakaway``
    (F_S − F_C) = 0 gives plain Coulomb friction.  tanh(ṡ/v_ε) regularises sign(ṡ).
    """

    constant: float              # F_0 [N]
    pressure_factor: float = 0.0  # μ [1]
    breakaway: float = 0.0       # F_S − F_C [N]
    stribeck_velocity: float = 0.01  # v_s [m/s]
    smoothing_velocity: float = 0.002  # v_ε [m/s]
    name = "seal friction"

    def __post_init__(self):
        if not (self.stribeck_velocity > 0 and self.smoothing_velocity > 0):
            raise ValueError("seal friction needs positive Stribeck and smoothing velocities")

    fields = (("constant", "N", "Coulomb friction F_0"),
              ("pressure_factor", "1", "share μ of the gas force acting as friction"),
              ("breakaway", "N", "Stribeck excess F_S − F_C"),
              ("stribeck_velocity", "m/s", "Stribeck velocity v_s"),
              ("smoothing_velocity", "m/s", "regularisation width v_ε"))

    def pack(self, p):
        p[dyn.FRICTION], p[dyn.FRICTION_PRESSURE] = self.constant, self.pressure_factor
        p[dyn.FRICTION_BREAKAWAY], p[dyn.FRICTION_STRIBECK] = self.breakaway, self.stribeck_velocity
        p[dyn.FRICTION_SMOOTHING] = self.smoothing_velocity


def _build(gear) -> SealFriction:
    friction = gear.unit.strut.seal_friction
    return SealFriction(friction.constant.si, friction.pressure_factor.si,
                        friction.breakaway.si, friction.stribeck_velocity.si)


def _stribeck(model, s: float):
    level = 0.05 * model.upper_mass * STANDARD_GRAVITY * s
    return model.with_effect(SealFriction(level, breakaway=0.5 * level, stribeck_velocity=0.02))


def _absolute(low: float, high: float):
    return lambda nominal: (min(low, nominal), max(high, nominal))


EFFECT = Effect(
    label="seal friction", name="seal-friction", needs=(("strut", "seal_friction"),),
    build=_build,
    knobs=(Knob("friction", "seal friction F_0", "N",
                lambda m: m.effect("seal friction").constant,
                lambda m, v: set_effect(m, "seal friction", constant=v),
                lambda nominal: (0.0, max(4.0 * nominal, 500.0)), needs="seal friction"),
           Knob("friction-pressure-factor", "pressure-energised friction μ", "1",
                lambda m: m.effect("seal friction").pressure_factor,
                lambda m, v: set_effect(m, "seal friction", pressure_factor=v),
                _absolute(0.0, 0.2), needs="seal friction")),
    candidates=(
        Candidate("seal friction", "Coulomb friction of 5 % of the upper mass's weight",
                  lambda m, phi: m.with_effect(
                      SealFriction(0.05 * m.upper_mass * STANDARD_GRAVITY * phi)),
                  form="Coulomb"),
        Candidate("seal friction", "friction of 5 % of the gas force (pressure-energised seals)",
                  lambda m, phi: m.with_effect(SealFriction(0.0, pressure_factor=0.05 * phi)),
                  form="pressure-energised")),
    truth=Truth("seal friction", "Stribeck seal friction: breakaway force 1.5 times the "
                                 "Coulomb level, decaying over 20 mm/s (the candidate: "
                                 "Coulomb only)", (0.02, 20.0), mechanics=_stribeck))
