"""The sim-to-real gap of a gear unit's drop model: where it lies (issue 5, steps 1-2).

1. The nominal model (no optional effects) is calibrated on the training runs; the
   held-out runs (default: the highest drop, and a middle one when there are four or
   more) are used for nothing else.
2. The residual (measured − calibrated nominal) of every channel is cut by the measured
   run's phases and summarised per channel × phase × run (:mod:`certkit.residuals`):
   RMS, bias, timing error and energy in frequency bands; the largest disagreement is
   named in words.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .calibration import GearCalibration, aligned_records, calibrate_gear
from .campaign import Campaign
from .phases import segment
from .residuals import Cell, band_shares, describe, largest, residual_cells

CHANNELS = ("load", "stroke", "tyre")


@dataclass
class GapMap:
    gear_id: str
    training: tuple[str, ...]
    held_out: tuple[str, ...]
    calibration: GearCalibration
    cells: list            # Cell, every run (training and held out)
    bands: dict            # (run, channel) -> {band: share of the residual's energy}
    largest: Cell | None
    summary: str


def default_split(campaign: Campaign, gear_id: str) -> tuple[list[str], list[str]]:
    """(training, held-out) run ids of the recorded drops of ``gear_id``: the highest drop
    held out (extrapolation, the certification case), and a middle one when there are
    four or more."""
    heights = {r.id: r.drop_height.si for r in campaign.spec.runs}
    recorded = sorted((r.id for r in campaign.spec.runs
                       if campaign.series.get(r.id) is not None
                       and gear_id in campaign.series[r.id].gears
                       and r.test_type != "small-signal"), key=lambda run: heights[run])
    held = recorded[-1:]
    if len(recorded) >= 4:
        held.append(recorded[(len(recorded) - 1) // 2])
    return [r for r in recorded if r not in held], held


def residual_map(campaign: Campaign, gear_id: str,
                 split: tuple[list[str], list[str]] | None = None) -> GapMap:
    """Steps 1-2 for one gear unit."""
    training, held = split or default_split(campaign, gear_id)
    calibration = calibrate_gear(campaign, gear_id, effects=[], run_ids=list(training))
    runs = list(training) + list(held)
    records = aligned_records(campaign, gear_id, calibration.apply, runs, effects=[])
    weight = campaign.gear_units[gear_id].static_weight.si
    cells, bands = [], {}
    for run_id in runs:
        record = records[run_id]
        stroke = record.measured.get("stroke", np.zeros(record.time.size))
        phases = segment(record.time, record.measured["load"], stroke, weight)
        cells += residual_cells(run_id, record.time, record.measured, record.simulated, phases)
        step = float(np.median(np.diff(record.time)))
        for channel, measured in record.measured.items():
            residual = measured[record.after] - record.simulated[channel][record.after]
            bands[(run_id, channel)] = band_shares(residual, step)
    worst = largest([c for c in cells if c.run in training])
    units = {"load": (1.0, "N"), "stroke": (1e3, "mm"), "tyre": (1e3, "mm")}
    summary = describe(worst, *units[worst.channel]) if worst else "No residual to map."
    return GapMap(gear_id, tuple(training), tuple(held), calibration, cells, bands, worst,
                  summary)
