"""Which drops of a gear unit the model stages work on, and which they hold out: the one
home of these rules for calibration, identification and the gap diagnosis.

A drop of a gear unit is a run that records the unit with time histories and is not a
small-signal run; each stage then cuts it at its touchdown.  The certification case is
extrapolation, so by default every drop at the highest drop height is held out, and with
:data:`MIDDLE_FROM` heights or more the middle height's drops too (an interpolation check).
Held-out drops are used for nothing but evaluation.  A spec may declare its own held-out
runs per stage (``model.identification.held_out``, ``model.gap.held_out``).
"""

from __future__ import annotations

from certkit.spec.campaign import Campaign

#: Distinct drop heights from which a middle height is held out as well.
MIDDLE_FROM = 4


def drop_heights(campaign: Campaign) -> dict[str, float]:
    """Run id -> drop height [m]."""
    return {run.id: run.drop_height.si for run in campaign.spec.runs}


def recorded_drops(campaign: Campaign, gear_id: str) -> list[str]:
    """Run ids of the drops that record ``gear_id`` with time histories (small-signal runs
    excluded), in the spec's order."""
    return [run.id for run in campaign.spec.runs
            if campaign.series.get(run.id) is not None
            and gear_id in campaign.series[run.id].gears and run.test_type != "small-signal"]


def by_height(campaign: Campaign, run_ids) -> list[str]:
    """``run_ids`` lowest drop height first (the spec's order within a height)."""
    heights = drop_heights(campaign)
    return sorted(run_ids, key=lambda run: heights[run])


def default_split(campaign: Campaign, gear_id: str) -> tuple[list[str], list[str]]:
    """(training, held-out) run ids of ``gear_id``, lowest height first: every drop at the
    highest drop height held out, and those at the middle height when there are
    :data:`MIDDLE_FROM` heights or more.  No checks: with one height everything is held out."""
    heights = drop_heights(campaign)
    recorded = by_height(campaign, recorded_drops(campaign, gear_id))
    levels = sorted({heights[r] for r in recorded})
    chosen = set(levels[-1:])
    if len(levels) >= MIDDLE_FROM:
        chosen.add(levels[(len(levels) - 1) // 2])
    held = [r for r in recorded if heights[r] in chosen]
    return [r for r in recorded if r not in held], held
