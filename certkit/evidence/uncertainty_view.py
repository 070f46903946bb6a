"""The report's view of the measurement uncertainties: each verdict's margin ± U, its
conformance probability and its outcome under the decision rule; the rule and its risk
stated once; the inputs; each measured verdict's full budget; the figure of the verdicts
nearest their limits.  Words and numbers only: every figure comes from
:mod:`certkit.compliance.verdict_uncertainty`.
"""

from __future__ import annotations

import math
from statistics import NormalDist

from markupsafe import Markup

from certkit.compliance.margin_draws import TRAVEL_BAND
from certkit.compliance.uncertainty_inputs import CHANNEL_WORDS, INPUT_WORDS, PROBE, Source
from certkit.compliance.verdict_uncertainty import (ENGINE_AGREEMENT, ENGINE_CHECKS, SEED,
                                                    Budgets)
from certkit.display import number, pretty, to_display, unit_of, with_unit

#: Significant digits of an expanded uncertainty (JCGM 100:2008 §7.2.6: "at most two").
U_DIGITS = 2
#: How many verdicts the figure shows: the ones with the smallest margin in units of U.
FIGURE_VERDICTS = 3
RULE_NAMES = {"simple": "simple acceptance", "guarded": "guarded acceptance",
              "probability": "a required conformance probability"}


def probability(p: float | None) -> str:
    """A conformance probability as a reader takes it in: four decimals, and "> 0.9999" or
    "< 0.0001" beyond them (never a rounded 1 or 0)."""
    if p is None:
        return "—"
    if p >= 0.99995:
        return "> 0.9999"
    if p <= 0.00005:
        return "< 0.0001"
    return f"{p:.4f}"


def _spread(source: Source, u: float, units) -> str:
    """An input's standard uncertainty as a person reads it: a share in %, a quantity in the
    campaign's display unit (SI where the kind has none)."""
    if source.relative:
        return f"{number(100.0 * u, U_DIGITS)} %"
    if unit_of(source.kind, units) is None:
        return f"{number(u, U_DIGITS)} {source.unit.replace('^2', '²')}"
    return with_unit(u, source.kind, units, U_DIGITS)


def _expanded(found, kind: str, units) -> str:
    return with_unit(found.expanded, kind, units, U_DIGITS)


def verdict_cells(verdict, units) -> dict:
    """The cells a verdict's row adds to the compliance table: "± U", p_c with the rule's
    statement, and its three largest contributions."""
    found = verdict.uncertainty
    if found is None:
        return {"u": "", "conformance": "", "top": ""}
    if found.expanded is None:
        return {"u": "", "conformance": found.statement,
                "top": ("U not stated: " + ", ".join(found.not_stated)) if found.not_stated
                else ""}
    top = "; ".join(f"{line.label} {number(100.0 * line.share, 2)} %"
                    for line in found.budget[:3])
    words = found.statement
    if found.not_stated:
        words = ("incomplete: " + ", ".join(found.not_stated) + " not stated; simple "
                 "acceptance shown")
    return {"u": f"± {_expanded(found, verdict.kind, units)}",
            "conformance": (f"p_c {probability(found.conformance)}; {words}"
                            if found.conformance is not None else words),
            "top": f"U from: {top}" if top else ""}


def rule_statement(found: Budgets) -> dict:
    """The decision rule and its risk, in words with the numbers the code used."""
    k = NormalDist().inv_cdf(0.5 + found.coverage / 2.0)
    coverage = f"{100.0 * found.coverage:g} %"
    if found.rule == "simple":
        rule = ("Simple acceptance (ILAC-G8:09/2019 §4.2.1; certkit's default, as no other "
                "rule is named in the spec): a criterion passes when its measured margin is "
                "not negative, the guard band w = 0.")
        risk = ("Risk: a pass whose margin is smaller than its expanded uncertainty carries "
                f"a specific probability of false acceptance above {100 * (1 - found.coverage) / 2:g} % "
                "(50 % at a zero margin); each verdict's conformance probability p_c is "
                "stated and its probability of false acceptance is 1 − p_c.")
    elif found.rule == "guarded":
        r = found.guard_factor
        pfa = 1.0 - NormalDist().cdf(r * k)
        rule = (f"Guarded acceptance (ILAC-G8:09/2019 §4.2.2) with the guard band w = "
                f"{r:g}·U: a criterion passes when its margin is at least w. A margin "
                f"within the tolerance but less than w is a conditional pass, one outside it "
                f"by less than w a conditional fail (§4.2.3); both count as not passing.")
        risk = (f"Risk: for a normal distribution of the margin, an accepted verdict has "
                f"p_c ≥ Φ({r:g}·k) with k = {number(k)}, so its specific probability "
                f"of false acceptance is at most {number(100.0 * pfa, 2)} %.")
    else:
        rule = (f"A required conformance probability (JCGM 106:2012 §8.3): a criterion "
                f"passes when P(margin ≥ 0) ≥ {number(100.0 * found.required)} %.")
        risk = (f"Risk: the specific probability of false acceptance of an accepted verdict "
                f"is at most {number(100.0 * (1.0 - found.required), 2)} %.")
    risk += (" The rule applies to the verdicts whose uncertainty is complete; a verdict "
             "that depends on an input with no stated uncertainty keeps its simple-acceptance "
             "outcome and says so." if found.rule != "simple" else "")
    method = (f"Each input is an error: the reading is the true value plus the error, so a "
              f"sensitivity is the change of the margin per unit of the error (a drop height "
              f"read too high by e leaves a margin smaller by e: −1). "
              f"Uncertainty of each value and margin: the GUM (JCGM 100:2008 §5.1.2) with "
              f"each sensitivity coefficient the change of the margin when the input is "
              f"moved by ±u(x_i), recomputed by certkit's own engine on the recorded signals "
              f"(§5.1.3 note 2), and the Monte Carlo method (JCGM 101:2008 §7) with "
              f"{found.trials} draws of every stated input (random numbers from the fixed "
              f"state {SEED}), each margin "
              f"recomputed by the clauses on the corrected channel extremes (maximum travel "
              f"searched over the samples within {100 * TRAVEL_BAND:g} % of its peak); "
              f"that vectorised model is checked against the engine on {ENGINE_CHECKS} draws "
              f"(agreement within {ENGINE_AGREEMENT:g} of the margin's scale). The report "
              f"uses the GUM result where the Monte Carlo one validates it (JCGM 101 §8.2, "
              f"u to two significant digits), the Monte Carlo one elsewhere, and says which "
              f"per verdict. U is given at a coverage probability of {coverage} "
              f"(k = {number(k)} for a normal distribution), to two significant digits "
              f"(JCGM 100 §7.2.6). The conformance probability is P(margin ≥ 0) (JCGM "
              f"106:2012 §7.3: Φ(margin/u) for the GUM, the share of the draws for Monte "
              f"Carlo). Inputs with no stated uncertainty are probed by {100 * PROBE:g} %"
              f" of their size to find what depends on them; a verdict that does gets no "
              f"conformance probability. A verdict whose drop was repeated (the same test "
              f"type, gear units and drop height) has a Type A line: the standard deviation "
              f"of its margin over the repeats (JCGM 100 §4.2.2), drawn for Monte Carlo from a "
              f"t-distribution with n − 1 degrees of freedom (JCGM 101 §6.4.9).")
    return {"rule": rule, "risk": risk, "method": method, "name": RULE_NAMES[found.rule]}


def uncertainty_view(assessment, units) -> dict | None:
    """The section's tables and figure (None without an uncertainty stage)."""
    found: Budgets | None = assessment.uncertainty
    if found is None:
        return None
    from certkit.evidence.figures import conformance_figure

    inputs = _input_rows(found, units)
    budgets = []
    measured = []
    for verdict in assessment.verdicts:
        item = found.verdicts.get(verdict.id)
        if item is None or item.expanded is None:
            continue
        measured.append((verdict, item))
        budgets.append({
            "id": verdict.id,
            "margin": with_unit(item.margin, verdict.kind, units),
            "u": with_unit(item.standard, verdict.kind, units, U_DIGITS),
            "expanded": _expanded(item, verdict.kind, units),
            "k": number(item.k, 3) if item.k else "—",
            "method": item.method, "why": _why(item, verdict.kind, units),
            "conformance": probability(item.conformance),
            "outcome": f"{item.outcome} ({item.statement})",
            "interval": ("" if item.method != "Monte Carlo" else
                         f"{100 * item.coverage:g} % interval of the margin "
                         f"[{with_unit(item.monte_carlo_interval[0], verdict.kind, units)}, "
                         f"{with_unit(item.monte_carlo_interval[1], verdict.kind, units)}] "
                         f"(U: its half-width)"),
            "lines": [_budget_line(found, line, verdict.kind, units) for line in item.budget],
            "not_stated": ", ".join(item.not_stated)})
    ranked = sorted((pair for pair in measured
                     if pair[0].id in found.samples and not pair[1].not_stated),
                    key=lambda pair: pair[1].margin / pair[1].expanded
                    if pair[1].expanded else math.inf)
    figure = None
    if ranked:
        figure = conformance_figure(
            [(verdict.id, found.samples[verdict.id], _acceptance(found, item), verdict.kind)
             for verdict, item in ranked[:FIGURE_VERDICTS]], units, RULE_NAMES[found.rule])
        figure = dict(figure, svg=Markup(figure["svg"]))
    planning = ("A planning campaign: these uncertainties are computed on synthetic "
                "histories and are predictions, as its verdicts are, not a statement about "
                "measured drops." if assessment.planning else "")
    none = ("The spec states no measurement uncertainty (it has no uncertainty block): no "
            "value or verdict has an uncertainty or a conformance probability, and every "
            "verdict is judged by simple acceptance." if found.none_stated else "")
    return {**rule_statement(found), "inputs": inputs, "budgets": budgets, "figure": figure,
            "unstated": [s.label for s in found.unstated], "planning": planning,
            "none_stated": none}


def _acceptance(found: Budgets, item) -> float:
    """The margin from which a verdict is accepted: the guard band w, or under a required
    conformance probability the margin whose p_c is that probability (z_p·u)."""
    if found.rule == "probability":
        return NormalDist().inv_cdf(found.required) * item.standard
    return item.acceptance or 0.0


def _input_rows(found: Budgets, units) -> list[dict]:
    """One row per stated uncertainty as the spec states it (the gear units or runs it
    applies to listed), then one per input a verdict needs that has none."""
    rows: dict[tuple, dict] = {}
    for source in found.sources:
        if source.input is None:
            continue
        owner = source.target[2]
        part = source.target[3] if source.target[0] == "channel" else ""
        key = (source.target[1], part, source.stated_as, source.basis, source.origin)
        if key not in rows:
            what = (f"{CHANNEL_WORDS[source.target[1]]}: {'gain' if part == 'gain' else 'zero'}"
                    if part else INPUT_WORDS[source.target[1]])
            rows[key] = {"label": what, "owners": [], "stated": source.stated_as,
                         "u": _spread(source, source.input.standard, units),
                         "source": f"{source.basis}: {source.origin}"}
        if owner:
            rows[key]["owners"].append(owner)
    out = [dict(row, label=row["label"] + (f" ({', '.join(row['owners'])})"
                                            if row["owners"] else ""))
           for row in rows.values()]
    out += [{"label": source.label, "stated": "not stated", "u": "—",
             "source": "to be supplied by the applicant"}
            for source in found.unstated]
    return out


def _why(item, kind: str, units) -> str:
    """The method used and why, short, δ in the margin's display unit."""
    if item.delta is None:
        return f"{item.method} only ({item.why.split(': ', 1)[-1]})"
    delta = with_unit(item.delta, kind, units, 1)
    if item.validated:
        return f"GUM, validated by Monte Carlo (both interval ends within δ = {delta})"
    return (f"Monte Carlo (the GUM interval is not validated: an end differs by more than "
            f"δ = {delta})")


def _budget_line(found: Budgets, line, kind: str, units) -> dict:
    """An input's line of a budget: u(x_i), c_i and |c_i|·u(x_i) in display units, share."""
    source = next((item for item in found.sources if item.key == line.source), None)
    if source is None:                  # a Type A line: the margin's own scatter, c = 1
        return {"label": line.label, "u": with_unit(line.standard, kind, units, U_DIGITS),
                "sensitivity": "1",
                "contribution": with_unit(abs(line.contribution), kind, units, U_DIGITS),
                "share": f"{number(100.0 * line.share, 3)} %"}
    contribution = to_display(line.contribution, kind, units) if unit_of(kind, units) \
        else line.contribution
    margin_unit = pretty(unit_of(kind, units) or "") or "1"
    if source.relative:
        sensitivity, per = contribution / (100.0 * line.standard), "%"
    elif unit_of(source.kind, units) is not None:
        sensitivity = contribution / to_display(line.standard, source.kind, units)
        per = pretty(unit_of(source.kind, units))
    else:
        sensitivity, per = contribution / line.standard, source.unit.replace("^2", "²")
    return {"label": line.label, "u": _spread(source, line.standard, units),
            "sensitivity": (f"{number(sensitivity)} per {per}" if margin_unit == "1" else
                            f"{number(sensitivity)} {margin_unit}/"
                            + (f"({per})" if "/" in per else per)),
            "contribution": with_unit(abs(line.contribution), kind, units, U_DIGITS),
            "share": f"{number(100.0 * line.share, 3)} %"}
