"""Compliance and inertia of the drop-test platform and its load cells."""

from __future__ import annotations

from dataclasses import dataclass

from certkit.physics import dynamics as dyn
from certkit.physics.drop_model import Term
from certkit.physics.effects.base import Effect


@dataclass(frozen=True)
class PlatformCompliance(Term):
    """Platform and load-cell compliance and inertia (the load cells measure
    the platform's support force, not the tyre force).

    The tyre stands on a platform of mass m_p carried by the load cells (spring k_p,
    damper c_p); the cells read k_p·x_p + c_p·ẋ_p, not the tyre force: ringing at
    about √(k_p/m_p)/2π on the load channel that the stroke does not show.
    """

    mass: float           # m_p [kg]
    stiffness: float      # k_p [N/m]
    damping: float = 0.0  # c_p [N·s/m]
    name = "platform compliance"

    def __post_init__(self):
        if not (self.mass > 0 and self.stiffness > 0 and self.damping >= 0):
            raise ValueError("the platform needs a positive mass and stiffness")

    fields = (("mass", "kg", "platform mass m_p"),
              ("stiffness", "N/m", "load-cell stiffness k_p"),
              ("damping", "N*s/m", "load-cell damping c_p"))

    def pack(self, p):
        p[dyn.PLATFORM], p[dyn.PLATFORM_MASS] = 1.0, self.mass
        p[dyn.PLATFORM_STIFFNESS], p[dyn.PLATFORM_DAMPING] = self.stiffness, self.damping


def _build(gear) -> PlatformCompliance:
    platform = gear.platform
    return PlatformCompliance(platform.mass.si, platform.stiffness.si, platform.damping.si)


EFFECT = Effect(label="platform compliance", name="platform-compliance",
                needs=((("instrumentation", "platform"),
                        "needed to simulate the platform's compliance (effect "
                        "platform-compliance)"),),
                build=_build)
