"""Which drops of a gear unit the gap diagnosis trains on and which it holds out.

The held-out drops are used for nothing but evaluation: not for the nominal calibration,
the score tests, the refits nor the choice of an effect.  The certification case is
extrapolation, so by default every drop at the highest drop height is held out, and with
four heights or more the middle height's drops too (an interpolation check).  The spec's
``model.gap.held_out`` overrides the default.

Below :mod:`certkit.gap.attribution` and :mod:`certkit.gap.diagnosis`, which both split the same way.
"""

from __future__ import annotations

from certkit.spec.campaign import Campaign
from certkit.errors import CertkitInputError

#: Distinct drop heights from which a middle height is held out as well.
MIDDLE_FROM = 4

NEEDS = ("The gap diagnosis needs drops of the gear unit at two drop heights or more: it "
         "calibrates the model and chooses an effect on the lower ones and holds out the "
         "highest, so that the held-out error measures extrapolation to a drop the model has "
         "not seen.")


def recorded_drops(campaign: Campaign, gear_id: str) -> list[str]:
    """Run ids of the drops that record ``gear_id`` with time histories (small-signal runs
    excluded), lowest drop height first (spec order within a height)."""
    heights = {r.id: r.drop_height.si for r in campaign.spec.runs}
    recorded = [r.id for r in campaign.spec.runs
                if campaign.series.get(r.id) is not None
                and gear_id in campaign.series[r.id].gears and r.test_type != "small-signal"]
    return sorted(recorded, key=lambda run: heights[run])


def default_split(campaign: Campaign, gear_id: str) -> tuple[list[str], list[str]]:
    """(training, held-out) run ids of ``gear_id``: every drop at the highest drop height held
    out, and those at the middle height when there are :data:`MIDDLE_FROM` heights or more.

    No checks: with one height everything is held out (see :func:`split_for`)."""
    heights = {r.id: r.drop_height.si for r in campaign.spec.runs}
    recorded = recorded_drops(campaign, gear_id)
    levels = sorted({heights[r] for r in recorded})
    chosen = set(levels[-1:])
    if len(levels) >= MIDDLE_FROM:
        chosen.add(levels[(len(levels) - 1) // 2])
    held = [r for r in recorded if heights[r] in chosen]
    return [r for r in recorded if r not in held], held


def split_for(campaign: Campaign, gear_id: str) -> tuple[list[str], list[str], bool]:
    """(training, held-out, declared) for ``gear_id``: the spec's ``model.gap.held_out``
    when declared (``declared`` True), else :func:`default_split`.

    Raises
    ------
    CertkitInputError
        When the gear unit's drops do not allow a diagnosis: no drop with time histories,
        drops at one drop height only, or no training or no held-out drop left; the message
        says what the diagnosis needs.
    """
    spec = campaign.spec
    display = campaign.spec_path.name
    heights = {r.id: r.drop_height for r in spec.runs}
    recorded = recorded_drops(campaign, gear_id)
    if not recorded:
        raise CertkitInputError.single(
            display, None, "runs", f"no run records gear unit {gear_id} with time histories, "
                                   f"so there is no gap to diagnose. {NEEDS}")
    levels = sorted({heights[r].si for r in recorded})
    if len(levels) < 2:
        listed = ", ".join(f"{r} ({heights[r].text})" for r in recorded)
        raise CertkitInputError.single(
            display, None, "runs",
            f"gear unit {gear_id} has drops at one drop height only ({listed}). {NEEDS}")
    declared = list(spec.model.gap.held_out)
    if not declared:
        training, held = default_split(campaign, gear_id)
        return training, held, False
    location = ("model", "gap", "held_out")
    line = campaign.line(*location)
    held = [r for r in recorded if r in declared]
    training = [r for r in recorded if r not in declared]
    if not held:
        raise CertkitInputError.single(
            display, line, "model.gap.held_out",
            f"none of the held-out runs ({', '.join(declared)}) records gear unit {gear_id} "
            f"with time histories (its drops: {', '.join(recorded)}), so no held-out run is "
            f"left to measure the diagnosis on. {NEEDS}")
    if not training:
        raise CertkitInputError.single(
            display, line, "model.gap.held_out",
            f"every drop of gear unit {gear_id} ({', '.join(recorded)}) is held out, so no "
            f"training run is left to calibrate on. {NEEDS}")
    return training, held, True
