"""Every verdict's margin for many draws of the stated input errors at once: the vectorised
model of the Monte Carlo propagation (JCGM 101:2008 §7).

The margins are recomputed by :mod:`certkit.compliance.clauses` on the corrected channel
extremes: a maximum of (r − o)/(1 + ε) is (max r − o)/(1 + ε), since 1 + ε > 0; the maximum
total travel δ + s·cos θ, whose instant the two channels' errors can move, is taken over
every sample near its nominal peak (:data:`TRAVEL_BAND`).  A value a source reported (no
time series) is exact.  :func:`certkit.compliance.verdict_uncertainty.budgets` checks this
model against the engine on the first draws before it uses it.
"""

from __future__ import annotations

import math

import numpy as np

from certkit.compliance import clauses
from certkit.compliance.assessment import Assessment
from certkit.compliance.uncertainty_inputs import SERIES, scalar
from certkit.results import Verdict
from certkit.units import STANDARD_GRAVITY

#: Travel samples within this share of the nominal peak are searched for the perturbed
#: maximum of δ + s·cos θ (an error of the channels' gains or zeros above 5 % would be
#: needed to lift a sample from outside the band).
TRAVEL_BAND = 0.05


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
        nominal = scalar(campaign.spec, *item.target[1:]).si
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


def margin_draws(assessment: Assessment, verdict: Verdict, check: str, items, draws,
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
        if verdict.unit != "m":      # 23.726(a) option (2) judges n, not the height
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
        values = getattr(channels, SERIES[channel])
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
