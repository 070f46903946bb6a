"""The measurement uncertainty of every verdict and measured value, and the statement of
conformity under the campaign's decision rule.

Inputs: :mod:`certkit.compliance.uncertainty_inputs` (each stated uncertainty an error with
estimate zero; an input the spec leaves out is probed only to find what depends on it).

Propagation through the engine (:func:`budgets`).  Each input is moved by ±u(x_i) and the
whole assessment recomputed by the engine itself (``evaluate``, the function that makes the
verdicts), so every value and every margin is recomputed by the code that made it on the
recorded signals: the sensitivity c_i = [f(x_i + u_i) − f(x_i − u_i)]/(2·u_i), JCGM 100:2008
§5.1.3 note 2, and u_c² = Σ (c_i·u_i)², §5.1.2 eq. (10) (the inputs are independent by
construction: one input that feeds several measures, such as a load-cell gain, is the same
input in each of them).

Monte Carlo (JCGM 101:2008 §7).  10⁵ draws of every stated input; each verdict's margin
recomputed for all draws at once by :mod:`certkit.compliance.margin_draws`.  That vectorised
model is checked against the engine on the first draws (:data:`ENGINE_CHECKS`); a verdict
whose model disagrees is propagated by the GUM alone and says so.  The GUM result is used
where the Monte Carlo one validates it (JCGM 101 §8.2, :func:`validated`), the Monte Carlo
one elsewhere.

Measurand and decision.  A verdict's measurand is its margin (value − limit for "≥", limit −
value for "≤"), so an input that feeds both the value and the limit (the drop height into
W_drop's check and into W_e) counts once.  The conformance probability is P(margin ≥ 0)
(JCGM 106:2012 §7.3 for a normal PDF; the share of the draws for Monte Carlo) and the
decision rule is ILAC-G8:09/2019's (:func:`certkit.compliance.uncertainty.decide`).
"""

from __future__ import annotations

import math
import time
import zlib
from collections.abc import Callable
from dataclasses import dataclass, field
from statistics import NormalDist

import numpy as np

from certkit.compliance.assessment import Assessment
from certkit.compliance.margin_draws import margin_draws
from certkit.compliance.uncertainty import (MonteCarloResult, conformance_probability, decide,
                                            summarise, tolerance)
from certkit.compliance.uncertainty_inputs import Source, perturbed, sources
from certkit.results import EQUALITY_TOLERANCE, NOT_SHOWN, Verdict
from certkit.spec.campaign import Campaign
from certkit.spec.uncertainty import UncertaintySpec

#: Monte Carlo trials per verdict.  With 10⁵ draws an end of a 95 % interval of a near-normal
#: margin scatters by about 0.01·u (the adaptive procedure of JCGM 101 §7.9 is not run), as
#: much as the tolerance δ of §8.2 at two significant digits: a GUM result is used only when
#: both ends agree within δ, the Monte Carlo one otherwise.
TRIALS = 100_000
SEED = 20_080_901            # JCGM 101's year and month: any fixed seed makes it reproducible
#: Draws on which the vectorised model is checked against the engine, and the agreement
#: required (relative to the margin's scale: its magnitude plus its standard uncertainty).
ENGINE_CHECKS = 4
ENGINE_AGREEMENT = 1e-6


# --------------------------------------------------------------------------- results
@dataclass(frozen=True)
class Contribution:
    """One input's line of a budget."""

    source: str            # Source.key
    label: str
    sensitivity: float     # c_i (margin SI per input SI, or per unit share)
    standard: float        # u(x_i) (SI or share)
    contribution: float    # c_i·u(x_i), margin SI, signed
    share: float           # of u_c²


@dataclass(frozen=True)
class VerdictUncertainty:
    """A verdict's margin with its uncertainty, and its statement of conformity."""

    margin: float
    standard: float | None             # u_c(margin) [SI] of the method used (None: none)
    expanded: float | None             # U at ``coverage``
    k: float | None
    coverage: float
    method: str                        # "GUM", "Monte Carlo" or "none"
    why: str                           # why that method
    gum_standard: float | None
    monte_carlo_interval: tuple | None  # (low, high) [SI]
    validated: bool | None             # JCGM 101 §8.2
    delta: float | None                # its numerical tolerance δ
    conformance: float | None          # p_c = P(margin ≥ 0)
    rule: str
    outcome: str                       # under the rule: PASS, FAIL (or the verdict's own)
    statement: str                     # pass, conditional pass, conditional fail, fail, ...
    simple_outcome: str                # the verdict under simple acceptance (today's)
    acceptance: float | None           # the acceptance limit of the margin (guard band w)
    budget: tuple = ()                 # Contributions, largest first
    not_stated: tuple = ()             # labels of inputs it depends on with no uncertainty


@dataclass
class Budgets:
    """Everything the uncertainty stage found for a campaign."""

    rule: str
    guard_factor: float
    required: float
    coverage: float
    sources: list[Source]
    verdicts: dict[str, VerdictUncertainty] = field(default_factory=dict)
    #: :func:`value_key` -> (u_c [SI] from the stated inputs, labels of the inputs it depends
    #: on that have no stated uncertainty)
    values: dict[tuple, tuple] = field(default_factory=dict)
    trials: int = TRIALS
    monte_carlo_seconds: float = 0.0
    #: the spec has no uncertainty block: nothing stated, nothing probed
    none_stated: bool = False
    #: verdict id -> its Monte Carlo margins, sorted and thinned to about 2000 (a figure's)
    samples: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def unstated(self) -> list[Source]:
        """The inputs some verdict depends on that have no stated uncertainty."""
        used = {label for item in self.verdicts.values() for label in item.not_stated}
        return [item for item in self.sources if item.input is None and item.label in used]


# --------------------------------------------------------------------------- the GUM, through the engine
def _margins(assessment: Assessment) -> dict[str, float | None]:
    return {v.id: v.margin for v in assessment.verdicts}


def value_key(scope: str, *where) -> tuple:
    """The key of a value in :attr:`Budgets.values`: ("design", key), ("basis", set, key),
    ("run", run, key) or ("gear", run, gear, key)."""
    return (scope, *where)


def _values(assessment: Assessment) -> dict[tuple, float | None]:
    out = {}
    for key, value in assessment.design.items():
        out[value_key("design", key)] = value.value
    for basis in assessment.basis:
        for key, value in basis.values.items():
            out[value_key("basis", basis.rules.id, key)] = value.value
    for run in assessment.runs:
        for key, value in run.values.items():
            out[value_key("run", run.run.id, key)] = value.value
        for gear in run.gears:
            for key, value in gear.values.items():
                out[value_key("gear", run.run.id, gear.gear_id, key)] = value.value
    return out


def _everything(assessment: Assessment) -> dict:
    return ({("margin", key): value for key, value in _margins(assessment).items()}
            | {("value", key): value for key, value in _values(assessment).items()})


def _slopes(evaluate, campaign, items, read) -> tuple[dict, dict]:
    """Per input: the central difference of every quantity ``read`` gives, over ±probe."""
    slopes: dict = {}
    for index, item in enumerate(items):
        up = read(evaluate(perturbed(campaign, {index: item.probe}, items)))
        down = read(evaluate(perturbed(campaign, {index: -item.probe}, items)))
        for key in up:
            a, b = up[key], down.get(key)
            if a is None or b is None:
                continue
            slopes.setdefault(key, {})[index] = (a - b) / (2.0 * item.probe)
    return slopes


# --------------------------------------------------------------------------- putting it together
def budgets(assessment: Assessment, evaluate: Callable[[Campaign], Assessment],
            trials: int = TRIALS) -> Budgets:
    """The uncertainty of every verdict's margin and every value of ``assessment``, and each
    measured verdict's statement of conformity under the spec's decision rule.

    ``evaluate`` is the engine without the data-quality audit (campaign -> assessment with
    its values and verdicts): every sensitivity is a difference of its results."""
    campaign = assessment.campaign
    stated = campaign.spec.uncertainty or UncertaintySpec()
    items = sources(campaign)
    found = Budgets(stated.decision_rule, stated.guard_factor.si,
                    stated.required_probability.si, stated.coverage_probability.si, items,
                    trials=trials)
    if campaign.spec.uncertainty is None:
        return _none_stated(assessment, found)
    slopes = _slopes(evaluate, campaign, items, _everything)
    margin_slopes = {key[1]: part for key, part in slopes.items() if key[0] == "margin"}
    value_slopes = {key[1]: part for key, part in slopes.items() if key[0] == "value"}
    for key, value in _values(assessment).items():
        if value is None:
            continue
        parts = value_slopes.get(key, {})
        u2 = sum((c * items[i].input.standard) ** 2 for i, c in parts.items()
                 if items[i].input is not None)
        missing = tuple(items[i].label for i, c in parts.items()
                        if items[i].input is None and abs(c) > 0)
        found.values[key] = (None if (u2 == 0 and missing) else math.sqrt(u2), missing)

    checks = {(b.rules.id, c.id): c.check for b in assessment.basis for c in b.rules.criteria}
    repeats = repeatability(assessment)
    stated_items = [i for i, item in enumerate(items) if item.input is not None]
    started = time.perf_counter()
    draws = (np.vstack([item.input.draws(np.random.default_rng([SEED, i]), trials)
                        if item.input is not None else np.zeros(trials)
                        for i, item in enumerate(items)]) if stated_items else None)
    engine_margins: dict[int, dict[str, float | None]] = {}

    def engine_draw(trial: int) -> dict[str, float | None]:
        # the engine's margins of every verdict at draw ``trial``: evaluated once, shared by
        # the verdicts' checks (the same draws feed every verdict's Monte Carlo)
        if trial not in engine_margins:
            changes = {i: float(draws[i, trial]) for i in stated_items}
            engine_margins[trial] = {v.id: v.margin for v in
                                     evaluate(perturbed(campaign, changes, items)).verdicts}
        return engine_margins[trial]

    for verdict in assessment.verdicts:
        if verdict.margin is None:
            continue
        parts = margin_slopes.get(verdict.id, {})
        budget = []
        for index, c in parts.items():
            item = items[index]
            if item.input is None:
                continue
            u = item.input.standard
            budget.append((index, c, u, c * u))
        u2 = sum(line[3] ** 2 for line in budget)
        missing = tuple(items[i].label for i, c in parts.items()
                        if items[i].input is None and abs(c) > 0)
        spread = repeats.get(verdict.id)
        if spread is not None:
            u2 += spread[0] ** 2
        lines = [Contribution(items[i].key, items[i].label, c, u, cu,
                              (cu * cu / u2) if u2 > 0 else 0.0)
                 for i, c, u, cu in budget if cu != 0.0]
        if spread is not None and spread[0] > 0:
            s, n, runs = spread
            lines.append(Contribution(f"{REPEATABILITY} [{verdict.id}]",
                                      f"repeatability over {n} drops ({runs}), Type A", 1.0, s,
                                      s, s * s / u2))
        lines = tuple(sorted(lines, key=lambda line: -abs(line.contribution)))
        check = checks[(verdict.requirement_set, verdict.criterion)]
        dof = None
        if spread is not None and spread[0] > 0 and u2 > 0:
            # Welch–Satterthwaite (JCGM 100 §G.4.1) with the Type B inputs taken as exact
            dof = u2 ** 2 / (spread[0] ** 4 / (spread[1] - 1))
        mc = None
        if spread is not None and spread[0] > 0 and spread[1] - 1 <= 2:
            mc = _Draws(None, None, f"a Type A input from {spread[1]} drops has {spread[1] - 1} "
                                    f"degree(s) of freedom, and its t-distribution no finite "
                                    f"variance (JCGM 101 §6.4.9): the GUM with a t-factor")
        elif draws is not None and u2 > 0:
            mc = _monte_carlo(assessment, verdict, check, items, draws, trials, engine_draw,
                              math.sqrt(u2), spread)
        found.verdicts[verdict.id] = _decided(verdict, math.sqrt(u2) if lines else None, mc,
                                              lines, missing, found, dof,
                                              any(items[i].input is not None and abs(c) > 0
                                                  for i, c in parts.items()))
        if mc is not None and mc.margins is not None:
            found.samples[verdict.id] = np.sort(mc.margins)[::max(trials // 2000, 1)]
    found.monte_carlo_seconds = time.perf_counter() - started
    return found


#: What a campaign without an ``uncertainty`` block leaves unstated.
NONE_STATED = "every input (the spec has no uncertainty block)"


def _none_stated(assessment: Assessment, found: Budgets) -> Budgets:
    """A campaign that states no uncertainty at all: every value and margin 'not stated',
    every verdict by simple acceptance, without probing the inputs one by one (a spec
    without the block learns nothing from which of them a verdict needs)."""
    found.none_stated = True
    for key, value in _values(assessment).items():
        if value is not None:
            found.values[key] = (None, (NONE_STATED,))
    for verdict in assessment.verdicts:
        if verdict.margin is not None:
            found.verdicts[verdict.id] = VerdictUncertainty(
                verdict.margin, None, None, None, found.coverage, "none",
                "the spec states no measurement uncertainty", None, None, None, None, None,
                found.rule, verdict.verdict, "not stated", verdict.verdict, None, (),
                (NONE_STATED,))
    return found


#: The key prefix of a budget's Type A line (no input of the spec: the drops themselves).
REPEATABILITY = "repeatability"


def repeatability(assessment: Assessment) -> dict[str, tuple[float, int, str]]:
    """Verdict id -> (s, n, the runs) for a verdict whose drop was repeated: runs of the same
    test type, gear units and drop height, n ≥ 2 of them with a margin of the same criterion
    and gear.  s is the experimental standard deviation of the margin of one drop over the n
    (JCGM 100:2008 §4.2.2, a Type A evaluation): what a drop repeated as the campaign
    repeated it would scatter by, measurement and rig together."""
    groups: dict[tuple, list[str]] = {}
    for run in assessment.runs:
        key = (run.run.test_type, tuple(run.run.gear_units), round(run.run.drop_height.si, 9))
        groups.setdefault(key, []).append(run.run.id)
    sibling = {run: ids for ids in groups.values() if len(ids) >= 2 for run in ids}
    margins: dict[tuple, dict[str, float]] = {}
    for verdict in assessment.verdicts:
        if verdict.run in sibling and verdict.margin is not None:
            margins.setdefault((verdict.requirement_set, verdict.criterion, verdict.gear),
                               {})[verdict.run] = verdict.margin
    out = {}
    for verdict in assessment.verdicts:
        if verdict.run not in sibling or verdict.margin is None:
            continue
        group = margins[(verdict.requirement_set, verdict.criterion, verdict.gear)]
        values = [group[run] for run in sibling[verdict.run] if run in group]
        if len(values) >= 2:
            runs = ", ".join(run for run in sibling[verdict.run] if run in group)
            out[verdict.id] = (float(np.std(values, ddof=1)), len(values), runs)
    return out


@dataclass(frozen=True)
class _Draws:
    result: MonteCarloResult | None
    margins: np.ndarray | None
    why: str


def _monte_carlo(assessment, verdict, check, items, draws, trials, engine_draw, u_gum,
                 spread=None) -> _Draws:
    """``verdict``'s margin at each draw, checked against the engine's margins on the first
    :data:`ENGINE_CHECKS` draws (``engine_draw(trial)``: every verdict's margin there)."""
    margins = margin_draws(assessment, verdict, check, items, draws, trials)
    if margins is None:
        return _Draws(None, None, "the Monte Carlo model does not cover this check")
    scale = abs(verdict.margin) + u_gum
    if abs(float(np.median(margins)) - verdict.margin) > 10 * u_gum + ENGINE_AGREEMENT * scale:
        return _Draws(None, None, "the Monte Carlo model's margin is off the engine's")
    for trial in range(ENGINE_CHECKS):
        engine = engine_draw(trial).get(verdict.id)
        if engine is None or abs(engine - float(margins[trial])) > ENGINE_AGREEMENT * scale:
            return _Draws(None, None, f"the Monte Carlo model disagrees with the engine on "
                                      f"draw {trial + 1} ({engine} against "
                                      f"{float(margins[trial])})")
    if spread is not None and spread[0] > 0:
        # JCGM 101 §6.4.9: a Type A input from n observations is a scaled t-distribution
        # with n − 1 degrees of freedom (here of one observation: scale s)
        s, n, _ = spread
        rng = np.random.default_rng([SEED, zlib.crc32(verdict.id.encode())])
        margins = margins + s * rng.standard_t(n - 1, margins.size)
    stated = assessment.campaign.spec.uncertainty or UncertaintySpec()
    return _Draws(summarise(margins, stated.coverage_probability.si), margins, "")


def _decided(verdict: Verdict, u_gum: float | None, mc: _Draws | None, budget, missing,
             found: Budgets, dof: float | None = None, stated: bool = False
             ) -> VerdictUncertainty:
    coverage = found.coverage
    # k for a normal output, or the t-quantile at the effective degrees of freedom of a
    # budget with a Type A line (JCGM 100 §G.4.1, §G.6.4)
    if dof is not None:
        # here, not at the top: scipy.stats adds about 1 s to every certkit command's
        # start-up (python -X importtime), and only a Type A line needs it
        from scipy.stats import t as student_t
    k_normal = (NormalDist().inv_cdf(0.5 + coverage / 2.0) if dof is None
                else float(student_t.ppf(0.5 + coverage / 2.0, dof)))
    margin = verdict.margin
    simple = verdict.verdict
    if u_gum is None:
        measured = stated                 # it depends on stated inputs, all with u = 0
        why = ("no input of this verdict has a stated uncertainty" if missing
               else "every input it depends on is stated with a zero uncertainty" if measured
               else "no measured input: the margin is exact (declared or regulatory values)")
        return VerdictUncertainty(margin, None, None, None, coverage, "none", why, None, None,
                                  None, None, None, found.rule, simple,
                                  "not stated" if missing else "zero stated uncertainty"
                                  if measured else "exact", simple, None, budget, missing)
    low_high = delta = ok = None
    method, standard, expanded, k = "GUM", u_gum, k_normal * u_gum, k_normal
    conformance = (conformance_probability(margin, u_gum, lower=0.0) if dof is None
                   else float(student_t.cdf(margin / u_gum, dof)))
    if mc is not None and mc.result is not None:
        result = mc.result
        low_high = result.interval
        delta = tolerance(u_gum, 2)
        gum_low, gum_high = margin - k_normal * u_gum, margin + k_normal * u_gum
        ok = abs(gum_low - low_high[0]) <= delta and abs(gum_high - low_high[1]) <= delta
        if ok:
            why = ("the GUM interval is validated by the Monte Carlo one (JCGM 101 §8.2: both "
                   "ends agree within δ)")
        else:
            method, standard = "Monte Carlo", result.standard
            expanded = 0.5 * (low_high[1] - low_high[0])
            k = expanded / standard if standard > 0 else None
            conformance = float(np.mean(mc.margins >= 0.0))
            why = ("the GUM interval is not validated by the Monte Carlo one (JCGM 101 §8.2: "
                   "an end differs by more than δ; at 10⁵ draws the ends scatter by about "
                   "0.01·u, so this may be the draws' own scatter), so the Monte Carlo one is "
                   "used")
    else:
        why = f"GUM only, not validated: {mc.why if mc is not None else 'no Monte Carlo run'}"
    if missing:
        # a stated part only: no conformance probability, the rule cannot be applied
        return VerdictUncertainty(margin, standard, expanded, k, coverage, method,
                                  why,
                                  u_gum, low_high, ok, delta, None, found.rule, simple,
                                  "incomplete uncertainty", simple, None, budget, missing)
    if simple == NOT_SHOWN:
        return VerdictUncertainty(margin, standard, expanded, k, coverage, method, why, u_gum,
                                  low_high, ok, delta, conformance, found.rule, simple,
                                  "not shown", simple, None, budget, missing)
    slack = EQUALITY_TOLERANCE * max(abs(verdict.value or 0.0), abs(verdict.limit or 0.0))
    decision = decide(margin + slack, expanded, k if k else k_normal, lower=0.0,
                      rule=found.rule, r=found.guard_factor, required=found.required,
                      conformance=conformance)
    outcome = simple if found.rule == "simple" else decision.outcome
    return VerdictUncertainty(margin, standard, expanded, k, coverage, method, why, u_gum,
                              low_high, ok, delta, conformance, found.rule, outcome,
                              decision.statement, simple, decision.acceptance[0], budget,
                              missing)
