"""Heat exchange between the strut's gas and its walls, in place of the polytropic law."""

from __future__ import annotations

from dataclasses import dataclass, replace

from certkit.physics import dynamics as dyn
from certkit.physics.drop_model import Term
from certkit.physics.effects.base import Candidate, Effect, Truth


@dataclass(frozen=True)
class GasHeatTransfer(Term):
    """Heat exchange between the gas and the strut walls (the first law for the closed gas
    volume with Newtonian heat exchange at the wall).

    Replaces the polytropic law by the gas energy equation m·c_v·Ṫ = −p·V̇ − hA·(T − T_w)
    with an ideal gas (p·V ∝ T), the walls at the pre-charge temperature.  With θ = T/T0:
    θ' = (γ − 1)·p·A_a·ṡ/(p_a0·V0) + (1 − θ)/τ,  τ = m·c_v/(hA).  Fast compression is
    near-adiabatic (n → γ), slow settling near-isothermal (n → 1); the gas cools back
    after the stroke, so the static stroke drifts over seconds.
    """

    time_constant: float   # τ [s]
    gamma: float = 1.4     # c_p/c_v of nitrogen
    name = "heat transfer"
    fields = (("time_constant", "s", "thermal time constant τ = m·c_v/(hA)"),
              ("gamma", "1", "ratio of specific heats γ"))

    def __post_init__(self):
        if not (self.time_constant > 0 and self.gamma > 1):
            raise ValueError("heat transfer needs τ > 0 and γ > 1")

    def pack(self, p):
        p[dyn.THERMAL], p[dyn.GAS_GAMMA] = 1.0, self.gamma
        p[dyn.GAS_COOLING] = 1.0 / self.time_constant


def _build(gear) -> GasHeatTransfer:
    heat = gear.unit.strut.heat_transfer
    return GasHeatTransfer(heat.time_constant.si, heat.ratio_of_specific_heats.si)


def _isothermal(model) -> str:
    """The candidate takes γ = the calibrated polytropic exponent n, so that fast compression
    stays where the calibration put it; at n = 1 the gas is isothermal already and a heat
    exchange with the walls has nothing left to change (γ = 1: θ stays 1)."""
    exponent = model.gas.exponent
    if exponent > 1.0:
        return ""
    return (f"the calibrated polytropic exponent is n = {exponent:.4g}, the isothermal "
            f"law: with γ = n the gas has no heat left to exchange with the walls, so the "
            f"form would not change the model")


EFFECT = Effect(
    label="heat transfer", name="heat-transfer", needs=(("strut", "heat_transfer"),),
    build=_build,
    candidates=(Candidate("heat transfer", "a thermal time constant of 1 s (γ = the polytropic n)",
                        lambda m, phi: m.with_effect(GasHeatTransfer(1.0 / phi, m.gas.exponent))
                        if phi > 0 else m, inapplicable=_isothermal,
                        quantities=(("1 s", 1.0, "s"),)),),
    truth=Truth("heat transfer", "nitrogen (γ = 1.4) exchanging heat with the walls, sized from "
                                 "its adiabatic limit (the candidate: γ = the calibrated "
                                 "polytropic exponent n)", (0.01, 50.0),
                mechanics=lambda m, s: m.with_effect(GasHeatTransfer(1.0 / s, 1.4)),
                base=lambda m: replace(m, gas=replace(m.gas, exponent=1.4))))
