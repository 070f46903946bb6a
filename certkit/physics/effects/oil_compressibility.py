"""Oil compressibility: the oil column as a spring in series with the orifice."""

from __future__ import annotations

from dataclasses import dataclass

from certkit.physics import dynamics as dyn
from certkit.physics.drop_model import Term
from certkit.physics.effects.base import Effect


@dataclass(frozen=True)
class OilCompressibility(Term):
    """Oil compressibility: the oil column as a spring in series with the orifice
    (hydraulic capacitance
    k = β·A²/V, Merritt, *Hydraulic Control Systems*, Wiley 1967).

    k_oil = β·A_h²/V_oil; the hydraulic force becomes a state, Ḟ_h = k_oil·(ṡ − q), with
    the orifice flow q from K·q|q| = F_h, regularised as q = F_h/√(K·√(F_h² + F_ε²)).
    The pressure builds with a lag of a few milliseconds at breakout.
    """

    stiffness: float             # k_oil [N/m]
    smoothing_force: float = 50.0  # F_ε [N]
    name = "oil compressibility"

    def __post_init__(self):
        if not (self.stiffness > 0 and self.smoothing_force > 0):
            raise ValueError("oil compressibility needs a positive stiffness and smoothing force")

    fields = (("stiffness", "N/m", "oil-column stiffness k_oil = β·A_h²/V_oil"),
              ("smoothing_force", "N", "regularisation F_ε of the inverse orifice law"))

    @classmethod
    def from_oil(cls, bulk_modulus: float, hydraulic_area: float, oil_volume: float,
                 **kwargs) -> OilCompressibility:
        """From the oil's (effective) bulk modulus β [Pa], A_h [m^2] and oil volume [m^3]."""
        return cls(bulk_modulus * hydraulic_area ** 2 / oil_volume, **kwargs)

    def pack(self, p):
        p[dyn.OIL], p[dyn.OIL_STIFFNESS] = 1.0, self.stiffness
        p[dyn.OIL_SMOOTHING] = self.smoothing_force


def _build(gear) -> OilCompressibility:
    oil = gear.unit.strut.oil
    return OilCompressibility.from_oil(oil.bulk_modulus.si, gear.orifice.hydraulic_area,
                                       oil.volume.si)


EFFECT = Effect(label="oil compressibility", name="oil-compressibility",
                needs=(("strut", "oil"),), build=_build)
