"""The gap diagnosis's decisions and answer in words.

:mod:`certkit.gap.selection` decides (its rules, each applied once) and records every
decision as a :class:`~certkit.gap.attribution.Decision`: the rule that decided and the
figures it compared, thresholds included.  This module only puts those records into
sentences, for the report, the CLI and results.json; it decides nothing and reads no
threshold of its own, so a sentence can never state another rule than the one applied.
"""

from __future__ import annotations

from certkit.display import percent

#: Every rule a Decision can name, with the figures it carries (see :func:`decision_words`).
RULES = {
    # candidates at one step (scored, then some refitted)
    "refitted": "the best form of one of the leading relevant effects",
    "other form refitted": "relevant; another form of the same effect was refitted",
    "not leading": "relevant, but not of the leading effects (leading)",
    "points the other way": "score of the wrong sign, profile gains too little (gain)",
    "not relevant": "explains too little and its profile gains too little "
                    "(relevant, leading, gain)",
    "cannot be added": "the form cannot be added to this model (why)",
    "none refitted": "no candidate qualified for a refit (relevant, gain)",
    # refits at one step
    "named": "the admissible refit with the lowest training cost (cut)",
    "gain": "cuts the training cost by too little (cut, gain)",
    "harm": "makes a training channel worse beyond its noise (channels, cut, alone: the "
            "only rule it fails)",
    "detectable": "removes too few noise variances (removed, detectable)",
    "timing": "a memoryless correction that fits better shifted in time "
              "(channel, shift_s, share, timing_share)",
    "outranked": "admissible, with a higher training cost than the named refit "
                 "(cost, named, named_cost)",
    "tie": "within the tie ratio of another admissible refit (other, tie_cost)",
    "tie broken": "a near-tie the missing force decided (named, other, marked, unmarked, "
                  "share, tie_cost)",
    "after a tie": "admissible, but the step ended in a tie (tie)",
    # the nominal model at the first step
    "calibrated again": "the bare parameters this refit reached, without its effect, fit "
                        "better than the calibration: calibrated again from them "
                        "(cost_before, start_cost, cost_after, recalibrate, start, "
                        "estimate_before)",
    "not settled": "the bare parameters of a refit (from) still fit better than the "
                   "calibration after the restarts (done, restarts): no effect named at "
                   "the step (cost_before, start_cost, recalibrate)",
}


def form_words(candidate) -> str:
    """An effect with its form ("seal friction (Stribeck form)")."""
    return f"{candidate.name} ({candidate.form} form)" if candidate.form else candidate.name


def decision_words(decision) -> str:
    """The sentence for one recorded decision (its rule, with its figures)."""
    f = decision.figures
    rule = decision.rule
    if rule == "refitted":
        return "refitted"
    if rule == "other form refitted":
        return "relevant; another form of this effect profiled better and was refitted"
    if rule == "not leading":
        return f"relevant, not among the {f['leading']} effects with the best profiles"
    if rule == "points the other way":
        return ("its score points the other way and its profile cuts the training cost by "
                f"less than {percent(f['gain'], 0)}: not relevant")
    if rule == "not relevant":
        return (f"not a form with {f['relevant']:g} σ or more of the {f['leading']} effects "
                f"with the best scores, and its profile cuts the training cost by less than "
                f"{percent(f['gain'], 0)}: not relevant")
    if rule == "cannot be added":
        return f"not scored: {f['why']}"
    if rule == "none refitted":
        return (f"No candidate would remove {f['relevant']:g} σ or more, nor cut the training "
                f"cost by {percent(f['gain'], 0)} in its profile: none was refitted.")
    if rule == "named":
        return f"cuts the training cost by {percent(f['cut'], 0)}, the most of the admissible " \
               "refits: named"
    if rule == "gain":
        # one decimal: a cut of 9.6 % must not read "10 %, less than 10 %"
        return (f"cuts the training cost by {percent(f['cut'], 1)}, less than "
                f"{percent(f['gain'], 0)}: not named")
    if rule == "harm":
        words = ("makes the training " + ", ".join(f["channels"])
                 + " error worse beyond its noise")
        if f["alone"]:
            words += (f", though it cuts the training cost by {percent(f['cut'], 0)} and "
                      f"passes every other rule")
        return words + ": not named"
    if rule == "detectable":
        return (f"removes {f['removed']:.2g} noise variances from the training records, fewer "
                f"than {f['detectable']:g}: not told apart from the nominal model's own floor, "
                f"not named")
    if rule == "timing":
        channel, shift = f["channel"], f["shift_s"]
        return (f"its correction of the recorded {channel} (with the channel skew its refit "
                f"fits, if the form has one) fits the residual better shifted "
                f"{abs(shift) * 1e3:.3g} ms {'later' if shift > 0 else 'earlier'} (the shift "
                f"removes {percent(f['share'], 0)} of the {channel}'s remaining mean square; "
                f"{percent(f['timing_share'], 0)} or more is a timing error the form cannot "
                f"make): the {channel} record's error is not this one: not named")
    if rule == "outranked":
        return (f"admissible, but its training cost {f['cost']:.4g} is above the "
                f"{f['named_cost']:.4g} of {f['named']}, which was named: not named")
    if rule == "tie":
        return (f"within {percent(f['tie_cost'] - 1, 0)} of the training cost of "
                f"{f['other']}: a tie, not named")
    if rule == "tie broken":
        within = f"within {percent(f['tie_cost'] - 1, 0)} of the training cost of {f['other']}"
        mark = (f"the missing force shows the mark of {f['marked']} "
                f"({percent(f['share'], 0)} of its variance) and not of {f['unmarked']}")
        return f"{within}; {mark}: " + ("named" if f["named"] else "not named")
    if rule == "after a tie":
        return (f"admissible, but the step ended in a tie of {f['tie'][0]} and {f['tie'][1]}: "
                f"not named")
    if rule == "calibrated again":
        return (f"the bare parameters this refit reached fit the training runs, without its "
                f"effect, at {f['start_cost']:.4g} against the calibration's "
                f"{f['cost_before']:.4g} (more than {percent(f['recalibrate'], 0)} better): "
                f"the calibration had not reached the best fit of the bare parameters and "
                f"was done again from them (training cost {f['cost_after']:.4g})")
    if rule == "not settled":
        return (f"the bare parameters the refit with {f['from']} reached still fit the "
                f"training runs, without its effect, at {f['start_cost']:.4g} against the "
                f"calibration's {f['cost_before']:.4g} after {f['done']} calibrations again "
                f"(at most {f['restarts']}): the calibration has not settled, and no effect "
                f"is named at this step")
    raise ValueError(f"no words for the rule {rule!r}")   # a rule added without its sentence


def tie_words(chosen, a: str, b: str, costs: tuple, cosine: float, tie_cost: float) -> str:
    """The answer when a step ended in a tie of the effects ``a`` and ``b``."""
    tie = (f"{a} and {b} cannot be told apart with these channels (training costs "
           f"{costs[0]:.4g} and {costs[1]:.4g}, within {percent(tie_cost - 1, 0)}; signature "
           f"cosine {cosine:.2f}).")
    if not chosen:
        return tie
    return (f"The gap is explained by {' and '.join(map(form_words, chosen))}; as a second "
            f"effect, {tie}")


def undecided_words(chosen, undecided) -> str:
    """The sentence after the answer for effects beside ``chosen`` whose refit failed the
    harm rule only: ((Candidate, Decision), ...)."""
    named = " and ".join(c.name for c in chosen)
    parts = []
    for candidate, decision in undecided:
        channels = decision.figures["channels"]
        errors = (f"{channels[0]} error worse beyond its noise" if len(channels) == 1 else
                  f"{' and '.join(channels)} errors worse beyond their noise")
        parts.append(f"{form_words(candidate)} would cut the training cost by a further "
                     f"{percent(decision.figures['cut'], 0)} but makes the training {errors}")
    subject, verb = ("it", "is") if len(parts) == 1 else ("they", "are")
    return (f" Beside {named}, " + "; ".join(parts) + f": {subject} {verb} not named, and these "
            f"records cannot tell whether {subject} {verb} present too.")


def recalibrated_words(decisions) -> str:
    """The sentences before the answer when the nominal model was calibrated again (rule
    "calibrated again", in order) or found not settled (rule "not settled", last)."""
    words = []
    for index, decision in enumerate(decisions):
        f = decision.figures
        if decision.rule == "not settled":
            words.append(f"The bare parameters the refit with {f['from']} reached still fit "
                         f"the training runs, without it, at {f['start_cost']:.4g} against "
                         f"the calibration's {f['cost_before']:.4g}: the nominal model's "
                         f"calibration has not settled, and no effect is named, since each "
                         f"would be credited with some of what its parameters can do.")
        elif index == 0:
            words.append(f"The nominal model's calibration on the training runs did not "
                         f"reach the best fit of its parameters (training cost "
                         f"{f['cost_before']:.4g}): the parameters the refit with "
                         f"{decision.name} reached fit them, without it, at "
                         f"{f['start_cost']:.4g}, so it was calibrated again from there "
                         f"(training cost {f['cost_after']:.4g}).")
        else:
            words.append(f"Nor did that calibration: from the parameters the refit with "
                         f"{decision.name} reached ({f['start_cost']:.4g} without it), it "
                         f"was calibrated again (training cost {f['cost_after']:.4g}).")
    if decisions and decisions[-1].rule == "calibrated again":
        words.append("Every effect is judged against the last calibration.")
    return "".join(w + " " for w in words)


def crosstalk_words(gain: float, delay: float) -> str:
    """The sentence after the answer when a named load-cell gain ε with its skew records the
    load as a share ε of it arriving ``delay`` [s] earlier would (crosstalk through the
    platform's frame; ε < 0: a share taken away), to within the load's noise over the load
    pulse (:mod:`certkit.gap.selection` decides)."""
    share = percent(abs(gain), 1)
    crosstalk = (f"{share} of the load arriving {delay * 1e3:.3g} ms earlier" if gain > 0 else
                 f"the load less {share} of itself from {delay * 1e3:.3g} ms earlier")
    return (f" The load record is also, to within its noise over the load pulse, what "
            f"{crosstalk} would make (crosstalk through the platform's frame): check the "
            f"load chain's calibration and the frame before taking either as the cause.")


def answer_words(chosen, settled: bool = True) -> str:
    """The answer when the diagnosis named ``chosen`` (Candidates) or abstained;
    ``settled`` False: it named nothing because the nominal model's calibration has not
    settled (rule "not settled"), which decides nothing about the library."""
    if not chosen and not settled:
        return ("Whether an effect of the library explains the gap is not decided on this "
                "calibration.")
    if not chosen:
        return "No effect in the library explains the gap."
    return "The gap is explained by " + " and ".join(map(form_words, chosen)) + "."


def held_out_words(shares: dict, caveats: tuple, count: int, channel: str) -> str:
    """The floor on ``channel`` and the caveats, as the statement's last sentences."""
    subject, verb = ("the named effects", "") if count > 1 else ("the named effect", "s")
    words = ""
    if channel in shares:
        share = shares[channel]
        words += (f" Of the held-out {channel} error beyond its noise, {subject} "
                  f"close{verb} {percent(share[0], 0)} and {percent(share[1], 0)} stays "
                  f"unexplained." if share is not None else
                  f" The held-out {channel} error lay within its noise before any "
                  f"effect was added.")
    if caveats:
        words += (f" Caveat: {subject} make{verb} the held-out " + " and ".join(caveats)
                  + " error worse beyond its noise.")
    return words
