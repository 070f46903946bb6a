"""An independent drop simulator for one landing-gear unit on a rigid load platform.

Written apart from certkit (it imports nothing from it) so that the gap diagnosis can be
tried on physics it did not write.  Textbook two-mass oleo-pneumatic model (Milwitzky &
Cook, NACA Report 1154, 1953; Currey, *Aircraft Landing Gear Design*, AIAA 1988, ch. 5):

* coordinates positive downward from the configuration at first tyre contact; x1 the
  upper (drop) mass, x2 the piston and unsprung mass; a third mass xl when a leg is
  flexible (the strut cylinder above the strut, or the wheel below the piston rod);
* strut force (pushing the masses apart) = gas + oil damping + friction − top-out pad:
  gas (p − p_atm)·A with p = p0·(V0/V)^n, V = V0 − A·s; oil K·ṡ·|ṡ| (K for compression
  and rebound); the top-out pad an elastomer k·(−s)^1.5 for s < 0;
* tyre force F(δ)·(1 + c·δ̇) ≥ 0, F(δ) = P·(δ/δ_ref)^b;
* integrated by the classical fourth-order Runge–Kutta method at a fixed step of at most
  20 µs (compiled with numba), so the same inputs give the same numbers.

Nuisance physics a nominal model lacks (:class:`Nuisances`, on by default): the top-out
pad compresses 1.5 mm under the gas preload (the strut starts to stroke softly), the gas
is not ideal (p·(1 + β·(V0/V − 1)), β = 0.03, a compressibility and dissolution
correction), and the tyre curve is not a pure power law (·(1 + 0.06·(δ/δ_ref − 1))).

Recorded channels: platform load (the tyre force), stroke (zeroed where the strut hangs
in free fall), tyre deflection (0 off the platform), acceleration of the drop mass
(positive downward) and its displacement from contact (positive downward), sampled at
the logger's instants, which need not fall on the contact (``phase``).  What a recording
chain does (a filter and a delay, a channel's skew, crosstalk) acts on the continuous
signals (the integrator's every step) before the logger samples them, as it does in a
real chain: a delay of a fraction of a sample is not an interpolation between samples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit
from scipy import signal

from .forms import FORMS

G = 9.80665
P_ATM = 101325.0
MAX_STEP = 2e-5

# state slots
X1, V1, X2, V2, XL, VL, Z, W = range(8)
# parameter slots
(M1, M2, ML, LIFT, LEG_MODE, K_LEG, C_LEG, AREA, VOLUME, PRECHARGE, EXPONENT, BETA, K_COMP,
 K_REB, REB_FORM, REB_SIZE, PAD_K, HANG, FRIC_FORM, FRIC_SIZE, TYRE_P, TYRE_D, TYRE_B,
 TYRE_C, TYRE_SHAPE, HYST_FORM, HYST_SIZE, HYST_W0, FRIC_RATIO, FRIC_VS, FRIC_BRISTLE,
 FRIC_VISC, DAHL_X, HYST_BETA, BLOW_SPEED, LIN_SPEED, LIN_SHARE) = range(37)
SLOTS = 37


@dataclass(frozen=True)
class Gear:
    """One gear unit in SI units: masses [kg], piston area [m²], gas volume [m³],
    precharge [Pa absolute], orifice coefficients K [N·s²/m²] (force K·ṡ²), tyre reference
    load [N] at reference deflection [m], tyre exponent, tyre damping [s/m], lift as a share
    of the gear's weight acting upward on the upper mass.  There is no bottoming stop: the
    drops it is used for stay well inside the stroke (about half of it in the example)."""

    upper_mass: float
    lower_mass: float
    piston_area: float
    gas_volume: float
    precharge_abs: float
    polytropic_exponent: float
    compression_coefficient: float
    rebound_coefficient: float
    tyre_reference_load: float
    tyre_reference_deflection: float
    tyre_exponent: float
    tyre_damping: float = 0.0
    lift: float = 0.0


@dataclass(frozen=True)
class Nuisances:
    """Physics a nominal model lacks: pad compression under preload [m] (0: a near-rigid
    top-out stop), the real-gas coefficient β, the tyre curve's departure per δ/δ_ref."""

    pad: float = 1.5e-3
    gas: float = 0.03
    tyre_shape: float = 0.06

    @classmethod
    def none(cls) -> "Nuisances":
        return cls(pad=0.0, gas=0.0, tyre_shape=0.0)


@dataclass(frozen=True)
class Record:
    time: np.ndarray
    load: np.ndarray
    stroke: np.ndarray
    tyre: np.ndarray
    acceleration: np.ndarray
    displacement: np.ndarray


@njit(cache=True)
def _gas_force(p, s):
    volume = p[VOLUME] - p[AREA] * s
    if volume < 0.02 * p[VOLUME]:
        volume = 0.02 * p[VOLUME]
    ratio = p[VOLUME] / volume
    pressure = p[PRECHARGE] * ratio ** p[EXPONENT] * (1.0 + p[BETA] * (ratio - 1.0))
    return (pressure - P_ATM) * p[AREA]


@njit(cache=True)
def _derivatives(p, y, dy):
    mode = int(p[LEG_MODE])
    if mode == 1:                          # leg above the strut: the cylinder is xl
        s = p[HANG] + y[XL] - y[X2]
        v = y[VL] - y[V2]
        delta, rate = y[X2], y[V2]
    elif mode == 2:                        # flexible axle: the wheel is xl
        s = p[HANG] + y[X1] - y[X2]
        v = y[V1] - y[V2]
        delta, rate = y[XL], y[VL]
    else:
        s = p[HANG] + y[X1] - y[X2]
        v = y[V1] - y[V2]
        delta, rate = y[X2], y[V2]

    strut = _gas_force(p, s)
    if s < 0.0:
        strut -= p[PAD_K] * (-s) ** 1.5
    if v >= 0.0:
        strut += p[K_COMP] * v * v
    else:
        speed = -v
        extra = 0.0
        if p[REB_FORM] == 1.0:
            if speed <= p[BLOW_SPEED]:
                extra = p[REB_SIZE] * p[K_REB] * speed * speed
            else:
                extra = p[REB_SIZE] * p[K_REB] * p[BLOW_SPEED] * speed
        elif p[REB_FORM] == 2.0:
            extra = p[REB_SIZE] * p[K_REB] * ((1.0 - p[LIN_SHARE]) * speed * speed
                                              + p[LIN_SHARE] * p[LIN_SPEED] * speed)
        strut -= p[K_REB] * speed * speed + extra

    dy[Z] = 0.0
    if p[FRIC_FORM] == 1.0:                # LuGre
        fc = p[FRIC_SIZE]
        sigma0 = fc / p[FRIC_BRISTLE]
        g = fc + (p[FRIC_RATIO] - 1.0) * fc * math.exp(-(v / p[FRIC_VS]) ** 2)
        dy[Z] = v - sigma0 * abs(v) * y[Z] / g
        strut += sigma0 * y[Z] + p[FRIC_VISC] * fc * v
    elif p[FRIC_FORM] == 2.0:              # Dahl, the state is the force
        fc = p[FRIC_SIZE]
        sign = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
        dy[Z] = fc / p[DAHL_X] * v * (1.0 - y[Z] * sign / fc)
        strut += y[Z]

    tyre = 0.0
    dy[W] = 0.0
    if delta > 0.0:
        x = delta / p[TYRE_D]
        static = p[TYRE_P] * x ** p[TYRE_B] * (1.0 + p[TYRE_SHAPE] * (x - 1.0))
        tyre = static * (1.0 + p[TYRE_C] * rate)
        if p[HYST_FORM] != 0.0:
            w0 = p[HYST_W0]
            same = 1.0 if rate * y[W] > 0.0 else 0.0
            beta = p[HYST_BETA]
            dy[W] = rate * (1.0 - (beta * same + (1.0 - beta)) * abs(y[W]) / w0)
            if p[HYST_FORM] == 1.0:
                tyre += p[HYST_SIZE] * y[W] / w0
            else:
                tyre += p[HYST_SIZE] * static * y[W] / w0
        if tyre < 0.0:
            tyre = 0.0

    dy[X1], dy[X2], dy[XL] = y[V1], y[V2], y[VL]
    if mode == 1:
        leg = p[K_LEG] * (y[X1] - y[XL]) + p[C_LEG] * (y[V1] - y[VL])
        dy[V1] = G - (p[LIFT] + leg) / p[M1]
        dy[VL] = G + (leg - strut) / p[ML]
        dy[V2] = G + (strut - tyre) / p[M2]
    elif mode == 2:
        leg = p[K_LEG] * (y[X2] - y[XL]) + p[C_LEG] * (y[V2] - y[VL])
        dy[V1] = G - (p[LIFT] + strut) / p[M1]
        dy[V2] = G + (strut - leg) / p[M2]
        dy[VL] = G + (leg - tyre) / p[ML]
    else:
        dy[V1] = G - (p[LIFT] + strut) / p[M1]
        dy[V2] = G + (strut - tyre) / p[M2]
        dy[VL] = 0.0
    return tyre, s


@njit(cache=True)
def _integrate(p, y0, samples, substeps, step):
    out = np.empty((samples, 6))
    y = y0.copy()
    k1, k2, k3, k4 = np.empty(8), np.empty(8), np.empty(8), np.empty(8)
    tmp = np.empty(8)
    for k in range(samples):
        tyre, s = _derivatives(p, y, k1)
        out[k, 0], out[k, 1] = tyre, s
        out[k, 2] = y[XL] if p[LEG_MODE] == 2.0 else y[X2]
        out[k, 3], out[k, 4] = k1[V1], y[X1]
        out[k, 5] = y[Z]
        for _ in range(substeps):
            _derivatives(p, y, k1)
            for i in range(8):
                tmp[i] = y[i] + 0.5 * step * k1[i]
            _derivatives(p, tmp, k2)
            for i in range(8):
                tmp[i] = y[i] + 0.5 * step * k2[i]
            _derivatives(p, tmp, k3)
            for i in range(8):
                tmp[i] = y[i] + step * k3[i]
            _derivatives(p, tmp, k4)
            for i in range(8):
                y[i] += step / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
    return out


def _parameters(gear: Gear, truths, nuisances: Nuisances, drop_index: int) -> np.ndarray:
    p = np.zeros(SLOTS)
    p[M1], p[M2] = gear.upper_mass, gear.lower_mass
    p[LIFT] = gear.lift * (gear.upper_mass + gear.lower_mass) * G
    p[AREA], p[VOLUME] = gear.piston_area, gear.gas_volume
    p[PRECHARGE], p[EXPONENT] = gear.precharge_abs, gear.polytropic_exponent
    p[BETA] = nuisances.gas
    p[K_COMP], p[K_REB] = gear.compression_coefficient, gear.rebound_coefficient
    p[TYRE_P], p[TYRE_D] = gear.tyre_reference_load, gear.tyre_reference_deflection
    p[TYRE_B], p[TYRE_C] = gear.tyre_exponent, gear.tyre_damping
    p[TYRE_SHAPE] = nuisances.tyre_shape
    for truth in truths:
        size = truth.size
        if truth.form == "lugre":
            p[FRIC_FORM], p[FRIC_SIZE] = 1.0, size
            p[FRIC_RATIO], p[FRIC_VS] = truth.value("static_ratio"), truth.value("stribeck_speed")
            p[FRIC_BRISTLE], p[FRIC_VISC] = truth.value("bristle"), truth.value("viscous")
        elif truth.form == "dahl":
            p[FRIC_FORM], p[FRIC_SIZE], p[DAHL_X] = 2.0, size, truth.value("presliding")
        elif truth.form in ("tyre-bouc-wen", "tyre-proportional"):
            p[HYST_FORM] = 1.0 if truth.form == "tyre-bouc-wen" else 2.0
            p[HYST_SIZE], p[HYST_W0] = size, truth.value("w0")
            p[HYST_BETA] = truth.value("beta")
        elif truth.form in ("leg-above", "leg-axle"):
            stiffness = 1.0 / size
            if truth.form == "leg-above":
                leg_mass = truth.value("leg_mass")
                p[LEG_MODE], p[ML] = 1.0, leg_mass
                p[M1] = gear.upper_mass - leg_mass
            else:
                share = truth.value("wheel_share")
                p[LEG_MODE], p[ML] = 2.0, share * gear.lower_mass
                p[M2] = (1.0 - share) * gear.lower_mass
            p[K_LEG] = stiffness
            p[C_LEG] = 2.0 * truth.value("damping_ratio") * math.sqrt(stiffness * p[ML])
        elif truth.form == "blow-off":
            p[REB_FORM], p[REB_SIZE], p[BLOW_SPEED] = 1.0, size, truth.value("blow_off_speed")
        elif truth.form == "linear-quadratic":
            p[REB_FORM], p[REB_SIZE] = 2.0, size
            p[LIN_SPEED], p[LIN_SHARE] = truth.value("linear_speed"), truth.value("linear_share")
        elif truth.form == "gas-drift":
            p[PRECHARGE] *= 1.0 + size * drop_index
        elif truth.form not in FORMS:
            raise ValueError(f"unknown truth form {truth.form!r}; known: {sorted(FORMS)}")
    # the top-out pad: at the hang stroke −d its force balances the gas preload
    depth = nuisances.pad if nuisances.pad > 0 else 5e-5
    p[HANG] = 0.0
    p[PAD_K] = 0.0
    p[PAD_K] = _gas_force(p, -depth) / depth ** 1.5
    p[HANG] = -depth
    return p


def _delayed(signal_in: np.ndarray, rate: float, delay: float) -> np.ndarray:
    """A signal on samples 1/``rate`` apart delayed by ``delay`` [s] (linear interpolation,
    steady at its first and last values)."""
    index = np.arange(signal_in.size, dtype=float) - delay * rate
    return np.interp(index, np.arange(signal_in.size, dtype=float), signal_in)


def _lag(signal_in: np.ndarray, rate: float, truth) -> np.ndarray:
    """A channel through the form's filter and delay (steady at its first value), on the
    integrator's fine grid (``rate`` its sample rate, far above the filter's band: the
    digital filter there is the analog one the recording chain has, to well within its
    own tolerance)."""
    size = truth.size
    order = int(round(truth.value("order")))
    cutoff = 1.0 / (2.0 * math.pi * size)
    nyquist = 0.5 * rate
    if cutoff >= 0.95 * nyquist:            # beyond any band the grid resolves: the delay only
        filtered = signal_in.copy()
    else:
        if truth.form == "bessel-delay":
            sos = signal.bessel(order, cutoff / nyquist, norm="delay", output="sos")
        else:
            sos = signal.butter(order, cutoff / nyquist, output="sos")
        zi = signal.sosfilt_zi(sos) * signal_in[0]
        filtered, _ = signal.sosfilt(sos, signal_in, zi=zi)
    return _delayed(filtered, rate, size * truth.value("delay_share"))


#: Forms that act on what the logger records, not on the mechanics.
RECORDER_FORMS = ("bessel-delay", "butterworth-delay", "crosstalk", "gain-skew")


def _recorded(fine: np.ndarray, fine_rate: float, every: int, truths) -> tuple:
    """The channels (load, stroke, tyre, acceleration, displacement) the logger samples,
    every ``every``-th instant of the integrator's fine grid (rate ``fine_rate``), after
    the recorder forms of ``truths`` acted on the continuous signals: a filter and a delay
    act before the logger samples (an analog anti-alias filter, a transducer's own
    dynamics); a channel skew means the load is sampled τ after the others, not that its
    samples are interpolated; crosstalk adds the load of an earlier instant."""
    channels = [fine[:, 0], fine[:, 1], fine[:, 2], fine[:, 3], fine[:, 4]]
    for truth in truths:
        if truth.form in ("bessel-delay", "butterworth-delay"):
            channels = [_lag(x, fine_rate, truth) for x in channels]
        elif truth.form == "crosstalk":
            channels[0] = channels[0] + truth.size * _delayed(channels[0], fine_rate,
                                                              truth.value("delay"))
        elif truth.form == "gain-skew":
            sign = 1.0 if truth.value("sign") >= 0 else -1.0
            channels[0] = (1.0 + sign * truth.size) * _delayed(channels[0], fine_rate,
                                                               truth.value("skew"))
    return tuple(x[::every] for x in channels)


def simulate(gear: Gear, contact_velocity: float, rate: float, duration: float = 2.0,
             lead: float = 0.1, truths=(), nuisances: Nuisances = Nuisances(),
             drop_index: int = 0, phase: float = 0.0) -> Record:
    """One drop: samples at t = −lead − phase/rate + k/rate, k < round((lead + duration)·rate);
    the tyre touches the platform at t = 0 with ``contact_velocity`` [m/s], ``phase`` (0 ≤
    phase < 1) of a sample interval after the last sample before it (0: contact falls on a
    sample; a logger's clock is not synchronised with the drop, so contact falls anywhere
    between two samples); ``truths`` the withheld effects (:class:`Truth`), ``drop_index``
    the drop's place in the test sequence."""
    if not 0.0 <= phase < 1.0:
        raise ValueError(f"the contact phase must lie in [0, 1), got {phase!r}")
    truths = tuple(truths)
    p = _parameters(gear, truths, nuisances, drop_index)
    samples = int(round((lead + duration) * rate))
    substeps = max(1, int(math.ceil(1.0 / (rate * MAX_STEP))))
    step = 1.0 / (rate * substeps)
    lead = lead + phase / rate                       # the first sample is this long before contact
    y0 = np.zeros(8)
    speed = contact_velocity - G * lead              # free fall until contact
    start = -(contact_velocity * lead - 0.5 * G * lead ** 2)
    for slot, velocity in ((X1, V1), (X2, V2), (XL, VL)):
        y0[slot], y0[velocity] = start, speed
    recorders = tuple(t for t in truths if t.form in RECORDER_FORMS)
    # with a recorder form, every integrator step is kept (the continuous signals it acts
    # on); the samples at the logger's instants are the same numbers either way
    out = _integrate(p, y0, samples * substeps if recorders else samples,
                     1 if recorders else substeps, step)
    out[:, 1] -= p[HANG]
    out[:, 2] = np.maximum(out[:, 2], 0.0)
    time = -lead + np.arange(samples) / rate
    load, stroke, tyre, acceleration, displacement = _recorded(
        out, rate * substeps, substeps if recorders else 1, recorders)
    return Record(time, load, stroke, tyre, acceleration, displacement)
