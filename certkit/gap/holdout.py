"""Which drops of a gear unit the gap diagnosis trains on and which it holds out, and what
it needs of them.

The rule is :func:`certkit.physics.drops.default_split`, the one the identification uses
too; the spec's ``model.gap.held_out`` overrides it.  The held-out drops are used for
nothing but evaluation: not for the nominal calibration, the score tests, the refits nor the
choice of an effect.  Below :mod:`certkit.gap.attribution` and :mod:`certkit.gap.diagnosis`,
which both split the same way.
"""

from __future__ import annotations

from certkit.errors import CertkitInputError
from certkit.physics.drops import by_height, default_split, recorded_drops
from certkit.spec.campaign import Campaign

NEEDS = ("The gap diagnosis needs drops of the gear unit at two drop heights or more: it "
         "calibrates the model and chooses an effect on the lower ones and holds out the "
         "highest, so that the held-out error measures extrapolation to a drop the model has "
         "not seen.")


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
    recorded = by_height(campaign, recorded_drops(campaign, gear_id))
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
