"""Flexibility of the gear leg: the axle, or the strut's cylinder, as an extra degree of
freedom."""

from __future__ import annotations

import math
from dataclasses import dataclass

from certkit.errors import CertkitInputError
from certkit.physics import dynamics as dyn
from certkit.physics.drop_model import Term
from certkit.physics.effects.base import Candidate, Effect, Truth


@dataclass(frozen=True)
class LegFlexibility(Term):
    """Structural flexibility of the gear leg as an extra degree of freedom (Flügge &
    Coale, NACA TN 3217, 1954).

    At the axle (``above`` False): the axle and wheel (mass m_w, taken out of the unsprung
    mass m2) hang on the strut's sliding tube through a spring k_l and damper c_l, the
    leg's bending and the axle's compliance as they act vertically.  It rings at about
    √((k_l + k_t)/m_w)/2π on load and tyre deflection, not on stroke.

    Above the strut (``above`` True): the strut's cylinder and the leg structure around it
    (mass m_w, taken out of the upper mass m1) hang on the airframe through k_l and c_l, a
    flexible leg or attachment.  The strut then strokes between that mass and the unsprung
    mass, and the mode shows on stroke as well as on load.
    """

    axle_mass: float      # m_w [kg]
    stiffness: float      # k_l [N/m]
    damping: float = 0.0  # c_l [N·s/m]
    above: bool = False   # the flexibility above the strut (m_w out of m1), not at the axle
    name = "leg flexibility"

    def __post_init__(self):
        if not (self.axle_mass > 0 and self.stiffness > 0 and self.damping >= 0):
            raise ValueError("the leg needs a positive axle mass and stiffness")

    fields = (("axle_mass", "kg", "mass m_w of the axle and wheel (part of m2), or of the "
                                  "strut's cylinder (part of m1) when the leg is above"),
              ("stiffness", "N/m", "leg stiffness k_l"),
              ("damping", "N*s/m", "leg damping c_l"))

    def pack(self, p):
        part = dyn.M1 if self.above else dyn.M2
        if not 0 < self.axle_mass < p[part]:
            raise ValueError(f"the leg's mass {self.axle_mass} kg must be positive and less "
                             f"than the mass it is part of, {p[part]} kg")
        p[dyn.LEG], p[part] = 1.0, p[part] - self.axle_mass
        p[dyn.LEG_ABOVE] = 1.0 if self.above else 0.0
        p[dyn.LEG_MASS], p[dyn.LEG_STIFFNESS] = self.axle_mass, self.stiffness
        p[dyn.LEG_DAMPING] = self.damping


def _build(gear) -> LegFlexibility:
    leg, unsprung = gear.unit.leg, gear.unit.strut.unsprung_mass
    if leg.axle_mass.si >= unsprung.si:
        raise CertkitInputError.single(
            gear.spec_file, gear.line(("gear_units", gear.index, "leg", "axle_mass")),
            f"gear_units[{gear.index}].leg.axle_mass",
            f"{leg.axle_mass.text} is not less than the unsprung mass {unsprung.text} it is "
            f"part of")
    return LegFlexibility(leg.axle_mass.si, leg.stiffness.si, leg.damping.si)


def _damped_leg(model, s: float):
    axle, stiffness = 0.35 * model.lower_mass, 3.0e6 / s
    damping = 2 * 0.05 * math.sqrt(stiffness * axle)           # 5 % of critical
    return model.with_effect(LegFlexibility(axle, stiffness, damping))


EFFECT = Effect(
    label="leg flexibility", name="leg-flexibility", needs=(("leg",),), build=_build,
    candidates=(
        Candidate("leg flexibility", "a leg compliance of 1/(3 kN/mm), half the unsprung mass "
                                     "at the axle",
                  lambda m, phi: m.with_effect(LegFlexibility(0.5 * m.lower_mass, 3.0e6 / phi))
                  if phi > 0 else m, probe=0.02, form="at the axle",
                  quantities=(("3 kN/mm", 3.0e6, "N/m"),)),
        Candidate("leg flexibility", "a compliance of 1/(10 kN/mm) above the strut, carrying "
                                     "a mass twice the unsprung mass",
                  lambda m, phi: m.with_effect(LegFlexibility(2.0 * m.lower_mass, 1.0e7 / phi,
                                                              above=True))
                  if phi > 0 else m, probe=0.02, form="above the strut",
                  quantities=(("10 kN/mm", 1.0e7, "N/m"),))),
    truth=Truth("leg flexibility", "a leg mode with 35 % of the unsprung mass at the axle and "
                                   "5 % damping (the candidate: 50 %, undamped)", (0.02, 5.0),
                mechanics=_damped_leg))
