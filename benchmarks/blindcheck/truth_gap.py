"""The gap a case's truth leaves, measured on its noise-free records: the held-out load
error of a model against them, the floor the nominal model reaches without the case's
effects, and what the effects change physically (``benchmarks/blind_independent.py``)."""

from __future__ import annotations

import math

import numpy as np

from certkit.gap.selection import NOMINAL_STARTS
from certkit.physics.calibration import aligned_records, calibrate_gear


def held_out_load(campaign, gear_id: str, held, configure) -> float:
    records = aligned_records(campaign, gear_id, configure, list(held), effects=[])
    return math.sqrt(np.mean([np.mean((r.simulated["load"][r.after]
                                       - r.measured["load"][r.after]) ** 2)
                              for r in records.values()]))


def floor_calibration(bare, gear_id: str, diagnosis):
    """The nominal model calibrated on the training runs of ``bare`` (the case without its
    effects and without sensor effects), from the nominal values and from where the
    diagnosis's own calibration ended, whichever fits better: the floor is the best the
    nominal model reaches, as the diagnosis's calibration is (from the nominal values and
    the same further starts, and done again when a refit's bare parameters fit better)."""
    runs = list(diagnosis.training)
    first = calibrate_gear(bare, gear_id, effects=[], run_ids=runs, starts=NOMINAL_STARTS)
    other = calibrate_gear(bare, gear_id, knobs=[k.name for k in diagnosis.calibration.knobs],
                           effects=[], run_ids=runs,
                           start=list(diagnosis.calibration.fit.estimate))
    return other if other.fit.cost < first.fit.cost else first


def physical_size(clean, bare, gear_id: str, held) -> dict:
    """What the truths change physically on the held-out drops, noise-free: the peak
    load (N and share) and the maximum stroke (m)."""
    out = {}
    for run_id in held:
        with_effect, without = (c.series[run_id].gears[gear_id] for c in (clean, bare))
        peak, plain_peak = float(with_effect.load.max()), float(without.load.max())
        out[run_id] = {"peak_load_change_N": peak - plain_peak,
                       "peak_load_change_share": peak / plain_peak - 1.0,
                       "max_stroke_change_m": float(with_effect.stroke.max()
                                                    - without.stroke.max())}
    return out
