"""Where a model disagrees with a drop: residuals (measured − simulated) per channel, phase
and run, as RMS, bias, timing error and energy in frequency bands.

Every statistic is computed on the measured run's phases (:mod:`certkit.gap.phases`), so a
simulated run that is late or early shows as a timing error, not as a changed phase.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from certkit.gap.phases import Phase

#: Frequency bands of the residual: rigid-body motion of the masses on the
#: gas spring and tyre, and the band of structural, wheel-hop and platform modes.
BANDS = (("rigid-body", 0.0, 10.0), ("structural and tyre modes", 10.0, 100.0),
         ("above 100 Hz", 100.0, float("inf")))
MAX_LAG = 0.020   # s, largest timing error looked for
#: s, the largest shift :func:`shifted_fit` tries: timing errors of a recording chain (a
#: skew between a logger's channels, a force reaching a cell through a frame) of a few to
#: tens of milliseconds, well inside a first compression (about 0.1 s)
TIMING_LAG = 0.030


@dataclass(frozen=True)
class Cell:
    """The residual of one channel in one phase of one run (channel units, SI)."""

    run: str
    channel: str
    phase: str
    samples: int
    rms: float
    bias: float            # mean of measured − simulated
    lag: float             # s, > 0: the simulation is late
    scale: float           # RMS of the measured channel over the whole run (normaliser)

    @property
    def normalised(self) -> float:
        return self.rms / self.scale if self.scale > 0 else float("nan")


def timing_lag(measured: np.ndarray, simulated: np.ndarray, step: float,
               max_lag: float = MAX_LAG) -> float:
    """Shift [s] that best aligns the simulation with the measurement (positive: the
    simulation is late): the cross-correlation peak of the mean-removed signals, refined by a
    parabola through the peak and its neighbours."""
    a = np.asarray(measured, dtype=float) - np.mean(measured)
    b = np.asarray(simulated, dtype=float) - np.mean(simulated)
    lags = np.arange(-int(max_lag / step), int(max_lag / step) + 1)
    lags = lags[np.abs(lags) < a.size - 1]
    if lags.size < 3 or not np.any(a) or not np.any(b):
        return 0.0
    values = np.array([np.dot(a[max(0, -k):a.size - max(0, k)], b[max(0, k):b.size - max(0, -k)])
                       for k in lags])
    best = int(np.argmax(values))
    shift = float(lags[best])
    if 0 < best < lags.size - 1:
        left, mid, right = values[best - 1], values[best], values[best + 1]
        curvature = left - 2 * mid + right
        if curvature < 0:
            shift += float(0.5 * (left - right) / curvature)
    return float(shift * step)


def shifted_fit(before: list, correction: list, step: float,
                max_lag: float = TIMING_LAG) -> tuple[float, float]:
    """How much better a correction fits a residual when shifted in time: (the shift [s],
    positive when the correction fits best delayed; the share of the corrected residual's
    mean square that shift removes).

    ``before`` and ``correction`` are one channel's residual (simulated − measured) and the
    change a refit makes to it, one array per run, on samples ``step`` apart; the corrected
    residual is before + correction, shifted by one common whole number of samples within
    ±``max_lag`` (the ends held at their edge values).  A memoryless correction (a gain)
    that fits the residual better at another instant than at the same one does not
    explain it: what is missing changes the record's timing too."""
    def mean_square(shift: int) -> float:
        total = count = 0.0
        for r, d in zip(before, correction):
            moved = d if shift == 0 else np.concatenate(
                [np.full(shift, d[0]), d[:-shift]] if shift > 0 else
                [d[-shift:], np.full(-shift, d[-1])])
            total += float(np.sum((r + moved) ** 2))
            count += r.size
        return total / count if count else 0.0

    reach = int(max_lag / step)
    shortest = min((r.size for r in before), default=0)
    shifts = [k for k in range(-reach, reach + 1) if abs(k) < shortest]
    if not shifts:
        return 0.0, 0.0
    costs = {k: mean_square(k) for k in shifts}
    best = min(shifts, key=lambda k: (costs[k], abs(k)))
    share = (costs[0] - costs[best]) / costs[0] if costs[0] > 0 else 0.0
    return best * step, float(share)


def band_shares(residual: np.ndarray, step: float) -> dict[str, float]:
    """Share of the residual's energy (mean removed) in each of :data:`BANDS`."""
    values = np.asarray(residual, dtype=float) - np.mean(residual)
    spectrum = np.abs(np.fft.rfft(values)) ** 2
    frequency = np.fft.rfftfreq(values.size, step)
    total = float(spectrum[1:].sum())
    shares = {}
    for name, low, high in BANDS:
        inside = (frequency >= low) & (frequency < high) & (frequency > 0)
        shares[name] = float(spectrum[inside].sum()) / total if total > 0 else 0.0
    return shares


def residual_cells(run: str, time: np.ndarray, measured: dict, simulated: dict,
                   phases: list[Phase]) -> list[Cell]:
    """One :class:`Cell` per channel and phase of one run (channels on the same samples)."""
    step = float(np.median(np.diff(time)))
    cells = []
    for channel, values in measured.items():
        values = np.asarray(values, dtype=float)
        model = np.asarray(simulated[channel], dtype=float)
        scale = float(np.sqrt(np.mean(values ** 2)))
        for phase in phases:
            part = slice(phase.start, phase.stop)
            residual = values[part] - model[part]
            if residual.size == 0:
                continue
            cells.append(Cell(run, channel, phase.name, int(residual.size),
                              float(np.sqrt(np.mean(residual ** 2))), float(np.mean(residual)),
                              timing_lag(values[part], model[part], step), scale))
    return cells


def largest(cells: list[Cell]) -> Cell | None:
    """The cell with the largest normalised RMS (ties: earlier in the list)."""
    finite = [c for c in cells if np.isfinite(c.normalised)]
    return max(finite, key=lambda c: c.normalised) if finite else None


def describe(cell: Cell, unit_scale: float = 1.0, unit: str = "") -> str:
    """The largest disagreement in words."""
    timing = f", the simulation {'late' if cell.lag > 0 else 'early'} by {abs(cell.lag) * 1e3:.3g} ms" \
        if abs(cell.lag) >= 0.5e-3 else ""
    return (f"The largest disagreement is in the {cell.channel} during {cell.phase} of run "
            f"{cell.run}: RMS {cell.rms * unit_scale:.3g} {unit} ({cell.normalised:.1%} of the "
            f"channel's RMS), bias {cell.bias * unit_scale:+.3g} {unit}{timing}.").replace(" ,", ",")


# --------------------------------------------------------------------------- noise, harm, floor
def noise_level(records) -> float:
    """The white-noise standard deviation of measured records (one array, or several),
    from their second differences: for white noise of variance σ², x[i+1] − 2·x[i] + x[i−1]
    has variance 6·σ², and the median absolute deviation (× 1.4826, its ratio to σ for a
    normal distribution) ignores the few samples where the signal itself bends sharply
    (the impact), so the estimate is robust (Hampel, J. Amer. Statist. Assoc. 69(346),
    1974, on the MAD; the difference-based variance estimator: Rice, Ann. Statist. 12(4),
    1984)."""
    parts = [np.diff(np.asarray(r, dtype=float), 2) for r in
             (records if isinstance(records, (list, tuple)) else [records])]
    values = np.concatenate([p for p in parts if p.size]) if parts else np.empty(0)
    if values.size == 0:
        return 0.0
    deviation = np.median(np.abs(values - np.median(values)))
    return float(1.4826 * deviation / np.sqrt(6.0))


def harmed(before: float, after: float, noise: float) -> bool:
    """True when an error grew beyond the noise: the model's own share of the RMSE grew,
    √(after² − before²) > σ.  The one rule by which a named effect harms a channel (the
    diagnosis and the blind check both apply it)."""
    return after > before and after * after - before * before > noise * noise


def model_gap(rmse: float, noise: float) -> float:
    """The part of an RMSE the model can remove, √(max(RMSE² − σ², 0)): white noise of
    variance σ² adds σ² to the mean square of any model's error."""
    return float(np.sqrt(max(rmse * rmse - noise * noise, 0.0)))


def gap_shares(before: float, after: float, noise: float) -> tuple[float, float] | None:
    """(closed, unexplained): the shares of the model's gap before (:func:`model_gap` of
    ``before``) that the named effects close and that stays, in RMS terms; they add to 1
    (closed is negative when the error grew).  None when there is no gap beyond the noise."""
    gap = model_gap(before, noise)
    if gap <= 0.0:
        return None
    remaining = model_gap(after, noise)
    return 1.0 - remaining / gap, remaining / gap
