"""Effects simple drop models omit (physics.md §3), each an optional strut term.

Every effect is off unless added to a :class:`~certkit.drop_model.DropModel`'s
``effects``; each is a small dataclass with named SI parameters and a
``force(stroke, rate, gas_force)`` method returning its axial strut force
(compression positive).  Adding an effect is adding one class here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .drop_model import Parameter, Term, orifice_coefficient


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

    def parameters(self):
        return [Parameter("constant", self.constant, "N", "Coulomb friction F_0"),
                Parameter("pressure_factor", self.pressure_factor, "1",
                          "share μ of the gas force acting as friction"),
                Parameter("breakaway", self.breakaway, "N", "Stribeck excess F_S − F_C"),
                Parameter("stribeck_velocity", self.stribeck_velocity, "m/s", "v_s"),
                Parameter("smoothing_velocity", self.smoothing_velocity, "m/s", "v_ε")]

    def force(self, stroke, rate, gas_force):
        level = self.constant + self.pressure_factor * np.abs(gas_force)
        if np.any(self.breakaway):  # skip the Stribeck term's exp when it is off
            level = level + self.breakaway * np.exp(-(rate / self.stribeck_velocity) ** 2)
        return level * np.tanh(rate / self.smoothing_velocity)


@dataclass(frozen=True)
class ReboundOrifice(Term):
    """Separate rebound orifice (recoil valve): extra damping on extension only (physics.md §3 #3).

    The nominal orifice damps both ways with K_h; on extension (ṡ < 0) this adds
    (K_reb − K_h)·ṡ|ṡ| so the total rebound damping is K_reb = ρ·A_h³/(2·(C_d·A_reb)²).
    """

    extra_coefficient: float  # K_reb − K_h [N·s²/m²]
    name = "rebound orifice"

    def parameters(self):
        return [Parameter("extra_coefficient", self.extra_coefficient, "N*s^2/m^2",
                          "rebound damping in excess of the compression orifice")]

    def force(self, stroke, rate, gas_force):
        extension = np.minimum(rate, 0.0)
        return -self.extra_coefficient * extension * extension


@dataclass(frozen=True)
class MeteringPin(Term):
    """Metering pin: orifice area varying with stroke, A_n(s) from a table (physics.md §3 #4).

    Added to the nominal orifice (area A_0) as the difference of the two square laws:
    F = ρ·A_h³/(2·C_d²)·(1/A_n(s)² − 1/A_0²)·ṡ|ṡ|, A_n(s) linearly interpolated.
    """

    strokes: tuple          # s_i [m], increasing
    areas: tuple            # A_n(s_i) [m^2]
    hydraulic_area: float   # A_h [m^2]
    nominal_area: float     # A_0, the nominal orifice's area [m^2]
    discharge: float        # C_d
    density: float = 860.0  # ρ [kg/m^3]
    name = "metering pin"

    def parameters(self):
        return [Parameter("strokes", self.strokes, "m", "stroke points of the area table"),
                Parameter("areas", self.areas, "m^2", "net orifice area at those strokes"),
                Parameter("hydraulic_area", self.hydraulic_area, "m^2", "A_h"),
                Parameter("nominal_area", self.nominal_area, "m^2", "A_0 of the nominal orifice"),
                Parameter("discharge", self.discharge, "1", "C_d"),
                Parameter("density", self.density, "kg/m^3", "ρ")]

    def force(self, stroke, rate, gas_force):
        area = np.interp(stroke, self.strokes, self.areas)
        pinned = orifice_coefficient(self.hydraulic_area, area, self.discharge, self.density)
        nominal = orifice_coefficient(self.hydraulic_area, self.nominal_area, self.discharge,
                                      self.density)
        return (pinned - nominal) * rate * np.abs(rate)


@dataclass(frozen=True)
class TyreHysteresis(Term):
    """Tyre hysteresis: loading above unloading by a share of the static curve (physics.md §3 #9).

    F = h·f(δ)·tanh(δ̇/v_ε): the loop between loading and unloading is 2·h·f(δ) wide, so a
    share of about h of the tyre's work is lost per cycle.
    """

    share: float                      # h [1]
    smoothing_velocity: float = 0.01  # v_ε [m/s]
    name = "tyre hysteresis"

    def parameters(self):
        return [Parameter("share", self.share, "1", "half-width h of the loop, share of f(δ)"),
                Parameter("smoothing_velocity", self.smoothing_velocity, "m/s", "v_ε")]

    def force(self, deflection, rate, static_force):
        return self.share * static_force * np.tanh(rate / self.smoothing_velocity)


@dataclass(frozen=True)
class SensorDynamics:
    """Transducer and logger dynamics on measured channels (physics.md §3 #12).

    A causal Butterworth low-pass of the given order and cut-off (an anti-alias or
    smoothing filter) followed by a pure delay (channel skew, transducer lag).  It acts on
    the recorded signals, not on the mechanics: apply it to a simulated channel to compare
    like with like.  Group delay of a 2nd-order 100 Hz Butterworth at 1 kHz: about 2.2 ms.
    """

    cutoff: float          # [Hz]
    order: int = 2
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
        b, a = butter(self.order, self.cutoff, fs=1.0 / step)
        filtered = lfilter(b, a, signal, zi=lfilter_zi(b, a) * signal[0])[0]
        if self.delay:
            filtered = np.interp(time - self.delay, time, filtered, left=filtered[0])
        return filtered
