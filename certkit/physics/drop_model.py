"""The two-mass drop model of one gear unit: the seed paper's governing equations, corrected.

The two-mass model of Milwitzky & Cook (*Analysis of Landing-Gear Behavior*, NACA Report
1154, 1953).  Coordinates: z positive downward from the configuration at first tyre
contact; z1 the upper (sprung) mass m1, z2 the lower (unsprung) mass m2; stroke
s = (z1 − z2)/cos θ positive in compression; tyre deflection δ = z2 on a rigid platform.

Equations of motion (seed eqs. 6-7, with the strut force between the masses and the lift
on the upper mass)::

    m1·z1'' = m1·g − L − F_s/cos θ
    m2·z2'' = m2·g + F_s/cos θ − F_V

For an inclined strut the vertical force the strut passes between the masses is F_s/cos θ
(the axial force plus the vertical share of the bearing reaction): by virtual work it is
the force whose power over the vertical relative velocity ṡ·cos θ equals F_s·ṡ, so the
gas spring's stored energy and the strut's work stay consistent, and a freely rolling
wheel at rest gets the exact static balance F_s = (m1·g − L)·cos θ.  The simpler form
F_s·cos θ and this one agree to first order in θ only (they differ by 1/cos²θ, 9.6 %
at 0.3 rad), which is why certkit uses the virtual-work form.

Each force law is a separate term object with named parameters (SI) and units; the
model is their composition, and the optional effects (:mod:`certkit.physics.effects`) are more
terms.  A term writes its parameters into the slots of the compiled equations of motion
(:mod:`certkit.physics.dynamics`, where the force laws are evaluated) with ``pack``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from certkit.physics import dynamics as dyn
from certkit.physics.dynamics import P_ATM
from certkit.compliance.servicing import gas_equilibrium_stroke
from certkit.units import STANDARD_GRAVITY

__all__ = ["P_ATM", "Parameter", "Term", "GasSpring", "Orifice", "EndStops", "Tyre",
           "DropModel", "orifice_coefficient"]


@dataclass(frozen=True)
class Parameter:
    """A named model parameter: SI value, SI unit and what it is."""

    name: str
    value: float
    unit: str
    description: str


class Term:
    """A force law with named parameters.  Subclasses are frozen dataclasses that set
    ``name``, describe their parameters and write them into the kernel's slots."""

    name = "term"
    #: (field, SI unit, description) of each parameter
    fields: tuple = ()

    def parameters(self) -> list[Parameter]:
        return [Parameter(name, getattr(self, name), unit, text)
                for name, unit, text in self.fields]

    def with_parameters(self, **values) -> Term:
        """A copy with some parameters replaced (SI values), for calibration."""
        return replace(self, **values)

    def pack(self, p: np.ndarray) -> None:  # pragma: no cover - every term overrides it
        raise NotImplementedError

    def recorded(self, step: float, channel: str, signal: np.ndarray) -> np.ndarray:
        """``signal``, the recorded ``channel`` (sampled every ``step`` s), as this term
        changes it: unchanged for a term of the mechanics, changed by one that acts on what
        the instruments record (a sensor lag, a load-cell gain error)."""
        return signal

    def record_delay(self, channel: str) -> float:
        """How long [s] the recorded ``channel`` lags the other channels as this term
        records it (a pure delay: a load chain's skew); 0 for a term of the mechanics."""
        return 0.0


# --------------------------------------------------------------------------- strut terms
@dataclass(frozen=True)
class GasSpring(Term):
    """Polytropic gas spring with absolute pressures (seed eq. 3, corrected).

    F_a = A_a·(p_a0·(V0/(V0 − A_a·s))^n − p_atm): the polytropic law holds for absolute
    pressures, and the atmosphere pushes back on the piston's outer face.
    The gas volume is floored at 2 % of V0 so the law stays finite past the stops.
    """

    area: float           # A_a [m^2]
    volume: float         # V0, gas volume at full extension [m^3]
    precharge: float      # p_a0, absolute pressure at full extension [Pa]
    exponent: float = 1.2  # n
    name = "gas spring"
    fields = (("area", "m^2", "pneumatic area A_a"),
              ("volume", "m^3", "gas volume V0 at full extension"),
              ("precharge", "Pa", "absolute pre-charge p_a0"),
              ("exponent", "1", "polytropic exponent n"))

    @property
    def preload(self) -> float:
        """Force at full extension, A_a·(p_a0 − p_atm) [N]."""
        return self.area * (self.precharge - P_ATM)

    def equilibrium_stroke(self, load: float, exponent: float | None = None) -> float:
        """Stroke at which the gas force carries ``load`` [N] (closed form of the gas law).

        ``exponent`` overrides n (1 for gas at wall temperature, with heat transfer)."""
        n = self.exponent if exponent is None else exponent
        return gas_equilibrium_stroke(self.volume, self.area, self.precharge, load, n)

    def pack(self, p):
        p[dyn.GAS_AREA], p[dyn.GAS_VOLUME] = self.area, self.volume
        p[dyn.GAS_PRECHARGE], p[dyn.GAS_EXPONENT] = self.precharge, self.exponent


def orifice_coefficient(hydraulic_area, orifice_area, discharge, density):
    """K_h = ρ·A_h³/(2·(C_d·A_n)²) [N·s²/m²] of the square-law orifice (seed eq. 2, corrected)."""
    return density * hydraulic_area ** 3 / (2 * (discharge * orifice_area) ** 2)


@dataclass(frozen=True)
class Orifice(Term):
    """Orifice (hydraulic) damping proportional to ṡ|ṡ| (seed eq. 2, corrected).

    F_h = ρ·A_h³·ṡ|ṡ|/(2·(C_d·A_n)²) (Milwitzky & Cook 1953; the seed's s²
    is a position spring that dissipates nothing).  Only the product C_d·A_n enters.
    """

    hydraulic_area: float   # A_h [m^2]
    orifice_area: float     # A_n [m^2]
    discharge: float        # C_d
    density: float = 860.0  # ρ [kg/m^3]
    name = "orifice damping"
    fields = (("hydraulic_area", "m^2", "hydraulic area A_h"),
              ("orifice_area", "m^2", "net orifice area A_n"),
              ("discharge", "1", "discharge coefficient C_d"),
              ("density", "kg/m^3", "oil density ρ"))

    @property
    def coefficient(self) -> float:
        """K_h = ρ·A_h³/(2·(C_d·A_n)²) [N·s²/m²]."""
        return orifice_coefficient(self.hydraulic_area, self.orifice_area, self.discharge,
                                   self.density)

    def pack(self, p):
        p[dyn.ORIFICE_K] = self.coefficient


@dataclass(frozen=True)
class EndStops(Term):
    """Top-out (s < 0) and bottoming (s > s_max) stops as stiff one-sided springs with damping.

    A penalty contact; the force never pulls (its damping cannot hold the strut shut).
    ``top_out``, when given, is how far the hanging strut sits into a compliant top-out
    stop (an elastomer pad) under the gas preload F_0: the top-out spring is then
    F_0/top_out, linear and without damping of its own (an elastic pad: the stop damping is
    the rigid stop's numerical device, about critical for the pad, which would cancel the
    pad's force as soon as the strut moves; the oil damps the strut in parallel), the
    stop stiffness and damping applying otherwise.  The strut hangs at
    s_hang = −F_0/k_top (:meth:`hang`), where a stroke transducer reads zero
    (:meth:`recorded_zero`).  Without a compliant top-out the stiff stop stands for a rigid
    one, whose give F_0/stiffness is a numerical device: the recorded stroke is then s, never
    below zero, and a compliant stop tends to it as ``top_out`` → 0.
    """

    travel: float               # s_max [m]
    stiffness: float = 2.0e7    # [N/m]
    damping: float = 2.0e4      # [N·s/m]
    top_out: float | None = None   # compression of the top-out stop under the preload [m]
    name = "end stops"
    fields = (("travel", "m", "stroke to the bottoming stop"),
              ("stiffness", "N/m", "stop stiffness"),
              ("damping", "N*s/m", "stop damping"))

    def parameters(self) -> list[Parameter]:
        extra = [] if self.top_out is None else [Parameter(
            "top_out", self.top_out, "m", "compression of the top-out stop under the preload")]
        return super().parameters() + extra

    def top_out_stiffness(self, preload: float) -> float:
        """The top-out spring [N/m] under the gas preload ``preload`` [N]."""
        if self.top_out is None or preload <= 0.0:
            return self.stiffness
        return preload / self.top_out

    def hang(self, preload: float) -> float:
        """The stroke at which the strut hangs, its top-out stop carrying ``preload`` [m]."""
        return -preload / self.top_out_stiffness(preload)

    def recorded_zero(self, preload: float) -> float:
        """The stroke s a stroke transducer reads as zero [m]: where the strut hangs on a
        compliant top-out stop, 0 on a rigid one."""
        return 0.0 if self.top_out is None else self.hang(preload)

    def pack(self, p):
        p[dyn.STOP_TRAVEL], p[dyn.STOP_STIFFNESS] = self.travel, self.stiffness
        p[dyn.STOP_DAMPING] = self.damping


# --------------------------------------------------------------------------- tyre
@dataclass(frozen=True)
class Tyre(Term):
    """Tyre vertical force F_V = max(0, f(δ)·(1 + C_T·δ̇)), f(δ) = F_ref·(δ/δ_ref)^b (seed eq. 5).

    Clipped at zero so the wheel can leave the platform: a tyre cannot pull.
    """

    reference_load: float        # F_ref [N]
    reference_deflection: float  # δ_ref [m]
    exponent: float = 1.25       # b
    damping: float = 0.0         # C_T [s/m]
    name = "tyre"
    fields = (("reference_load", "N", "load F_ref at δ_ref"),
              ("reference_deflection", "m", "deflection δ_ref"),
              ("exponent", "1", "exponent b of the static curve"),
              ("damping", "s/m", "multiplicative damping C_T"))

    def static_force(self, deflection):
        """f(δ) [N], the static load-deflection curve."""
        ratio = np.maximum(deflection, 0.0) / self.reference_deflection
        return self.reference_load * ratio ** self.exponent

    def pack(self, p):
        p[dyn.TYRE_LOAD], p[dyn.TYRE_DEFLECTION] = self.reference_load, self.reference_deflection
        p[dyn.TYRE_EXPONENT], p[dyn.TYRE_DAMPING] = self.exponent, self.damping


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
        Optional effects (:mod:`certkit.physics.effects`), off unless listed here.
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

    def __post_init__(self):
        if not (self.upper_mass > 0 and self.lower_mass > 0):
            raise ValueError(f"the masses must be positive (m1 = {self.upper_mass} kg, "
                             f"m2 = {self.lower_mass} kg)")
        if not 0 <= self.inclination < math.pi / 2:
            raise ValueError(f"the strut inclination must lie in [0, 90°), got "
                             f"{math.degrees(self.inclination):g}°")
        for term in self.terms():
            values = [p.value for p in term.parameters() if isinstance(p.value, float)]
            if not all(math.isfinite(v) for v in values):
                raise ValueError(f"{term.name}: every parameter must be finite")

    @property
    def total_mass(self) -> float:
        return self.upper_mass + self.lower_mass

    @property
    def lift(self) -> float:
        return self.lift_ratio * self.total_mass * STANDARD_GRAVITY

    def terms(self) -> list[Term]:
        nominal = [self.gas, self.orifice, self.stops, self.tyre]
        return [term for term in nominal if term is not None] + list(self.effects)

    def effect(self, name: str):
        """The optional effect called ``name``, or None when it is off."""
        return next((e for e in self.effects if e.name == name), None)

    def record_delay(self, channel: str) -> float:
        """How long [s] the recorded ``channel`` lags the others, summed over the effects
        (:meth:`Term.record_delay`)."""
        return float(sum(e.record_delay(channel) for e in self.effects))

    def with_effect(self, effect) -> "DropModel":
        """This model with ``effect`` on, replacing an effect of the same name."""
        others = tuple(e for e in self.effects if e.name != effect.name)
        return replace(self, effects=others + (effect,))

    def pack(self) -> np.ndarray:
        """The parameter vector of the compiled equations of motion (:mod:`certkit.physics.dynamics`)."""
        p = np.zeros(dyn.SLOTS)
        p[dyn.M1], p[dyn.M2] = self.upper_mass, self.lower_mass
        p[dyn.LIFT], p[dyn.COS] = self.lift, math.cos(self.inclination)
        for term in self.terms():
            term.pack(p)
        preload = self.gas.preload
        p[dyn.TOP_OUT_STIFFNESS] = self.stops.top_out_stiffness(preload)
        p[dyn.HANG] = self.stops.recorded_zero(preload)
        return p

    def initial_state(self, contact_velocity: float) -> np.ndarray:
        """State at first contact: strut topped out with its stop carrying the preload."""
        y = np.zeros(dyn.STATES)
        stroke0 = self.stops.hang(self.gas.preload)   # stop compressed just enough
        y[dyn.Z1] = stroke0 * math.cos(self.inclination)
        leg = self.effect("leg flexibility")
        if leg is not None and leg.above:   # the leg's mass tops the strut; its spring is slack
            y[dyn.ZW] = y[dyn.Z1]
        y[dyn.V1] = y[dyn.V2] = y[dyn.VW] = contact_velocity
        y[dyn.THETA] = 1.0
        return y

    def rates(self, state: np.ndarray) -> np.ndarray:
        """Time derivative of a full state vector (slots of :mod:`certkit.physics.dynamics`)."""
        dy = np.empty(dyn.STATES)
        dyn.rates(self.pack(), np.asarray(state, dtype=float), dy)
        return dy

    def static_stroke(self) -> float:
        """Equilibrium stroke under the upper mass's weight less lift (friction-free; with
        heat transfer the gas at rest is at wall temperature, so isothermal)."""
        load = (self.upper_mass * STANDARD_GRAVITY - self.lift) * math.cos(self.inclination)
        return self.gas.equilibrium_stroke(
            load, 1.0 if self.effect("heat transfer") is not None else None)

    def described(self) -> list[tuple[str, Parameter]]:
        """Every term's parameters, for reports: (term name, parameter)."""
        return [(term.name, parameter) for term in self.terms()
                for parameter in term.parameters()]
