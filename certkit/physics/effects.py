"""Effects simple drop models omit (physics.md §3), each an optional term of the drop model.

Every effect is off unless added to a :class:`~certkit.physics.drop_model.DropModel`'s
``effects``.  Each is a small frozen dataclass with named SI parameters that writes them
into the slots of the compiled equations of motion (:mod:`certkit.physics.dynamics`), where its
force law lives.  :class:`SensorDynamics` is different: it acts on recorded signals, not
on the mechanics.  ``EFFECTS`` maps the spec's effect names to the classes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from certkit.physics import dynamics as dyn
from certkit.physics.drop_model import Parameter, Term, orifice_coefficient


@dataclass(frozen=True)
class SealFriction(Term):
    """Seal friction, Coulomb with an optional Stribeck peak, regularised (physics.md §3 #1).

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


@dataclass(frozen=True)
class ReboundOrifice(Term):
    """Separate rebound orifice (recoil valve): extra damping on extension only (physics.md §3 #3).

    The nominal orifice damps both ways with K_h; on extension (ṡ < 0) this adds
    (K_reb − K_h)·ṡ|ṡ| so the total rebound damping is K_reb = ρ·A_h³/(2·(C_d·A_reb)²).
    With a metering pin the excess adds to the pin's K(s) (a parallel recoil restriction).
    """

    extra_coefficient: float  # K_reb − K_h [N·s²/m²]
    name = "rebound orifice"
    fields = (("extra_coefficient", "N*s^2/m^2",
               "rebound damping in excess of the compression orifice"),)

    def pack(self, p):
        p[dyn.REBOUND_EXTRA] = self.extra_coefficient


@dataclass(frozen=True)
class MeteringPin(Term):
    """Metering pin: orifice area varying with stroke, A_n(s) from a table (physics.md §3 #4).

    Replaces the nominal orifice's constant area: F_h = ρ·A_h³/(2·C_d²·A_n(s)²)·ṡ|ṡ|,
    A_n(s) linearly interpolated in the table (held constant beyond its ends).
    """

    strokes: tuple          # s_i [m], increasing
    areas: tuple            # A_n(s_i) [m^2]
    hydraulic_area: float   # A_h [m^2]
    nominal_area: float     # A_0, the nominal orifice's area [m^2] (for reference)
    discharge: float        # C_d
    density: float = 860.0  # ρ [kg/m^3]
    name = "metering pin"
    fields = (("strokes", "m", "stroke points of the area table"),
              ("areas", "m^2", "net orifice area at those strokes"),
              ("hydraulic_area", "m^2", "hydraulic area A_h"),
              ("nominal_area", "m^2", "area A_0 of the nominal orifice"),
              ("discharge", "1", "discharge coefficient C_d"),
              ("density", "kg/m^3", "oil density ρ"))

    def __post_init__(self):
        if not 2 <= len(self.strokes) == len(self.areas) <= dyn.PIN_POINTS:
            raise ValueError(f"a metering-pin table needs 2 to {dyn.PIN_POINTS} points, as many "
                             "areas as strokes")
        if any(b <= a for a, b in zip(self.strokes, self.strokes[1:])):
            raise ValueError("the metering-pin strokes must increase")
        if min(self.areas) <= 0:
            raise ValueError("the metering-pin areas must be positive")

    def pack(self, p):
        count = len(self.strokes)
        p[dyn.PIN], p[dyn.PIN_COUNT] = 1.0, count
        # K(s) = ρ·A_h³/(2·C_d²)/A_n(s)², the nominal orifice law with the table's area
        p[dyn.PIN_COEFFICIENT] = orifice_coefficient(self.hydraulic_area, 1.0, self.discharge,
                                                     self.density)
        p[dyn.PIN_STROKES:dyn.PIN_STROKES + count] = self.strokes
        p[dyn.PIN_AREAS:dyn.PIN_AREAS + count] = self.areas


@dataclass(frozen=True)
class TyreHysteresis(Term):
    """Tyre hysteresis: loading above unloading by a share of the static curve (physics.md §3 #9).

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


@dataclass(frozen=True)
class GasHeatTransfer(Term):
    """Heat exchange between the gas and the strut walls (physics.md §3 #6).

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


@dataclass(frozen=True)
class LegFlexibility(Term):
    """Structural flexibility of the gear leg: the axle as an extra degree of freedom
    (physics.md §3 #8).

    The axle and wheel (mass m_w, taken out of the unsprung mass m2) hang on the strut's
    sliding tube through a spring k_l and damper c_l: the leg's bending and the axle's
    compliance, as they act in the vertical direction.  It rings at about
    √((k_l + k_t)/m_w)/2π on load and tyre deflection, not on stroke.
    """

    axle_mass: float      # m_w [kg]
    stiffness: float      # k_l [N/m]
    damping: float = 0.0  # c_l [N·s/m]
    name = "leg flexibility"

    def __post_init__(self):
        if not (self.axle_mass > 0 and self.stiffness > 0 and self.damping >= 0):
            raise ValueError("the leg needs a positive axle mass and stiffness")

    fields = (("axle_mass", "kg", "mass of axle and wheel m_w (part of m2)"),
              ("stiffness", "N/m", "leg stiffness k_l"),
              ("damping", "N*s/m", "leg damping c_l"))

    def pack(self, p):
        if not 0 < self.axle_mass < p[dyn.M2]:
            raise ValueError(f"the axle mass {self.axle_mass} kg must be positive and less than "
                             f"the unsprung mass {p[dyn.M2]} kg")
        p[dyn.LEG], p[dyn.M2] = 1.0, p[dyn.M2] - self.axle_mass
        p[dyn.LEG_MASS], p[dyn.LEG_STIFFNESS] = self.axle_mass, self.stiffness
        p[dyn.LEG_DAMPING] = self.damping


@dataclass(frozen=True)
class PlatformCompliance(Term):
    """Platform and load-cell compliance and inertia (physics.md §3 #10).

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


@dataclass(frozen=True)
class OilCompressibility(Term):
    """Oil compressibility: the oil column as a spring in series with the orifice
    (physics.md §3 #7).

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


@dataclass(frozen=True)
class SensorLag(Term):
    """A first-order lag of every recorded channel (time constant τ): the simplest form of
    transducer and logger dynamics (physics.md §3 #12), as a model term.

    It acts on the channels the simulation records, not on the mechanics (``pack`` writes
    nothing); :func:`certkit.physics.simulation.simulate_batch` and ``simulate_reference`` apply
    it.  Exact discretisation of τ·ẏ + y = x for a piecewise-constant input.
    """

    time_constant: float  # τ [s]
    name = "sensor lag"
    fields = (("time_constant", "s", "time constant τ of the first-order lag"),)

    def __post_init__(self):
        if not self.time_constant >= 0:
            raise ValueError("the sensor lag's time constant must not be negative")

    def pack(self, p):
        pass  # recorded channels only

    def apply(self, step: float, signal: np.ndarray) -> np.ndarray:
        """The lagged signal (last axis is time), starting at the signal's first value."""
        from scipy.signal import lfilter

        if self.time_constant == 0:
            return np.asarray(signal, dtype=float)
        a = np.exp(-step / self.time_constant)
        signal = np.asarray(signal, dtype=float)
        return lfilter([1 - a], [1, -a], signal, axis=-1, zi=(a * signal[..., :1]))[0]


@dataclass(frozen=True)
class SensorDynamics:
    """Transducer and logger dynamics on measured channels (physics.md §3 #12).

    A causal Butterworth low-pass of the given order and cut-off (an anti-alias or
    smoothing filter) followed by a pure delay (channel skew, transducer lag).  It acts on
    the recorded signals, not on the mechanics: apply it to a simulated channel to compare
    like with like.  Group delay of a 2nd-order 100 Hz Butterworth at 1 kHz: about 2.2 ms.
    """

    cutoff: float          # [Hz]
    order: int = 2         # 0: no low-pass, a pure delay
    delay: float = 0.0     # [s]
    name = "sensor dynamics"

    def parameters(self):
        return [Parameter("cutoff", self.cutoff, "Hz", "low-pass cut-off frequency"),
                Parameter("order", self.order, "1", "Butterworth order"),
                Parameter("delay", self.delay, "s", "pure delay")]

    def apply(self, time: np.ndarray, signal: np.ndarray) -> np.ndarray:
        """The signal as the logger records it (time uniform, starting before contact)."""
        from scipy.signal import butter, lfilter, lfilter_zi

        step = float(np.mean(np.diff(time)))
        filtered = np.asarray(signal, dtype=float)
        if self.order:                      # order 0: no low-pass, a pure delay
            b, a = butter(self.order, self.cutoff, fs=1.0 / step)
            filtered = lfilter(b, a, filtered, zi=lfilter_zi(b, a) * filtered[0])[0]
        if self.delay:
            filtered = np.interp(time - self.delay, time, filtered, left=filtered[0])
        return filtered
