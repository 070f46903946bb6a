"""Scoring a blind check's outcomes against their sealed truths: the metrics, their 95 %
Wilson intervals (Wilson, J. Am. Stat. Assoc. 22, 1927), the curve over effect sizes and
the confusion matrix.  Used by both batteries (:mod:`blindcheck.battery`, certkit's own
physics; ``benchmarks/blind_independent.py``, the independent truth generator)."""

from __future__ import annotations

import math
import statistics

#: The targets the diagnosis is held to (at effect/noise ≥ 2): (value, "at least" | "at most").
TARGETS = {"top1": (0.85, "at least"), "false_attribution": (0.10, "at most"),
           "median_shrink": (0.50, "at least"), "harm_rate": (0.10, "at most")}
SCORED_FROM = 2.0
TIED = "cannot tell apart"
FAILED = "failed"


def wilson(count: int, cases: int, z: float = 1.959964) -> list[float] | None:
    """95 % Wilson score interval of a proportion count/cases (None without cases)."""
    if not cases:
        return None
    p, n = count / cases, cases
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return [max(0.0, centre - half), min(1.0, centre + half)]


def metric(name: str, value, count, cases, targets: dict | None = None) -> dict:
    """One metric with its target (from ``targets``, default :data:`TARGETS`), whether it
    is met, and the Wilson interval of its proportion."""
    target, direction = (TARGETS if targets is None else targets).get(name, (None, None))
    met = None
    if target is not None and value is not None:
        met = bool(value >= target) if direction == "at least" else bool(value <= target)
    return {"value": value, "count": count, "cases": cases, "target": target,
            "direction": direction, "met": met,
            "interval": wilson(count, cases) if count is not None else None}


def named_label(outcome: dict) -> str:
    """What a case's answer counts as: its first named effect, a tie, a failure or none."""
    if outcome.get("error"):
        return FAILED
    if outcome["named"]:
        return outcome["named"][0]
    return TIED if "cannot be told apart" in outcome["statement"] else "none"


def score(outcomes: list[dict], effects: tuple) -> dict:
    """The blind check's metrics from case outcomes (see :func:`blindcheck.battery.run_case`),
    ``effects`` the library's effect names in the order of the confusion matrix.

    - top-1 accuracy: single-effect cases at effect/noise ≥ :data:`SCORED_FROM` whose first
      named effect is the truth (an abstention, a tie or a failure is wrong);
    - exact: the same cases whose answer is the truth and nothing else;
    - false attribution: no-effect cases that do not end in a clean abstention (an effect
      named, a tie declared, or a failure);
    - set precision / recall: two-effect cases, pooled over the cases; recall or tie: a
      truth effect named, or stated undecided beside the named one;
    - median held-out shrink: 1 − RMSE_after/RMSE_before of the held-out load channel,
      against the noisy measurement, over the single-effect cases at ratio ≥
      :data:`SCORED_FROM` (an abstention shrinks 0); the two-effect cases separately;
    - median gap closed: the same shrink of the load RMSE against the noise-free truth
      (what a model can remove; the noise cannot be);
    - harm rate: of the cases in which an effect was named, those in which it made the
      held-out load error worse beyond its noise (:func:`certkit.gap.residuals.harmed`);
      and on any held-out channel;
    - the curve: top-1 and median shrink of the single-effect cases at every ratio;
    - the confusion matrix of truth (single effect or none) against first named effect.

    A case whose effect cannot be sized as asked on this campaign (``skipped``) is not
    scored; it is listed.  Proportions carry 95 % Wilson intervals, which treat the cases
    as independent (each has its own noise, offsets and scatter).
    """
    skipped = [o["id"] for o in outcomes if o.get("skipped")]
    outcomes = [o for o in outcomes if not o.get("skipped")]
    single = [o for o in outcomes if len(o["truth"]) == 1]
    scored = [o for o in single if o["ratio"] >= SCORED_FROM]
    null = [o for o in outcomes if not o["truth"]]
    pairs = [o for o in outcomes if len(o["truth"]) == 2]
    named = [o for o in outcomes if o["named"]]

    def rate(hits, cases):
        return hits / len(cases) if cases else None

    def median(values):
        return statistics.median(values) if values else None

    correct = sum(o["named"][:1] == o["truth"] for o in scored)
    exact = sum(o["named"] == o["truth"] for o in scored)
    false = sum(named_label(o) != "none" for o in null)
    right = sum(len(set(o["named"]) & set(o["truth"])) for o in pairs)
    # a truth effect stated undecided beside the named one (certkit.gap.selection: the
    # records cannot tell whether it is present too): not found, but not silently lost
    tied = sum(len((set(o.get("undecided", [])) - set(o["named"])) & set(o["truth"]))
               for o in pairs)
    said = sum(len(o["named"]) for o in pairs)
    wanted = sum(len(o["truth"]) for o in pairs)
    harm_count = sum(bool(o.get("harmed")) for o in named)
    harmed_any = sum(bool(o.get("harmed_any")) for o in named)
    failed = [o["id"] for o in outcomes if o.get("error")]
    shrinks = [o["shrink"] for o in scored]
    closed = [o["closed"] if o.get("closed") is not None else 0.0 for o in scored]
    metrics = {
        "top1": metric("top1", rate(correct, scored), correct, len(scored)),
        "exact": metric("exact", rate(exact, scored), exact, len(scored)),
        "false_attribution": metric("false_attribution", rate(false, null), false, len(null)),
        "set_precision": metric("set_precision", right / said if said else None, right, said),
        "set_recall": metric("set_recall", right / wanted if wanted else None, right, wanted),
        "set_recall_or_tie": metric("set_recall_or_tie", (right + tied) / wanted
                                    if wanted else None, right + tied, wanted),
        "median_shrink": metric("median_shrink", median(shrinks), None, len(shrinks)),
        "median_gap_closed": metric("median_gap_closed", median(closed), None, len(closed)),
        "median_shrink_pairs": metric("median_shrink_pairs",
                                       median([o["shrink"] for o in pairs]), None, len(pairs)),
        "harm_rate": metric("harm_rate", rate(harm_count, named), harm_count, len(named)),
        "harm_any_channel": metric("harm_any_channel", rate(harmed_any, named), harmed_any,
                                    len(named)),
    }
    curve = []
    for ratio in sorted({o["ratio"] for o in single}):
        at = [o for o in single if o["ratio"] == ratio]
        curve.append({"ratio": ratio, "cases": len(at),
                      "top1": sum(o["named"][:1] == o["truth"] for o in at) / len(at),
                      "median_shrink": statistics.median(o["shrink"] for o in at)})
    truths = [e for e in effects if any(o["truth"] == [e] for o in single)] + ["none"]
    columns = list(effects) + ["none", TIED, FAILED]
    counts = [[0] * len(columns) for _ in truths]
    for o in single + null:
        row = truths.index(o["truth"][0] if o["truth"] else "none")
        counts[row][columns.index(named_label(o))] += 1
    return {"metrics": metrics, "curve": curve, "failed": failed, "skipped": skipped,
            "confusion": {"truths": truths, "named": columns, "counts": counts}}
