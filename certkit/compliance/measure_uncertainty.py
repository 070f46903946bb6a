"""The standard uncertainty of each drop quantity read off a gear unit's histories, from the
uncertainties of the instrument channels that recorded them (issue 28 groundwork, not yet
wired into the report).

A channel's calibration leaves an error of its gain and of its zero: the recorded value is
r = (1 + ε)·q + o for the quantity q, with the gain error ε (a share) and the offset o (SI)
each an input quantity with estimate 0 and the certificate's uncertainty
(:class:`certkit.compliance.uncertainty.Input`).  Every measure of
:func:`certkit.compliance.measures.measure_gear` is then a function of those inputs through
the corrected channels q = (r − o)/(1 + ε), and the GUM law of propagation (JCGM 100:2008
§5.1.2) gives its standard uncertainty, with the sensitivity coefficients taken by central
differences through ``measure_gear`` itself on the recorded histories.  One input that
feeds several measures (the load gain into the peak load and the strut energy) is the same
input in each, so the measures' budgets can be combined with their correlation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from certkit.compliance.measures import GearMeasures, measure_gear
from certkit.compliance.uncertainty import GumResult, Input

CHANNELS = ("load", "stroke", "tyre")
#: The measures of GearMeasures given an uncertainty (the others are times and counts).
MEASURES = ("peak_load", "max_stroke", "max_tyre", "max_total_travel", "strut_energy",
            "tyre_energy", "energy_at_max_travel")


@dataclass(frozen=True)
class ChannelUncertainty:
    """A channel's gain error ε (a share, estimate 0) and zero offset o (SI, estimate 0),
    either of them None when not stated."""

    channel: str
    gain: Input | None = None
    offset: Input | None = None

    def __post_init__(self):
        if self.channel not in CHANNELS:
            raise ValueError(f"channel {self.channel!r} is not one of {', '.join(CHANNELS)}")


def _inputs(channels) -> list[tuple[str, str, Input]]:
    """(channel, "gain" | "offset", input) for every stated part, in a fixed order."""
    out = []
    for item in channels:
        for part in ("gain", "offset"):
            value = getattr(item, part)
            if value is not None:
                out.append((item.channel, part, value))
    return out


def measure_uncertainties(time: np.ndarray, load: np.ndarray, stroke: np.ndarray | None,
                          tyre: np.ndarray | None, static_weight: float,
                          channels: list[ChannelUncertainty], inclination: float = 0.0,
                          unsprung_mass: float = 0.0, relative_step: float = 1e-3
                          ) -> dict[str, GumResult]:
    """Measure name -> its GUM result (value, u_c, sensitivities, contributions, shares in
    the order of the stated channel parts) for every measure the histories give.

    The central differences step each input by ``relative_step`` times its standard
    uncertainty: small against the uncertainty, large enough that a touchdown or a peak
    sample that moves by a sample does not dominate (the measures are piecewise smooth in
    the channels' gains and offsets)."""
    parts = _inputs(channels)
    recorded = {"load": load, "stroke": stroke, "tyre": tyre}

    def measured(x: np.ndarray) -> GearMeasures:
        corrected = dict(recorded)
        for (channel, part, _), value in zip(parts, x):
            if corrected[channel] is None:
                continue
            if part == "gain":
                corrected[channel] = corrected[channel] / (1.0 + value)
            else:
                corrected[channel] = corrected[channel] - value
        return measure_gear(time, corrected["load"], corrected["stroke"], corrected["tyre"],
                            static_weight, inclination, unsprung_mass)

    x0 = np.array([item.value for _, _, item in parts], dtype=float)
    u = np.array([item.standard for _, _, item in parts], dtype=float)
    centre = measured(x0)
    names = [m for m in MEASURES if getattr(centre, m) is not None]
    slopes = {m: np.zeros(len(parts)) for m in names}
    for index in range(len(parts)):
        if u[index] == 0:
            continue
        step = relative_step * u[index]
        up, down = x0.copy(), x0.copy()
        up[index] += step
        down[index] -= step
        high, low = measured(up), measured(down)
        for m in names:
            slopes[m][index] = (getattr(high, m) - getattr(low, m)) / (2.0 * step)
    out = {}
    for m in names:
        contributions = slopes[m] * u
        squares = contributions ** 2
        total = float(squares.sum())
        out[m] = GumResult(float(getattr(centre, m)), float(np.sqrt(total)),
                           tuple(map(float, slopes[m])), tuple(map(float, contributions)),
                           tuple(float(s / total) if total > 0 else 0.0 for s in squares))
    return out


def labels(channels: list[ChannelUncertainty]) -> list[str]:
    """Each stated input's name in a budget, in the order of the results' tuples."""
    return [f"{channel} {part} ({item.name})" for channel, part, item in _inputs(channels)]

