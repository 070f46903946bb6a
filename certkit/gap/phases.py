"""Physical phases of a drop, found by the same code on measured and simulated runs.

Events: contact t0 (the touchdown detector of :mod:`certkit.compliance.measures`),
strut breakout t_bo (stroke first above its pre-contact level by ``BREAKOUT_TRAVEL``), peak
load t_pk, maximum stroke t_smax and the end of the rebound t_ext (the first stroke minimum
after t_smax, i.e. the strut stops extending).  Phases between them::

    free fall            [start, t0)
    tyre-only contact    [t0, t_bo)
    strut breakout       [t_bo, t_bo + BREAKOUT_WINDOW), cut at t_pk
    compression          [end of breakout, t_pk]   (to peak load)
    rebound              (t_pk, t_ext]   (load falling from its peak: the strut reaches
                                          its maximum stroke and extends; t_ext is looked
                                          for once the stroke has come down REBOUND_DROP
                                          of its travel)
    settling             (t_ext, end]

A phase whose events are missing (a record starting loaded, a strut that never breaks
out) is left out rather than guessed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from certkit.compliance.measures import touchdown_index

PHASES = ("free fall", "tyre-only contact", "strut breakout", "compression", "rebound",
          "settling")
BREAKOUT_TRAVEL = 0.5e-3    # m: above stroke-transducer noise, within the first millimetre
BREAKOUT_WINDOW = 0.010     # s, the breakout transient examined on its own
SMOOTHING = 0.005           # s, moving average used to find the stroke minimum
#: The end of the extension is looked for only once the stroke has come down this share of
#: its travel from its maximum: a strut held at the top of its stroke by its seals, read
#: through a noisy sensor, shows local minima on that plateau that end nothing.
REBOUND_DROP = 0.10


@dataclass(frozen=True)
class Phase:
    name: str
    start: int      # first sample
    stop: int       # one past the last sample


def _first_minimum(signal: np.ndarray, start: int, width: int) -> int | None:
    """First local minimum of a moving average of ``signal`` after ``start``."""
    if width > 1:
        kernel = np.ones(width) / width
        smooth = np.convolve(signal, kernel, mode="same")
    else:
        smooth = signal
    for index in range(max(start, 1), smooth.size - 1):
        if smooth[index] <= smooth[index - 1] and smooth[index] < smooth[index + 1]:
            return index
    return None


def segment(time: np.ndarray, load: np.ndarray, stroke: np.ndarray,
            static_weight: float) -> list[Phase]:
    """The phases of one gear unit's drop, as sample ranges of ``time``."""
    time, load, stroke = (np.asarray(a, dtype=float) for a in (time, load, stroke))
    step = float(np.median(np.diff(time)))
    contact = touchdown_index(load, static_weight)
    phases: list[Phase] = []
    if contact is None:
        return phases
    phases.append(Phase("free fall", 0, contact))
    baseline = float(np.median(stroke[:contact])) if contact >= 5 else float(stroke[0])
    moved = np.flatnonzero(stroke[contact:] - baseline > BREAKOUT_TRAVEL)
    peak = contact + int(np.argmax(load[contact:]))
    if moved.size == 0:
        phases.append(Phase("tyre-only contact", contact, load.size))
        return phases
    breakout = contact + int(moved[0])
    phases.append(Phase("tyre-only contact", contact, breakout))
    breakout_end = min(breakout + max(int(round(BREAKOUT_WINDOW / step)), 1), peak + 1)
    if breakout_end > breakout:
        phases.append(Phase("strut breakout", breakout, breakout_end))
    if peak + 1 > breakout_end:
        phases.append(Phase("compression", breakout_end, peak + 1))
    top = peak + int(np.argmax(stroke[peak:]))
    fallen = np.flatnonzero(stroke[top:] < stroke[top] - REBOUND_DROP * (stroke[top] - baseline))
    end = None if fallen.size == 0 else _first_minimum(
        stroke, top + int(fallen[0]), max(int(round(SMOOTHING / step)), 1))
    if end is None:
        phases.append(Phase("rebound", peak + 1, load.size))
        return phases
    phases.append(Phase("rebound", peak + 1, end + 1))
    if end + 1 < load.size:
        phases.append(Phase("settling", end + 1, load.size))
    return phases
