"""What a drop's time histories say: touchdown, peaks, travels, energies, rebound, settling.

Plain functions on SI arrays, shared by measured runs and (later) simulated ones,
so both go through identical code downstream.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from certkit.compliance.clauses import drop_test_load_factor
from certkit.compliance.energy import absorbed_energy, work_until
from certkit.units import STANDARD_GRAVITY

#: Touchdown: load first exceeds this share of the unit's static weight (the upper end of a
#: 1-2 % threshold, so that platform noise alone does not start a drop) or six robust
#: standard deviations of the pre-contact noise.
TOUCHDOWN_SHARE = 0.02
TOUCHDOWN_SIGMAS = 6.0
#: Settling: stroke stays within this share of its maximum around its final value.
SETTLING_BAND = 0.05
#: Final value: mean over this last share of the record.
FINAL_SHARE = 0.05
#: Window before touchdown used to fit the contact velocity from the drop-mass displacement.
VELOCITY_WINDOW = 0.050
#: Window before the touchdown sample over which a travel channel's zero is read (median): the
#: last samples below the touchdown threshold may already follow contact (a soft tyre deflects
#: about a millimetre before its load clears the threshold), so a single sample's reading
#: would depend on where the logger's samples happen to fall.
ZERO_WINDOW = 0.010


def _touchdown_threshold(load: np.ndarray, static_weight: float) -> tuple[float, float] | None:
    """(baseline, threshold above it) of the touchdown detector, None without a peak."""
    peak = float(np.max(load))
    if peak <= 0:
        return None
    quiet = load[:int(np.argmax(load >= 0.2 * peak))]
    noise, baseline = 0.0, 0.0
    if quiet.size >= 5:
        baseline = float(np.median(quiet))
        noise = 1.4826 * float(np.median(np.abs(quiet - baseline)))
    return baseline, max(TOUCHDOWN_SHARE * static_weight, TOUCHDOWN_SIGMAS * noise)


def _first_above(values: np.ndarray, level: float) -> int | None:
    above = np.flatnonzero(values > level)
    if above.size == 0 or above[0] == 0:
        return None
    return int(above[0])


def touchdown_index(load: np.ndarray, static_weight: float) -> int | None:
    """First sample of tyre contact, from the load channel (None if the record starts loaded).

    The threshold is the larger of 2 % of the unit's static weight and six robust
    standard deviations (1.4826 x median absolute deviation) of the samples before
    the load first reaches 20 % of its peak, above their median.
    """
    load = np.asarray(load, dtype=float)
    found = _touchdown_threshold(load, static_weight)
    if found is None:
        return None
    baseline, threshold = found
    return _first_above(load - baseline, threshold)


def touchdown_time(time: np.ndarray, load: np.ndarray, static_weight: float | None,
                   level: float | None = None) -> tuple[float, float] | None:
    """Time the load first crosses the touchdown threshold, interpolated between samples.

    The threshold is :func:`touchdown_index`'s (above the pre-contact baseline), or
    ``level`` above zero when given, so a simulated run is detected at the measured run's
    level.  Returns (time, threshold), or None.
    """
    load = np.asarray(load, dtype=float)
    if level is None:
        found = _touchdown_threshold(load, static_weight)
        if found is None:
            return None
        baseline, level = found
        load = load - baseline
    index = _first_above(load, level)
    if index is None:
        return None
    before, after = float(load[index - 1]), float(load[index])
    fraction = (level - before) / (after - before)
    return float(time[index - 1] + fraction * (time[index] - time[index - 1])), level


@dataclass(frozen=True)
class GearMeasures:
    """Quantities read off one gear unit's histories (SI; None when not recorded)."""

    touchdown_time: float | None
    peak_load: float
    peak_load_time: float
    max_stroke: float | None
    max_tyre: float | None
    max_total_travel: float | None
    strut_energy: float | None
    tyre_energy: float | None
    min_stroke_after_peak: float | None
    lift_off_duration: float | None
    settling_time: float | None
    stroke_at_touchdown: float | None = None    # median over ZERO_WINDOW before touchdown
    tyre_at_touchdown: float | None = None
    #: E_s + E_t each taken from touchdown to the instant of maximum total travel d (certkit E5)
    energy_at_max_travel: float | None = None


#: Savitzky-Golay window for the axle acceleration: 20 ms (cubic; 21 samples at 1 kHz),
#: passing the tyre/axle motion (< 50 Hz) while suppressing sensor noise, whose second
#: difference is σ·√6/dt² (300 m/s² for 0.05 mm at 1 kHz).
AXLE_WINDOW = 0.020   # s
AXLE_POLYORDER = 3


def window_samples(duration: float, step: float, minimum: int = 1) -> int:
    """The odd number of samples spanning ``duration`` [s] at sample interval ``step`` [s]
    (first to last sample), at least ``minimum``: 21 for 20 ms at 1 kHz, 41 at 2 kHz."""
    return max(2 * int(round(0.5 * duration / step)) + 1, minimum)


def axle_acceleration(time: np.ndarray, tyre: np.ndarray) -> np.ndarray:
    """δ̈ from the tyre deflection: Savitzky-Golay second derivative (cubic, over
    :data:`AXLE_WINDOW`) on a uniform time base; cubic-spline second derivative otherwise."""
    # lazy, as in certkit.compliance.energy: about 0.25 s of start-up, time series only
    from scipy.interpolate import CubicSpline
    from scipy.signal import savgol_filter

    steps = np.diff(time)
    step = float(np.mean(steps))
    window = window_samples(AXLE_WINDOW, step, AXLE_POLYORDER + 2)
    if len(time) > window and np.ptp(steps) <= 1e-6 * step:
        return savgol_filter(tyre, window, AXLE_POLYORDER, deriv=2, delta=step)
    return CubicSpline(time, tyre).derivative(2)(time)


def strut_force(time: np.ndarray, load: np.ndarray, tyre: np.ndarray | None,
                unsprung_mass: float, inclination: float) -> np.ndarray:
    """Axial strut force from the platform load: F_s/cos θ = F_V − m2·(g − δ̈).

    The lower-mass equation of the drop model (certkit.physics.drop_model) with the axle
    acceleration δ̈ from :func:`axle_acceleration` (rigid platform).  With m2 = 0 (not
    declared) or no tyre channel, F_s = F_V·cos θ.
    """
    cos_theta = math.cos(inclination)
    if not unsprung_mass or tyre is None:
        return load * cos_theta
    return (load - unsprung_mass * (STANDARD_GRAVITY - axle_acceleration(time, tyre))) * cos_theta


def measure_gear(time: np.ndarray, load: np.ndarray, stroke: np.ndarray | None,
                 tyre: np.ndarray | None, static_weight: float,
                 inclination: float = 0.0, unsprung_mass: float = 0.0) -> GearMeasures:
    """Read the drop quantities off one gear unit's load, stroke and tyre histories.

    Energies over each element's loading stroke: E_t = ∫ F_V dδ and E_s = ∫ F_s ds with
    the strut force from :func:`strut_force` (the unsprung mass's weight and inertia
    removed when its mass is known).  d = max over time of (δ + s·cosθ), 23.725(b), reached
    at t_d; the same two integrals taken to t_d give the work absorbed by then, E_d
    (certkit E5), the energy the drop had to supply at maximum total travel.
    """
    start = touchdown_index(load, static_weight)
    i0 = 0 if start is None else max(start - 1, 0)
    t, f = time[i0:], load[i0:]
    peak_index = int(np.argmax(f))
    cos_theta = math.cos(inclination)

    max_stroke = strut_energy = min_after = settling = None
    if stroke is not None:
        s = stroke[i0:]
        max_stroke = float(np.max(s))
        axial = strut_force(t, f, None if tyre is None else tyre[i0:], unsprung_mass,
                            inclination)
        strut_energy = absorbed_energy(t, axial, s)
        after = s[int(np.argmax(s)):]
        min_after = float(np.min(after))
        settling = _settling_time(t, s, max_stroke)
    max_tyre = tyre_energy = None
    if tyre is not None:
        d = tyre[i0:]
        max_tyre = float(np.max(d))
        tyre_energy = absorbed_energy(t, f, d)
    total = at_max_travel = None
    if stroke is not None and tyre is not None:
        travel = tyre[i0:] + stroke[i0:] * cos_theta
        end = int(np.argmax(travel))
        total = float(travel[end])
        at_max_travel = work_until(t, axial, s, end) + work_until(t, f, d, end)

    lift_off = None
    contact_threshold = TOUCHDOWN_SHARE * static_weight
    after_peak = f[peak_index:]
    off = after_peak < contact_threshold
    if off.any():
        lift_off = float(np.count_nonzero(off) * np.median(np.diff(t)))
    return GearMeasures(
        touchdown_time=None if start is None else float(time[start]),
        peak_load=float(f[peak_index]), peak_load_time=float(t[peak_index]),
        max_stroke=max_stroke, max_tyre=max_tyre, max_total_travel=total,
        strut_energy=strut_energy, tyre_energy=tyre_energy,
        min_stroke_after_peak=min_after, lift_off_duration=lift_off, settling_time=settling,
        stroke_at_touchdown=None if stroke is None else _before_contact(time, stroke, i0),
        tyre_at_touchdown=None if tyre is None else _before_contact(time, tyre, i0),
        energy_at_max_travel=at_max_travel)


def _before_contact(time: np.ndarray, values: np.ndarray, index: int) -> float:
    """A channel's reading just before contact: its median over :data:`ZERO_WINDOW` before
    sample ``index`` (the sample at ``index`` itself when the record starts there)."""
    window = (time >= time[index] - ZERO_WINDOW) & (time < time[index])
    if not window.any():
        return float(values[index])
    return float(np.median(values[window]))


def _settling_time(t: np.ndarray, stroke: np.ndarray, max_stroke: float) -> float | None:
    """Time from touchdown after which the stroke stays within ±5 % of its maximum
    around its final value; None when it has not settled before the last 5 % of the record."""
    tail = max(int(len(stroke) * FINAL_SHARE), 1)
    final = float(np.mean(stroke[-tail:]))
    outside = np.flatnonzero(np.abs(stroke - final) > SETTLING_BAND * max_stroke)
    if outside.size == 0:
        return 0.0
    last = int(outside[-1])
    if last >= len(stroke) - tail:
        return None
    return float(t[last + 1] - t[0])


def drop_mass_load_factor(time: np.ndarray, acceleration: np.ndarray, reference: str,
                          touchdown_time: float) -> float:
    """n_j of 23.725(e) from the drop-mass acceleration after touchdown."""
    after = acceleration[time >= touchdown_time]
    return drop_test_load_factor(float(np.max(after)), reference)


def contact_velocity(time: np.ndarray, displacement: np.ndarray,
                     touchdown_time: float) -> float | None:
    """Drop-mass velocity at touchdown: derivative at touchdown of a parabola fitted to
    the displacement over the 50 ms before it (a free fall is a parabola, so a straight
    line would return the velocity at the window's middle, 25 ms early); None if fewer
    than 5 samples."""
    window = (time >= touchdown_time - VELOCITY_WINDOW) & (time <= touchdown_time)
    if np.count_nonzero(window) < 5:
        return None
    _, slope, _ = np.polyfit(time[window] - touchdown_time, displacement[window], 2)
    return float(slope)
