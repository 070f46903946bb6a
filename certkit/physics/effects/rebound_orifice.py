"""A separate rebound orifice (recoil valve): extra damping on extension only."""

from __future__ import annotations

import math
from dataclasses import dataclass

from certkit.physics import dynamics as dyn
from certkit.physics.drop_model import Orifice, Term
from certkit.physics.effects.base import Candidate, Effect, Knob, Truth, set_effect


#: The rebound speed at which the linear form's unit size matches the square law's [m/s].
REBOUND_SPEED = 0.5


@dataclass(frozen=True)
class ReboundOrifice(Term):
    """Separate rebound orifice (recoil valve): extra damping on extension only (Currey, *Aircraft Landing Gear Design*, AIAA 1988,
    recoil damping).

    The nominal orifice damps both ways with K_h; on extension (ṡ < 0) this adds
    (K_reb − K_h)·ṡ|ṡ| so the total rebound damping is K_reb = ρ·A_h³/(2·(C_d·A_reb)²).
    With a metering pin the excess adds to the pin's K(s) (a parallel recoil restriction).
    A linear share c_reb·ṡ (laminar flow through a recoil valve's narrow passages) may add
    to it on extension.
    """

    extra_coefficient: float  # K_reb − K_h [N·s²/m²]
    linear: float = 0.0       # c_reb [N·s/m]
    name = "rebound orifice"
    fields = (("extra_coefficient", "N*s^2/m^2",
               "rebound damping in excess of the compression orifice"),
              ("linear", "N*s/m", "linear rebound damping c_reb"))

    def pack(self, p):
        p[dyn.REBOUND_EXTRA], p[dyn.REBOUND_LINEAR] = self.extra_coefficient, self.linear


def _build(gear) -> ReboundOrifice:
    strut, nominal = gear.unit.strut, gear.orifice
    diameter = strut.rebound_orifice_diameter.si
    rebound = Orifice(nominal.hydraulic_area, math.pi * diameter ** 2 / 4, nominal.discharge,
                      nominal.density)
    return ReboundOrifice(rebound.coefficient - nominal.coefficient)


EFFECT = Effect(
    label="rebound orifice", name="rebound-orifice", needs=(("strut", "rebound_orifice_diameter"),),
    build=_build,
    knobs=(Knob("rebound-damping", "rebound damping excess K_reb − K_h", "N*s^2/m^2",
                lambda m: m.effect("rebound orifice").extra_coefficient,
                lambda m, v: set_effect(m, "rebound orifice", extra_coefficient=v),
                lambda nominal: (0.0, max(10.0 * nominal, 1.0)), needs="rebound orifice"),),
    candidates=(
        Candidate("rebound orifice", "rebound damping 3 times the compression orifice's",
                  lambda m, phi: m.with_effect(ReboundOrifice(3.0 * m.orifice.coefficient * phi)),
                  form="square law"),
        Candidate("rebound orifice", "linear rebound damping, as much at 0.5 m/s as 3 times "
                                     "the compression orifice's",
                  lambda m, phi: m.with_effect(ReboundOrifice(
                      0.0, linear=3.0 * m.orifice.coefficient * REBOUND_SPEED * phi)),
                  form="linear", quantities=(("0.5 m/s", 0.5, "m/s"),))),
    truth=Truth("rebound orifice", "rebound damping K_reb − K_h (the candidate's own form)",
                (0.01, 20.0), mechanics=lambda m, s: m.with_effect(
                    ReboundOrifice(3.0 * m.orifice.coefficient * s))))
