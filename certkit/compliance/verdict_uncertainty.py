"""The measurement uncertainty of every verdict and measured value, and the statement of
conformity under the campaign's decision rule.

Inputs (:func:`sources`).  Each stated uncertainty of the spec's ``uncertainty`` block is an
input quantity whose estimate is zero: the error of a channel's gain ε (a share: the
recorded r = (1 + ε)·q + o for the quantity q) and of its zero o, per gear unit, the same
in every run (one instrument, one calibration: a systematic error, so it is correlated
between runs by construction); the error of the drop height and of the drop mass of each
run (set and weighed per drop: independent between runs); the error of each gear unit's
static weight; the error of the wing area.  An input the spec leaves out is "not stated":
it is probed (a small error put in and taken out) only to find which verdicts depend on it.

Propagation through the engine (:func:`budgets`).  Each input is moved by ±u(x_i) and the
whole assessment recomputed by the engine itself (``evaluate``, the function that makes the
verdicts), so every value and every margin is recomputed by the code that made it on the
recorded signals: the sensitivity c_i = [f(x_i + u_i) − f(x_i − u_i)]/(2·u_i), JCGM 100:2008
§5.1.3 note 2, and u_c² = Σ (c_i·u_i)², §5.1.2 eq. (10) (the inputs are independent by
construction: one input that feeds several measures, such as a load-cell gain, is the same
input in each of them).

Monte Carlo (:func:`monte_carlo_margins`, JCGM 101:2008 §7).  10⁵ draws of every stated input;
each verdict's margin recomputed for all draws at once by :mod:`certkit.compliance.clauses`
on the corrected channel extremes (a maximum of (r − o)/(1 + ε) is (max r − o)/(1 + ε); the
maximum total travel is taken over every sample near its nominal peak).  That vectorised
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
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from statistics import NormalDist

import numpy as np

from certkit.compliance import clauses
from certkit.compliance.assessment import Assessment
from certkit.compliance.uncertainty import (Input, MonteCarloResult, conformance_probability,
                                            decide, summarise, tolerance)
from certkit.results import EQUALITY_TOLERANCE, FAIL, NOT_SHOWN, PASS, Verdict
from certkit.spec.campaign import Campaign
from certkit.spec.schema import UncertaintySpec
from certkit.units import STANDARD_GRAVITY, SpecQuantity

#: Monte Carlo trials per verdict (JCGM 101 §7.2: 10⁶ is often enough for a 95 % interval
#: to two significant digits; 10⁵ with the adaptive check of §7.9 not run: the validation
#: of §8 compares intervals to two significant digits of u, which 10⁵ draws resolve for
#: the margins here; the report states the number).
TRIALS = 100_000
SEED = 20_080_901            # JCGM 101's year and month: any fixed seed makes it reproducible
#: Draws on which the vectorised model is checked against the engine, and the agreement
#: required (relative to the margin's scale: its magnitude plus its standard uncertainty).
ENGINE_CHECKS = 4
ENGINE_AGREEMENT = 1e-6
#: Share of an unstated input's probe (gain: this share; zero: this share of the channel's
#: largest reading; a scalar: this share of its value) to find what depends on it.
PROBE = 1e-3
#: Travel samples within this share of the nominal peak are searched for the perturbed
#: maximum of δ + s·cos θ (an error of the channels' gains or zeros above 5 % would be
#: needed to lift a sample from outside the band).
TRAVEL_BAND = 0.05

CHANNEL_WORDS = {"vertical_load": "vertical load", "strut_stroke": "strut stroke",
                 "tyre_deflection": "tyre deflection",
                 "drop_mass_acceleration": "drop-mass acceleration"}
_SERIES = {"vertical_load": "load", "strut_stroke": "stroke", "tyre_deflection": "tyre"}
INPUT_WORDS = {"drop_height": "drop height", "drop_mass": "drop mass",
               "static_weight": "static weight", "wing_area": "wing area"}
_INPUT_KINDS = {"drop_height": "length", "drop_mass": "mass", "static_weight": "force",
                "wing_area": "area"}
#: The SI unit of an input's spread, by its display kind.
SI_UNIT = {"length": "m", "force": "N", "mass": "kg", "area": "m^2", "acceleration": "m/s^2",
           "ratio": "1"}
_CHANNEL_KINDS = {"vertical_load": "force", "strut_stroke": "length",
                  "tyre_deflection": "length", "drop_mass_acceleration": "acceleration"}


# --------------------------------------------------------------------------- inputs
@dataclass(frozen=True)
class Source:
    """One input quantity of the budgets (estimate 0: an error)."""

    key: str               # "vertical_load gain [left-main]", "drop_height [D300]"
    label: str             # in words, for the report
    target: tuple          # ("channel", channel, gear | None, "gain" | "offset") or
                           # ("input", name, run or gear id | None)
    relative: bool         # a share of the quantity (gain, or a scalar stated in %)
    kind: str              # display kind of the spread ("ratio" for a share)
    input: Input | None    # None: not stated (probed only)
    probe: float           # the step of a probe (stated: u; not stated: a small error)
    basis: str = ""        # certificate | assumed
    origin: str = ""       # the certificate's reference, or what the assumption rests on
    stated_as: str = ""    # "U = 0.5 % (k = 2, normal)" as typed

    @property
    def unit(self) -> str:
        """The SI unit of the input's spread ("1" for a share)."""
        return SI_UNIT[self.kind]


def _stated_as(part) -> str:
    if part.distribution == "normal":
        return f"U = {part.expanded.text} (k = {part.k.text}, normal)"
    return f"± {part.half_width.text} ({part.distribution})"


def _input_of(name: str, part) -> Input:
    spread = part.spread.si
    if part.distribution == "normal":
        return Input.expanded(name, 0.0, spread, part.k.si)
    return Input(name, 0.0, part.distribution, spread)


def sources(campaign: Campaign) -> list[Source]:
    """Every input quantity the campaign's verdicts can depend on, stated or not, in a fixed
    order: channels per gear unit (gain, then zero), the drop-mass acceleration, then the
    drop height and drop mass per run, the static weight per unit and the wing area."""
    spec = campaign.spec
    stated = spec.uncertainty or UncertaintySpec()
    by_channel: dict[tuple, object] = {}
    for item in stated.channels:
        gears = ([None] if item.channel == "drop_mass_acceleration"
                 else item.gear_units or [g.id for g in spec.gear_units])
        for gear in gears:
            by_channel[(item.channel, gear)] = item
    peaks = _channel_peaks(campaign)
    out = []
    channels = [(c, g.id) for g in spec.gear_units for c in _SERIES]
    if peaks.get(("drop_mass_acceleration", None)) is not None:
        channels.append(("drop_mass_acceleration", None))
    for channel, gear in channels:
        if peaks.get((channel, gear)) is None:
            continue                       # never recorded: nothing depends on it
        item = by_channel.get((channel, gear))
        where = f" [{gear}]" if gear else ""
        for part in ("gain", "offset"):
            given = getattr(item, part) if item is not None else None
            key = f"{channel} {part}{where}"
            label = (f"{CHANNEL_WORDS[channel]}{f' of {gear}' if gear else ''}: "
                     f"{'gain' if part == 'gain' else 'zero'}")
            probe = PROBE if part == "gain" else PROBE * peaks[(channel, gear)]
            kind = "ratio" if part == "gain" else _CHANNEL_KINDS[channel]
            if given is None:
                out.append(Source(key, label, ("channel", channel, gear, part),
                                  part == "gain", kind, None, probe))
            else:
                value = _input_of(key, given)
                out.append(Source(key, label, ("channel", channel, gear, part), part == "gain",
                                  kind, value, value.standard, item.basis, item.source,
                                  _stated_as(given)))
    scalars = ([("drop_height", run.id) for run in spec.runs]
               + [("drop_mass", run.id) for run in spec.runs]
               + [("static_weight", g.id) for g in spec.gear_units] + [("wing_area", None)])
    for name, owner in scalars:
        given = getattr(stated.inputs, name)
        where = f" [{owner}]" if owner else ""
        label = f"{INPUT_WORDS[name]}{f' of {owner}' if owner else ''}"
        nominal = _scalar(spec, name, owner).si
        if given is None:
            out.append(Source(f"{name}{where}", label, ("input", name, owner), True, "ratio",
                              None, PROBE))
            continue
        relative = given.spread.unit == "1"
        value = _input_of(f"{name}{where}", given)
        out.append(Source(f"{name}{where}", label, ("input", name, owner), relative,
                          "ratio" if relative else _INPUT_KINDS[name], value,
                          value.standard if value.standard > 0 else PROBE * (1 if relative
                                                                              else nominal),
                          given.basis, given.source, _stated_as(given)))
    return out


def _channel_peaks(campaign: Campaign) -> dict[tuple, float]:
    """(channel, gear) -> the largest magnitude recorded in any run (the size of a probe)."""
    peaks: dict[tuple, float] = {}
    for series in campaign.series.values():
        if series is None:
            continue
        for gear, channels in series.gears.items():
            for channel, attribute in _SERIES.items():
                values = getattr(channels, attribute)
                if values is not None:
                    peak = float(np.max(np.abs(values)))
                    peaks[(channel, gear)] = max(peaks.get((channel, gear), 0.0), peak)
        if series.acceleration is not None:
            key = ("drop_mass_acceleration", None)
            peaks[key] = max(peaks.get(key, 0.0), float(np.max(np.abs(series.acceleration))))
    return peaks


def _scalar(spec, name: str, owner: str | None) -> SpecQuantity:
    if name in ("drop_height", "drop_mass"):
        run = next(run for run in spec.runs if run.id == owner)
        return getattr(run, name)
    if name == "static_weight":
        return next(g for g in spec.gear_units if g.id == owner).static_weight
    return spec.aircraft.wing_area


# --------------------------------------------------------------------------- perturbed campaign
def perturbed(campaign: Campaign, changes: dict[int, float], items: list[Source]) -> Campaign:
    """``campaign`` with the errors ``changes`` (index into ``items`` -> the error's value)
    taken out of its inputs: a channel's recorded r becomes (r − o)/(1 + ε); a scalar x
    becomes x − e (or x·(1 − e) for a share).  Only the SI magnitudes change: the typed text,
    and so every stated resolution, stays."""
    spec = campaign.spec
    gains: dict[tuple, float] = {}
    offsets: dict[tuple, float] = {}
    scalars: dict[tuple, tuple[float, bool]] = {}
    for index, error in changes.items():
        item = items[index]
        if item.target[0] == "channel":
            _, channel, gear, part = item.target
            (gains if part == "gain" else offsets)[(channel, gear)] = error
        else:
            scalars[item.target[1:]] = (error, item.relative)

    def corrected(values, channel, gear):
        if values is None:
            return None
        gain, offset = gains.get((channel, gear), 0.0), offsets.get((channel, gear), 0.0)
        if gain == 0.0 and offset == 0.0:
            return values
        return (values - offset) / (1.0 + gain)

    def moved(quantity: SpecQuantity, name: str, owner) -> SpecQuantity:
        if (name, owner) not in scalars:
            return quantity
        error, relative = scalars[(name, owner)]
        si = quantity.si * (1.0 - error) if relative else quantity.si - error
        return replace(quantity, si=si)

    series = {}
    for run_id, run_series in campaign.series.items():
        if run_series is None:
            series[run_id] = None
            continue
        gears = {gear: type(channels)(**{attribute: corrected(getattr(channels, attribute),
                                                               channel, gear)
                                         for channel, attribute in _SERIES.items()})
                 for gear, channels in run_series.gears.items()}
        series[run_id] = replace(run_series, gears=gears, acceleration=corrected(
            run_series.acceleration, "drop_mass_acceleration", None))
    runs = [run.model_copy(update={"drop_height": moved(run.drop_height, "drop_height", run.id),
                                   "drop_mass": moved(run.drop_mass, "drop_mass", run.id)})
            for run in spec.runs]
    units = [unit.model_copy(update={"static_weight": moved(unit.static_weight,
                                                             "static_weight", unit.id)})
             for unit in spec.gear_units]
    aircraft = spec.aircraft.model_copy(
        update={"wing_area": moved(spec.aircraft.wing_area, "wing_area", None)})
    new_spec = spec.model_copy(update={"runs": runs, "gear_units": units, "aircraft": aircraft})
    return replace(campaign, spec=new_spec, series=series)


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


# --------------------------------------------------------------------------- Monte Carlo
def _channel_draws(items, draws) -> tuple[dict, dict]:
    gains, offsets = {}, {}
    for index, item in enumerate(items):
        if item.target[0] == "channel" and item.input is not None:
            _, channel, gear, part = item.target
            (gains if part == "gain" else offsets)[(channel, gear)] = draws[index]
    return gains, offsets


def _scalar_draws(campaign, items, draws) -> dict:
    """(name, owner) -> the drawn SI values of each stated scalar input (nominal if not)."""
    out = {}
    for index, item in enumerate(items):
        if item.target[0] != "input":
            continue
        nominal = _scalar(campaign.spec, *item.target[1:]).si
        if item.input is None:
            out[item.target[1:]] = nominal
        else:
            error = draws[index]
            out[item.target[1:]] = nominal * (1.0 - error) if item.relative else nominal - error
    return out


def _extreme(values: np.ndarray, start: int, channel, gear, gains, offsets, trials):
    """max over samples from ``start`` of (r − o)/(1 + ε), for every draw."""
    peak = float(np.max(values[start:]))
    gain = gains.get((channel, gear), 0.0)
    offset = offsets.get((channel, gear), 0.0)
    return np.broadcast_to((peak - offset) / (1.0 + gain), (trials,))


def _travel(tyre, stroke, cos_theta, start, gear, gains, offsets, trials):
    """max over time of δ + s·cos θ on the corrected channels, for every draw."""
    travel = tyre[start:] + stroke[start:] * cos_theta
    peak = float(np.max(travel))
    near = np.flatnonzero(travel >= peak - TRAVEL_BAND * max(abs(peak), 1e-12)) + start
    g_t = np.asarray(gains.get(("tyre_deflection", gear), 0.0))
    o_t = np.asarray(offsets.get(("tyre_deflection", gear), 0.0))
    g_s = np.asarray(gains.get(("strut_stroke", gear), 0.0))
    o_s = np.asarray(offsets.get(("strut_stroke", gear), 0.0))
    best = np.full(trials, -np.inf)
    for index in near:
        sample = ((tyre[index] - o_t) / (1.0 + g_t)
                  + (stroke[index] - o_s) / (1.0 + g_s) * cos_theta)
        best = np.maximum(best, sample)
    return best


def _start(time: np.ndarray, touchdown: float | None) -> int:
    """measure_gear's first sample: the one before touchdown (0 without a touchdown)."""
    if touchdown is None:
        return 0
    return max(int(np.searchsorted(time, touchdown)) - 1, 0)


def _verdict_draws(assessment: Assessment, verdict: Verdict, check: str, items, draws,
                   trials: int) -> np.ndarray | None:
    """The verdict's margin for every draw, by the clauses on the corrected extremes; None
    for a verdict the vectorised model does not cover (its uncertainty then comes from the
    GUM alone)."""
    campaign = assessment.campaign
    spec = campaign.spec
    gains, offsets = _channel_draws(items, draws)
    scalars = _scalar_draws(campaign, items, draws)
    run = next((r for r in assessment.runs if r.run.id == verdict.run), None)
    if run is None or verdict.margin is None:
        return None
    h = np.broadcast_to(scalars[("drop_height", run.run.id)], (trials,))
    area = scalars[("wing_area", None)]
    basis = next(b for b in assessment.basis if b.rules.id == verdict.requirement_set)
    rules = basis.rules

    def required(factor_key):
        formula_units = rules.parameters["drop_height_formula_units"]
        loading = spec.aircraft.maximum_weight.si / np.asarray(area)
        height = clauses.drop_height_formula(loading, rules.number("drop_height_coefficient"),
                                             formula_units["wing_loading"],
                                             formula_units["height"])
        bounded = clauses.bounded_drop_height(height, rules.length("drop_height_minimum"),
                                              rules.length("drop_height_maximum"))
        return bounded * (1.0 if factor_key is None else rules.number(factor_key))

    if check in ("limit_drop_height", "reserve_drop_height", "dynamic_drop_height"):
        if check == "dynamic_drop_height" and verdict.reason != "option (1): 2.25·h_req":
            return None
        factor = {"limit_drop_height": None, "reserve_drop_height": "reserve_height_factor",
                  "dynamic_drop_height": "dynamic_height_factor"}[check]
        return h - required(factor)
    gear = next((g for g in run.gears if g.gear_id == verdict.gear), None)
    if gear is None:
        return None
    unit = campaign.gear_units[gear.gear_id]
    strut = unit.strut
    cos_theta = math.cos(strut.inclination.si if strut and strut.inclination else 0.0)
    recorded = run.series is not None and gear.gear_id in run.series.gears
    channels = run.series.gears[gear.gear_id] if recorded else None
    start = _start(run.series.time, gear.get("t0")) if recorded else 0
    weight = scalars[("static_weight", gear.gear_id)]
    mass = scalars[("drop_mass", run.run.id)]
    w_drop = mass * STANDARD_GRAVITY
    if len(run.run.gear_units) > 1:
        w_drop = weight * w_drop / spec.aircraft.maximum_weight.si
    w_drop = np.broadcast_to(w_drop, (trials,))

    def measured(key, channel):
        """A gear's extreme from its corrected channel, or the value reported (exact)."""
        if not recorded:
            value = gear.get(key)
            return None if value is None else np.full(trials, value)
        values = getattr(channels, _SERIES[channel])
        if values is None:
            return None
        return _extreme(values, start, channel, gear.gear_id, gains, offsets, trials)

    def travel():
        if not recorded:
            return None if gear.get("d") is None else np.full(trials, gear.get("d"))
        if channels.stroke is None or channels.tyre is None:
            return None
        return _travel(channels.tyre, channels.stroke, cos_theta, start, gear.gear_id, gains,
                       offsets, trials)

    if check in ("effective_weight", "reserve_effective_weight"):
        if verdict.unit != "N":             # the lift-ratio line of the check: no measurement
            return None
        method = run.run.lift.method
        if method != "reduced_mass":
            w_e = np.broadcast_to(weight, (trials,))
        else:
            d = travel()
            if d is None:
                return None
            w_e = (clauses.reserve_effective_weight(weight, h, d) if check ==
                   "reserve_effective_weight" and run.run.test_type == "reserve"
                   else clauses.effective_weight(weight, h, d, run.get("L")))
        return w_drop - w_e
    if check == "inertia_load_factor":
        if run.series is None or run.series.acceleration is None:
            return None
        touchdowns = [g.get("t0") for g in run.gears if g.get("t0") is not None]
        after = run.series.time >= min(touchdowns)
        a_peak = _extreme(run.series.acceleration[after], 0, "drop_mass_acceleration", None,
                          gains, offsets, trials)
        n_j = clauses.drop_test_load_factor(a_peak, run.series.acceleration_reference)
        lift = 0.0 if run.run.lift.method == "lift_device" else run.get("L")
        n = clauses.inertia_load_factor(n_j, w_drop, weight, lift)
        return verdict.limit - n
    if check == "energy_method_load_factor":
        d_t, d_s = measured("d_t", "tyre_deflection"), measured("d_s", "strut_stroke")
        if d_t is None or d_s is None:
            return None
        lift = rules.number("energy_method_wing_lift_ratio")
        n_j = clauses.energy_method_load_factor(h, d_t, d_s * cos_theta, lift,
                                                rules.number("tyre_efficiency"),
                                                rules.number("shock_absorber_efficiency"))
        return verdict.limit - (n_j + lift)
    return None


# --------------------------------------------------------------------------- putting it together
def budgets(assessment: Assessment, evaluate: Callable[[Campaign], Assessment],
            trials: int = TRIALS) -> Budgets:
    """The uncertainty of every verdict's margin and every value of ``assessment``, and each
    measured verdict's statement of conformity under the spec's decision rule.

    ``evaluate`` is the engine without the data-quality audit (campaign -> assessment with
    its values and verdicts): every sensitivity is a difference of its results."""
    import time as clock

    campaign = assessment.campaign
    stated = campaign.spec.uncertainty or UncertaintySpec()
    items = sources(campaign)
    found = Budgets(stated.decision_rule, stated.guard_factor.si,
                    stated.required_probability.si, stated.coverage_probability.si, items,
                    trials=trials)
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
        found.values[key] = (math.sqrt(u2), missing)

    checks = {(b.rules.id, c.id): c.check for b in assessment.basis for c in b.rules.criteria}
    stated_items = [i for i, item in enumerate(items) if item.input is not None]
    started = clock.perf_counter()
    draws = (np.vstack([item.input.draws(np.random.default_rng([SEED, i]), trials)
                        if item.input is not None else np.zeros(trials)
                        for i, item in enumerate(items)]) if stated_items else None)
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
        lines = tuple(sorted((Contribution(items[i].key, items[i].label, c, u, cu,
                                           (cu * cu / u2) if u2 > 0 else 0.0)
                              for i, c, u, cu in budget if cu != 0.0),
                             key=lambda line: -abs(line.contribution)))
        check = checks[(verdict.requirement_set, verdict.criterion)]
        mc = None
        if draws is not None and u2 > 0:
            mc = _monte_carlo(assessment, verdict, check, items, draws, trials, evaluate,
                              math.sqrt(u2))
        found.verdicts[verdict.id] = _decided(verdict, math.sqrt(u2) if lines else None, mc,
                                              lines, missing, found)
        if mc is not None and mc.margins is not None:
            found.samples[verdict.id] = np.sort(mc.margins)[::max(trials // 2000, 1)]
    found.monte_carlo_seconds = clock.perf_counter() - started
    return found


@dataclass(frozen=True)
class _Draws:
    result: MonteCarloResult | None
    margins: np.ndarray | None
    why: str


def _monte_carlo(assessment, verdict, check, items, draws, trials, evaluate, u_gum) -> _Draws:
    margins = _verdict_draws(assessment, verdict, check, items, draws, trials)
    if margins is None:
        return _Draws(None, None, "the Monte Carlo model does not cover this check")
    scale = abs(verdict.margin) + u_gum
    if abs(float(np.median(margins)) - verdict.margin) > 10 * u_gum + ENGINE_AGREEMENT * scale:
        return _Draws(None, None, "the Monte Carlo model's margin is off the engine's")
    for trial in range(ENGINE_CHECKS):
        changes = {i: float(draws[i, trial]) for i, item in enumerate(items)
                   if item.input is not None}
        engine = {v.id: v.margin for v in evaluate(perturbed(assessment.campaign, changes,
                                                             items)).verdicts}.get(verdict.id)
        if engine is None or abs(engine - float(margins[trial])) > ENGINE_AGREEMENT * scale:
            return _Draws(None, None, f"the Monte Carlo model disagrees with the engine on "
                                      f"draw {trial + 1} ({engine} against "
                                      f"{float(margins[trial])})")
    stated = assessment.campaign.spec.uncertainty or UncertaintySpec()
    return _Draws(summarise(margins, stated.coverage_probability.si), margins, "")


def _decided(verdict: Verdict, u_gum: float | None, mc: _Draws | None, budget, missing,
             found: Budgets) -> VerdictUncertainty:
    coverage = found.coverage
    k_normal = NormalDist().inv_cdf(0.5 + coverage / 2.0)
    margin = verdict.margin
    simple = verdict.verdict
    if u_gum is None:
        why = ("no input of this verdict has a stated uncertainty" if missing
               else "no measured input: the margin is exact (declared or regulatory values)")
        return VerdictUncertainty(margin, None, None, None, coverage, "none", why, None, None,
                                  None, None, None, found.rule, simple,
                                  "not stated" if missing else "exact", simple, None,
                                  budget, missing)
    low_high = delta = ok = None
    method, standard, expanded, k = "GUM", u_gum, k_normal * u_gum, k_normal
    conformance = conformance_probability(margin, u_gum, lower=0.0)
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
                   "an end differs by more than δ), so the Monte Carlo one is used")
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
