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
