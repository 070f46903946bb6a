"""The two-mass drop model of one gear unit: the seed paper's governing equations, corrected.

Coordinates (physics.md §2.1): z positive downward from the configuration at first tyre
contact; z1 the upper (sprung) mass m1, z2 the lower (unsprung) mass m2; stroke
s = (z1 − z2)/cos θ positive in compression; tyre deflection δ = z2 on a rigid platform.

Equations of motion (seed eqs. 6-7, corrected as physics.md §2.5 items 2-3)::

    m1·z1'' = m1·g − L − F_s/cos θ
    m2·z2'' = m2·g + F_s/cos θ − F_V

For an inclined strut the vertical force the strut passes between the masses is F_s/cos θ
(the axial force plus the vertical share of the bearing reaction): by virtual work it is
the force whose power over the vertical relative velocity ṡ·cos θ equals F_s·ṡ, so the
gas spring's stored energy and the strut's work stay consistent.  physics.md §2.2 writes
the small-θ form F_s·cos θ; the two agree to second order in θ.

The strut force F_s is the sum of the strut terms and F_V the tyre term's force.  Each
force law is a separate term object with named parameters (SI); the model is their
composition, and optional effects (:mod:`certkit.effects`) are more terms.  Every term
is written with numpy element-wise operations, so one implementation serves the
reference path (scipy ``solve_ivp``, one drop) and the batched path (many parameter
sets at once, a trailing batch axis on every array).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from .units import STANDARD_GRAVITY

P_ATM = 101325.0  # Pa, standard atmosphere (ISO 2533)


@dataclass(frozen=True)
class Parameter:
    """A named model parameter: SI value, SI unit and what it is."""

    name: str
    value: float
    unit: str
    description: str


class Term:
    """A force law with named parameters.  Subclasses set ``name`` and define ``force``."""

    name = "term"

    def parameters(self) -> list[Parameter]:
        return []

    def with_parameters(self, **values) -> Term:
        """A copy with some parameters replaced (SI values), for calibration."""
        return replace(self, **values)  # terms are dataclasses


# --------------------------------------------------------------------------- strut terms
@dataclass(frozen=True)
class GasSpring(Term):
    """Polytropic gas spring with absolute pressures (seed eq. 3, corrected).

    F_a = A_a·(p_a0·(V0/(V0 − A_a·s))^n − p_atm), physics.md §2.3 and §2.5 item 4.
    The gas volume is floored at 2 % of V0 so the law stays finite past the stops.
    """

    area: float           # A_a [m^2]
    volume: float         # V0, gas volume at full extension [m^3]
    precharge: float      # p_a0, absolute pressure at full extension [Pa]
    exponent: float = 1.2  # n
    name = "gas spring"

    def parameters(self):
        return [Parameter("area", self.area, "m^2", "pneumatic area A_a"),
                Parameter("volume", self.volume, "m^3", "gas volume V0 at full extension"),
                Parameter("precharge", self.precharge, "Pa", "absolute pre-charge p_a0"),
                Parameter("exponent", self.exponent, "1", "polytropic exponent n")]

    def pressure(self, stroke):
        volume = np.maximum(self.volume - self.area * stroke, 0.02 * self.volume)
        return self.precharge * (self.volume / volume) ** self.exponent

    def force(self, stroke):
        return self.area * (self.pressure(stroke) - P_ATM)

    def energy(self, stroke):
        """Work stored from s = 0 to ``stroke`` (∫F_a ds), for energy accounting.

        Valid while the gas volume stays above its 2 % floor (the builder demands that
        over the whole design stroke)."""
        ratio = self.volume / (self.volume - self.area * stroke)
        if self.exponent == 1.0:
            stored = self.precharge * self.volume * np.log(ratio)
        else:
            stored = self.precharge * self.volume * (ratio ** (self.exponent - 1) - 1) / (
                self.exponent - 1)
        return stored - P_ATM * self.area * stroke

    def equilibrium_stroke(self, load: float) -> float:
        """Stroke at which the gas force carries ``load`` [N] (closed form of the gas law)."""
        pressure = P_ATM + load / self.area
        if pressure <= self.precharge:
            return 0.0  # the preload holds the load: the strut stays topped out
        return self.volume / self.area * (1.0 - (self.precharge / pressure) ** (1.0 / self.exponent))


def orifice_coefficient(hydraulic_area, orifice_area, discharge, density):
    """K_h = ρ·A_h³/(2·(C_d·A_n)²) [N·s²/m²] of the square-law orifice (seed eq. 2, corrected)."""
    return density * hydraulic_area ** 3 / (2 * (discharge * orifice_area) ** 2)


@dataclass(frozen=True)
class Orifice(Term):
    """Orifice (hydraulic) damping proportional to ṡ|ṡ| (seed eq. 2, corrected).

    F_h = ρ·A_h³·ṡ|ṡ|/(2·(C_d·A_n)²), physics.md §2.3 and §2.5 item 1 (the seed's s²
    is a position spring that dissipates nothing).
    """

    hydraulic_area: float   # A_h [m^2]
    orifice_area: float     # A_n [m^2]
    discharge: float        # C_d
    density: float = 860.0  # ρ [kg/m^3]
    name = "orifice damping"

    def parameters(self):
        return [Parameter("hydraulic_area", self.hydraulic_area, "m^2", "hydraulic area A_h"),
                Parameter("orifice_area", self.orifice_area, "m^2", "net orifice area A_n"),
                Parameter("discharge", self.discharge, "1", "discharge coefficient C_d"),
                Parameter("density", self.density, "kg/m^3", "oil density ρ")]

    @property
    def coefficient(self) -> float:
        """K_h = ρ·A_h³/(2·(C_d·A_n)²) [N·s²/m²]."""
        return orifice_coefficient(self.hydraulic_area, self.orifice_area, self.discharge,
                                   self.density)

    def force(self, stroke, rate):
        return self.coefficient * rate * np.abs(rate)


@dataclass(frozen=True)
class EndStops(Term):
    """Top-out (s < 0) and bottoming (s > s_max) stops as stiff one-sided springs with damping.

    physics.md §2.3 "End stops"; the force never pulls (its damping cannot hold the strut shut).
    """

    travel: float               # s_max [m]
    stiffness: float = 2.0e7    # [N/m]
    damping: float = 2.0e4      # [N·s/m]
    name = "end stops"

    def parameters(self):
        return [Parameter("travel", self.travel, "m", "stroke to the bottoming stop"),
                Parameter("stiffness", self.stiffness, "N/m", "stop stiffness"),
                Parameter("damping", self.damping, "N*s/m", "stop damping")]

    def force(self, stroke, rate):
        # penetration: negative past top-out, positive past the bottoming stop, else zero
        penetration = np.minimum(stroke, 0.0) + np.maximum(stroke - self.travel, 0.0)
        force = self.stiffness * penetration + self.damping * rate * (penetration != 0.0)
        return np.where(penetration < 0.0, np.minimum(force, 0.0), np.maximum(force, 0.0))


# --------------------------------------------------------------------------- tyre
@dataclass(frozen=True)
class Tyre(Term):
    """Tyre vertical force F_V = max(0, f(δ)·(1 + C_T·δ̇)), f(δ) = F_ref·(δ/δ_ref)^b (seed eq. 5).

    Clipped at zero so the wheel can leave the platform (physics.md §2.4, §2.5 item 7).
    """

    reference_load: float        # F_ref [N]
    reference_deflection: float  # δ_ref [m]
    exponent: float = 1.25       # b
    damping: float = 0.0         # C_T [s/m]
    name = "tyre"

    def parameters(self):
        return [Parameter("reference_load", self.reference_load, "N", "load F_ref at δ_ref"),
                Parameter("reference_deflection", self.reference_deflection, "m", "δ_ref"),
                Parameter("exponent", self.exponent, "1", "exponent b of the static curve"),
                Parameter("damping", self.damping, "s/m", "multiplicative damping C_T")]

    def static_force(self, deflection):
        ratio = np.maximum(deflection, 0.0) / self.reference_deflection
        return self.reference_load * ratio ** self.exponent

    def unclipped(self, deflection, rate):
        """f(δ)·(1 + C_T·δ̇) before clipping (zero while the tyre is off the platform)."""
        return self.static_force(deflection) * (1.0 + self.damping * rate)

    def force(self, deflection, rate):
        return np.maximum(0.0, self.unclipped(deflection, rate))

    def energy(self, deflection):
        """Work stored in the static curve from 0 to ``deflection`` (∫f dδ)."""
        deflection = np.maximum(deflection, 0.0)
        return (self.reference_load * self.reference_deflection / (self.exponent + 1)
                * (deflection / self.reference_deflection) ** (self.exponent + 1))


# --------------------------------------------------------------------------- the model
@dataclass(frozen=True)
class DropModel:
    """One gear unit in a free drop: masses, geometry, force terms and optional effects.

    Attributes
    ----------
    upper_mass, lower_mass : float
        m1 and m2 [kg]; m1 + m2 is the mass the unit carries in the drop.
    lift_ratio : float
        L·(m1 + m2)·g acts upward on m1 from contact on (a lift device); 0 for a free
        drop or a reduced-mass drop (14 CFR 23.725(b)).
    inclination : float
        θ [rad], strut axis from vertical.
    gas, orifice, stops, tyre : terms
        The nominal force laws (``orifice=None`` for an undamped spring strut).
    effects : tuple
        Optional strut terms (:mod:`certkit.effects`), each with ``force(stroke, rate, gas)``.
    tyre_effects : tuple
        Optional tyre terms, each with ``force(deflection, rate, static_force)``.
    """

    upper_mass: float
    lower_mass: float
    gas: GasSpring
    orifice: Orifice | None
    stops: EndStops
    tyre: Tyre
    lift_ratio: float = 0.0
    inclination: float = 0.0
    effects: tuple = field(default_factory=tuple)
    tyre_effects: tuple = field(default_factory=tuple)

    @property
    def total_mass(self) -> float:
        return self.upper_mass + self.lower_mass

    @property
    def lift(self) -> float:
        return self.lift_ratio * self.total_mass * STANDARD_GRAVITY

    def terms(self) -> list[Term]:
        nominal = [self.gas, self.orifice, self.stops, self.tyre]
        return ([term for term in nominal if term is not None] + list(self.effects)
                + list(self.tyre_effects))

    def ground_force(self, deflection, rate):
        """Platform load F_V: the tyre law plus tyre effects, clipped at zero (no pull)."""
        force = self.tyre.unclipped(deflection, rate)
        if self.tyre_effects:
            static = self.tyre.static_force(deflection)
            for effect in self.tyre_effects:
                force = force + effect.force(deflection, rate, static)
        return np.maximum(0.0, force)

    def strut_parts(self, stroke, rate) -> dict[str, np.ndarray]:
        """Each strut term's axial force (compression positive) at (s, ṡ)."""
        gas = self.gas.force(stroke)
        parts = {"gas": gas, "stops": self.stops.force(stroke, rate)}
        if self.orifice is not None:
            parts["orifice"] = self.orifice.force(stroke, rate)
        for effect in self.effects:
            parts[effect.name] = effect.force(stroke, rate, gas)
        return parts

    def strut_force(self, stroke, rate):
        return sum(self.strut_parts(stroke, rate).values())

    def initial_state(self, contact_velocity) -> np.ndarray:
        """[z1, v1, z2, v2] at first contact: strut topped out, its stop carrying the preload.

        ``contact_velocity`` and the model's parameters may be arrays (a batch)."""
        preload = self.gas.force(0.0)
        stroke0 = -preload / self.stops.stiffness  # stop compressed just enough to hold it
        z1 = stroke0 * np.cos(self.inclination)
        velocity = np.asarray(contact_velocity, dtype=float)
        shape = np.broadcast(z1, velocity).shape
        return np.array([np.broadcast_to(z1, shape), np.broadcast_to(velocity, shape),
                         np.zeros(shape), np.broadcast_to(velocity, shape)], dtype=float)

    def rates(self, state):
        """Time derivative of [z1, v1, z2, v2] (arrays may carry a trailing batch axis)."""
        z1, v1, z2, v2 = state[0], state[1], state[2], state[3]
        cos_theta = np.cos(self.inclination)
        stroke, rate = (z1 - z2) / cos_theta, (v1 - v2) / cos_theta
        strut = self.strut_force(stroke, rate)
        ground = self.ground_force(z2, v2)
        # the simulation starts at first contact, when a lift device engages
        a1 = STANDARD_GRAVITY - (self.lift + strut / cos_theta) / self.upper_mass
        a2 = STANDARD_GRAVITY + (strut / cos_theta - ground) / self.lower_mass
        return np.array([v1, a1, v2, a2])

    def static_stroke(self) -> float:
        """Equilibrium stroke under the upper mass's weight less lift (friction-free)."""
        load = (self.upper_mass * STANDARD_GRAVITY - self.lift) * math.cos(self.inclination)
        return self.gas.equilibrium_stroke(load)
