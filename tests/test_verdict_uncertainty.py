"""Every verdict's measurement uncertainty (issue 28), against figures worked out by hand
from the analytic drop of conftest.py, from the regulation's formulas and from the seed
example's typed inputs; properties (zero uncertainty, a pure gain, SI against US units);
the spec's errors; results.json and the audit's baseline."""

from __future__ import annotations

import json
import math
import re
from statistics import NormalDist

import numpy as np
import pytest

from certkit import assess, load_campaign
from certkit.errors import CertkitInputError

from .conftest import (A_PEAK, D_MAX, DROP_MASS, F0, G, S_MAX, SEED, TIMESERIES_SPEC,
                       analytic_signals, write_campaign, write_csv)

PHI = NormalDist().cdf
K95 = NormalDist().inv_cdf(0.975)


def _campaign(tmp_path, block: str, spec: str = TIMESERIES_SPEC, name: str = "c"):
    folder = tmp_path / name
    (folder / "data").mkdir(parents=True)
    write_csv(folder / "data" / "r1.csv", analytic_signals())
    return write_campaign(folder, spec + block)


def _verdict(assessment, prefix: str):
    return next(v for v in assessment.verdicts if v.id.startswith(prefix))


CHANNELS = """\
uncertainty:
  decision_rule: {rule}
  channels:
    - channel: vertical_load
      gain: {{expanded: {load_gain}, k: 2}}
      basis: certificate
      source: "certificate LC-1"
    - channel: strut_stroke
      gain: {{expanded: 1 %, k: 2}}
      offset: {{expanded: 0.1 mm, k: 2}}
      basis: assumed
      source: "a typical LVDT"
    - channel: drop_mass_acceleration
      gain: {{expanded: {accel_gain}, k: 2}}
      basis: assumed
      source: "a typical accelerometer"
"""


def test_a_pure_gain_gives_the_peak_load_its_own_relative_uncertainty_and_scales_linearly(
        tmp_path):
    found = {}
    for load_gain in ("0.5 %", "1 %"):
        spec = _campaign(tmp_path, CHANNELS.format(rule="simple", load_gain=load_gain, accel_gain="2 %"),
                         name=load_gain.replace(" %", ""))
        budgets = assess(load_campaign(spec)).uncertainty
        found[load_gain] = budgets.values[("gear", "R1", "left-main", "F_peak")]
    # F = r/(1 + ε): u(F_peak) = F_peak·u(ε) = 12 kN × 0.25 % = 30 N, by hand (the engine's
    # difference over ±u is the secant, r·u/(1 − u²): 6·10⁻⁶ above the derivative)
    assert found["0.5 %"][0] == pytest.approx(F0 * 0.0025, rel=1e-5)
    # twice the gain's uncertainty, twice the peak load's
    # (to the secant's u²: 1/(1 − 0.005²) against 1/(1 − 0.0025²))
    assert found["1 %"][0] == pytest.approx(2 * found["0.5 %"][0], rel=1e-4)
    # a zero offset of the load would move the peak too: not stated here, so it is listed
    assert found["0.5 %"][1] == ("vertical load of left-main: zero",)


def test_the_verdicts_of_the_analytic_drop_by_hand(tmp_path):
    assessment = assess(load_campaign(_campaign(
        tmp_path, CHANNELS.format(rule="simple", load_gain="0.5 %", accel_gain="2 %"))))
    h, lift, weight = 0.300, 0.667, 2600.0
    d = D_MAX + S_MAX                                # δ and s peak together: d = 0.12 m
    w_drop = DROP_MASS * G
    w_e = weight * (h + (1 - lift) * d) / (h + d)    # 23.725(b)
    item = _verdict(assessment, "CFR23.725b-effective-weight/R1/left-main").uncertainty
    assert item.margin == pytest.approx(w_drop - w_e, rel=1e-9)
    # the stroke gain ε_s: d = δ + s/(1 + ε_s), ∂d/∂ε_s = −S_MAX; ∂W_e/∂d = −W·L·h/(h + d)²,
    # and the margin is W_drop − W_e: c = −W·L·h/(h + d)²·S_MAX
    slope = -weight * lift * h / (h + d) ** 2          # ∂W_e/∂d, and ∂margin/∂d = −∂W_e/∂d
    gain, zero = item.budget
    assert gain.source == "strut_stroke gain [left-main]"
    assert gain.sensitivity == pytest.approx(slope * S_MAX, rel=1e-4)
    # the stroke's zero o_s: d = δ + (s − o_s), ∂d/∂o_s = −1
    assert zero.source == "strut_stroke offset [left-main]"
    assert zero.sensitivity == pytest.approx(slope, rel=1e-6)
    assert item.gum_standard == pytest.approx(math.hypot(slope * S_MAX * 0.005,
                                                         slope * 0.00005), rel=1e-4)
    # the margin's inputs not stated: the tyre channel (d), drop mass, static weight, height
    assert {"drop height of R1", "drop mass of R1", "static weight of left-main"} \
        <= set(item.not_stated)
    assert item.conformance is None and item.statement == "incomplete uncertainty"
    # 23.725(e): n = n_j·W_drop/W + L with n_j = a/g + 1 (kinematic); the accelerometer's
    # gain ε_a: ∂n/∂ε_a = −(a/g)·W_drop/W
    load = _verdict(assessment, "CFR23.725f-load-factor/R1/left-main").uncertainty
    slope = -(A_PEAK / G) * w_drop / weight
    accel = next(x for x in load.budget if x.source == "drop_mass_acceleration gain")
    # (margin = n_limit − n; the secant over ±1 % is 1/(1 − 0.01²) of the derivative)
    assert accel.sensitivity == pytest.approx(-slope, rel=2e-4)
    assert accel.contribution == pytest.approx(-slope * 0.01, rel=2e-4)


FULL = CHANNELS + """\
      offset: {{expanded: 0.05 m/s^2, k: 2}}
    - channel: tyre_deflection
      gain: {{expanded: 1 %, k: 2}}
      offset: {{expanded: 0.2 mm, k: 2}}
      basis: assumed
      source: "a typical laser sensor"
  inputs:
    drop_height: {{half_width: 2 mm, distribution: rectangular, basis: assumed, source: tape}}
    drop_mass: {{expanded: 0.2 kg, k: 2, basis: certificate, source: "scale S-1"}}
    static_weight: {{expanded: 0.5 %, k: 2, basis: assumed, source: weighing}}
    wing_area: {{half_width: 0.5 %, distribution: rectangular, basis: assumed, source: drawing}}
"""


def test_zero_uncertainty_gives_todays_outcomes_exactly(tmp_path):
    plain = assess(load_campaign(_campaign(tmp_path, "", name="plain")))
    zero = FULL.format(rule="guarded", load_gain="0 %", accel_gain="0 %")
    zero = re.sub(r"expanded: [0-9.]+ ", "expanded: 0 ", zero)
    zero = re.sub(r"half_width: [0-9.]+ ", "half_width: 0 ", zero)
    zeroed = assess(load_campaign(_campaign(tmp_path, zero, name="zero")))
    assert [(v.id, v.verdict, v.margin) for v in zeroed.verdicts] == \
        [(v.id, v.verdict, v.margin) for v in plain.verdicts]
    assert all(v.uncertainty.expanded in (None, 0.0) for v in zeroed.verdicts
               if v.uncertainty is not None)


def test_a_guard_band_turns_a_thin_pass_into_a_conditional_pass(tmp_path):
    # an accelerometer of 8 % (k = 2): u(n) = (a/g)·(W_drop/W)·4 % = 0.147 > margin/1.96
    stated = FULL.format(rule="guarded", load_gain="0.5 %", accel_gain="8 %")
    found = assess(load_campaign(_campaign(tmp_path, stated)))
    load = _verdict(found, "CFR23.725f-load-factor/R1/left-main")
    item = load.uncertainty
    # n's margin 5.5 − n is small against its U: inside the tolerance, within w = U
    assert 0 < item.margin < item.expanded
    assert item.simple_outcome == "PASS"
    assert (load.verdict, item.statement) == ("FAIL", "conditional pass")
    assert item.acceptance == pytest.approx(item.expanded)
    # the conformance probability, by hand from the budget the report prints
    u = item.standard
    if item.method == "GUM":
        assert item.conformance == pytest.approx(PHI(item.margin / u), rel=1e-9)
    # the campaign's outcome follows the rule
    assert found.outcome == "NOT COMPLIANT"


def test_the_seed_examples_effective_weight_by_hand():
    # 23.725(b), no lift simulated: W_e = W; W_drop = W_unit·m·g/W_max (certkit W1):
    # margin = W_unit·(m/M − 1)·g with W_unit = 292.5 kgf, m = 650 kg, M = 1430 lb
    assessment = assess(load_campaign(SEED))
    item = _verdict(assessment, "CFR23.725b-effective-weight/D300/left-main").uncertainty
    w_unit, m, big = 292.5 * G, 650.0, 1430 * 0.45359237
    assert item.margin == pytest.approx(w_unit * (m / big - 1), rel=1e-9)
    # the scale, U = 0.5 kg (k = 2): ∂margin/∂m = W_unit/M; the weighing, 0.5 % (k = 2):
    # ∂margin/∂(share) = margin
    by_mass = w_unit / big * 0.25
    by_weight = item.margin * 0.0025
    assert item.gum_standard == pytest.approx(math.hypot(by_mass, by_weight), rel=1e-6)
    assert item.method == "GUM" and item.validated            # JCGM 101 §8.2
    assert item.expanded == pytest.approx(K95 * math.hypot(by_mass, by_weight), rel=1e-6)
    assert item.conformance == pytest.approx(PHI(item.margin / item.gum_standard), rel=1e-12)
    assert item.outcome == "PASS" and item.rule == "simple"


def test_si_and_us_customary_inputs_give_the_same_probabilities(tmp_path):
    us = FULL.format(rule="simple", load_gain="0.5 %", accel_gain="2 %").replace("0.2 mm", "0.0078740157 in") \
        .replace("2 mm", "0.078740157 in").replace("0.2 kg", "0.44092452 lb")
    si = FULL.format(rule="simple", load_gain="0.5 %", accel_gain="2 %")
    spec_us = TIMESERIES_SPEC.replace("drop_height: 300 mm", "drop_height: 11.811023622 in") \
        .replace("drop_mass: 250 kg", "drop_mass: 551.15565546 lb")
    a = assess(load_campaign(_campaign(tmp_path, si, name="si")))
    b = assess(load_campaign(_campaign(tmp_path, us, spec=spec_us, name="us")))
    for x, y in zip(a.verdicts, b.verdicts):
        assert x.id == y.id
        if x.uncertainty is not None and x.uncertainty.conformance is not None:
            assert y.uncertainty.conformance == pytest.approx(x.uncertainty.conformance,
                                                              rel=1e-6, abs=1e-9)
            assert y.uncertainty.expanded == pytest.approx(x.uncertainty.expanded, rel=1e-6)


def test_the_monte_carlo_model_reproduces_the_engine_on_random_draws(tmp_path):
    from certkit.compliance.engine import evaluate
    from certkit.compliance.margin_draws import margin_draws
    from certkit.compliance.uncertainty_inputs import perturbed, sources

    campaign = load_campaign(_campaign(tmp_path, FULL.format(rule="simple",
                                                             load_gain="0.5 %", accel_gain="2 %")))
    nominal = evaluate(campaign)
    items = sources(campaign)
    rng = np.random.default_rng(5)
    trials = 12
    # errors ten times the stated ones: the model must hold beyond the usual draws
    draws = np.vstack([10 * item.input.draws(rng, trials) if item.input is not None
                       else np.zeros(trials) for item in items])
    checks = {(b.rules.id, c.id): c.check for b in nominal.basis for c in b.rules.criteria}
    covered = 0
    for verdict in nominal.verdicts:
        if verdict.margin is None:
            continue
        model = margin_draws(nominal, verdict, checks[(verdict.requirement_set,
                                                       verdict.criterion)],
                             items, draws, trials)
        if model is None:
            continue
        covered += 1
        for trial in range(trials):
            changes = {i: float(draws[i, trial]) for i, item in enumerate(items)
                       if item.input is not None}
            engine = next(v.margin for v in evaluate(perturbed(campaign, changes,
                                                               items)).verdicts
                          if v.id == verdict.id)
            assert model[trial] == pytest.approx(engine, rel=1e-9, abs=1e-12), verdict.id
    assert covered == 3     # the limit drop's height, effective weight and load factor


@pytest.mark.parametrize("bad, message", [
    ("gain: {expanded: 20 N, k: 2}", "expected a share of the reading"),
    ("gain: {expanded: 1 %, k: 0}", "must be positive"),
    ("gain: {expanded: -1 %, k: 2}", "zero or more"),
    ("gain: {expanded: 1 %, k: 2, distribution: lognormal}", "'normal', 'rectangular'"),
    ("gain: {half_width: 1 %, k: 2}", "a normal distribution takes"),
    ("offset: {expanded: 1 %, k: 2}", "an absolute uncertainty"),
    ("gain: {expanded: 30 %, k: 2}", "more than 20 % of the reading"),
    ("gain: {expanded: 20 %, k: 0.1}", "standard uncertainty of more than 10 %"),
    ("gain: {expanded: 0.1, k: 2}", "a bare number is ambiguous"),
])
def test_nonsense_uncertainties_are_input_errors_at_their_line(tmp_path, bad, message):
    block = ("uncertainty:\n  channels:\n    - channel: vertical_load\n"
             f"      {bad}\n      basis: assumed\n      source: x\n")
    spec = _campaign(tmp_path, block)
    with pytest.raises(CertkitInputError) as caught:
        load_campaign(spec)
    text = str(caught.value)
    line = TIMESERIES_SPEC.count("\n") + 4
    assert f"campaign.yaml:{line} uncertainty.channels[0]" in text and message in text, text


def test_an_unknown_gear_and_a_channel_stated_twice_are_input_errors(tmp_path):
    block = ("uncertainty:\n  channels:\n"
             "    - {channel: strut_stroke, gear_units: [nose], gain: {expanded: 1 %, k: 2},"
             " basis: assumed, source: x}\n"
             "    - {channel: vertical_load, gain: {expanded: 1 %, k: 2}, basis: assumed,"
             " source: x}\n"
             "    - {channel: vertical_load, gear_units: [left-main], offset: {expanded: 5 N,"
             " k: 2}, basis: assumed, source: x}\n")
    with pytest.raises(CertkitInputError) as caught:
        load_campaign(_campaign(tmp_path, block))
    text = str(caught.value)
    assert "uncertainty.channels[0].gear_units[0]: unknown gear unit 'nose'" in text
    assert "uncertainty.channels[2].channel" in text and "already has its uncertainty" in text


def test_results_json_carries_the_uncertainties_and_the_baseline_catches_a_change(tmp_path):
    from certkit.evidence.comparison import compare
    from certkit.evidence.results_document import results_json

    first = json.loads(results_json(assess(load_campaign(_campaign(
        tmp_path, FULL.format(rule="simple", load_gain="0.5 %", accel_gain="2 %"), name="a")))))
    second = json.loads(results_json(assess(load_campaign(_campaign(
        tmp_path, FULL.format(rule="simple", load_gain="0.5 %", accel_gain="2 %").replace("0.2 kg", "0.4 kg"),
        name="b")))))
    verdict = next(v for v in first["verdicts"]
                   if v["id"] == "CFR23.725b-effective-weight/R1/left-main")
    assert verdict["uncertainty"]["expanded"] > 0 and verdict["unit"] == "N"
    assert first["uncertainty"]["decision_rule"] == "simple"
    assert first["uncertainty"]["monte_carlo"]["trials"] == 100_000
    peak = next(v for v in first["runs"][0]["gears"][0]["values"] if v["key"] == "F_peak")
    assert peak["standard_uncertainty"] == pytest.approx(F0 * 0.0025, rel=1e-5)
    moved = {c.path for c in compare(first, second, 1e-9)}
    assert "verdicts/CFR23.725b-effective-weight/R1/left-main/uncertainty/expanded" in moved
    # the values themselves did not move
    assert not any(path.endswith("/margin") for path in moved)


#: A repeat of the analytic campaign's run R1 (its own block, renamed), from data/r2.csv.
SECOND_DROP = (TIMESERIES_SPEC[TIMESERIES_SPEC.index("  - id: R1"):]
               .replace("id: R1", "id: R2").replace("data/r1.csv", "data/r2.csv"))


def test_a_repeated_drop_adds_the_scatter_of_its_margins_as_a_type_a_component(tmp_path):
    folder = tmp_path / "repeat"
    (folder / "data").mkdir(parents=True)
    write_csv(folder / "data" / "r1.csv", analytic_signals())
    second = analytic_signals()
    second["stroke_mm"] = 1.05 * second["stroke_mm"]        # the repeat strokes 5 % further
    write_csv(folder / "data" / "r2.csv", second)
    spec = write_campaign(folder, TIMESERIES_SPEC.replace("    inspection: {failure: false}\n",
                                                          "    inspection: {failure: false}\n"
                                                          + SECOND_DROP, 1)
                          + FULL.format(rule="simple", load_gain="0.5 %", accel_gain="2 %"))
    assessment = assess(load_campaign(spec))
    h, lift, weight, w_drop = 0.300, 0.667, 2600.0, DROP_MASS * G
    margins = [w_drop - weight * (h + (1 - lift) * d) / (h + d)       # 23.725(b), by hand
               for d in (D_MAX + S_MAX, D_MAX + 1.05 * S_MAX)]
    s = abs(margins[0] - margins[1]) / math.sqrt(2)                 # two observations
    for run, margin in zip(("R1", "R2"), margins):
        item = _verdict(assessment, f"CFR23.725b-effective-weight/{run}/left-main").uncertainty
        assert item.margin == pytest.approx(margin, rel=1e-6)
        line = next(x for x in item.budget if x.source.startswith("repeatability"))
        assert line.label == "repeatability over 2 drops (R1, R2), Type A"
        assert line.standard == pytest.approx(s, rel=1e-6) and line.sensitivity == 1.0
        stated = math.sqrt(sum(x.contribution ** 2 for x in item.budget if x is not line))
        u = math.hypot(stated, s)
        assert item.gum_standard == pytest.approx(u, rel=1e-9)
        # two drops: one degree of freedom, a t-distribution without a finite variance, so no
        # Monte Carlo; k is the t-quantile at Welch–Satterthwaite's ν_eff = u⁴/(s⁴/1)
        from scipy.stats import t as student_t
        nu = u ** 4 / s ** 4
        assert item.method == "GUM" and item.monte_carlo_interval is None
        assert item.k == pytest.approx(student_t.ppf(0.975, nu), rel=1e-9) and item.k > 2.5
        assert item.conformance == pytest.approx(student_t.cdf(margin / u, nu), rel=1e-9)
    # one drop of a kind has no repeat: no Type A line
    single = assess(load_campaign(_campaign(tmp_path, CHANNELS.format(
        rule="simple", load_gain="0.5 %", accel_gain="2 %"))))
    item = _verdict(single, "CFR23.725b-effective-weight/R1/left-main").uncertainty
    assert not any(x.source.startswith("repeatability") for x in item.budget)


def test_a_probability_out_of_range_is_an_error_at_its_own_key(tmp_path):
    spec = _campaign(tmp_path, "uncertainty:\n  decision_rule: probability\n"
                               "  required_probability: 40 %\n")
    with pytest.raises(CertkitInputError) as caught:
        load_campaign(spec)
    line = TIMESERIES_SPEC.count("\n") + 3
    assert f"campaign.yaml:{line} uncertainty.required_probability: must lie in [50 %, 100 %)" \
        in str(caught.value)


def test_a_channel_recorded_as_zeros_does_not_stop_the_assessment(tmp_path):
    # a dead tyre channel: nothing depends on its zero (the data-quality audit speaks of it)
    folder = tmp_path / "dead"
    (folder / "data").mkdir(parents=True)
    signals = analytic_signals()
    signals["tyre_mm"] = 0.0 * signals["tyre_mm"]
    write_csv(folder / "data" / "r1.csv", signals)
    assessment = assess(load_campaign(write_campaign(folder, TIMESERIES_SPEC)))
    assert not any("tyre deflection" in s.label for s in assessment.uncertainty.sources)


def test_stated_zero_uncertainties_are_said_to_be_zero_not_exact(tmp_path):
    zero = FULL.format(rule="simple", load_gain="0 %", accel_gain="0 %")
    zero = re.sub(r"expanded: [0-9.]+ ", "expanded: 0 ", zero)
    zero = re.sub(r"half_width: [0-9.]+ ", "half_width: 0 ", zero)
    found = assess(load_campaign(_campaign(tmp_path, zero)))
    item = _verdict(found, "CFR23.725f-load-factor/R1/left-main").uncertainty
    assert item.statement == "zero stated uncertainty" and item.expanded is None
    lift = _verdict(found, "CFR23.473g-design-load-factor").uncertainty
    assert lift.statement == "exact"          # declared and regulatory values only


def test_a_campaign_that_states_no_uncertainty_says_so_and_probes_nothing(tmp_path):
    from .conftest import report_html

    assessment = assess(load_campaign(_campaign(tmp_path, "")))
    found = assessment.uncertainty
    assert found.none_stated and found.unstated == []
    item = _verdict(assessment, "CFR23.725b-effective-weight/R1/left-main").uncertainty
    assert (item.statement, item.expanded, item.conformance) == ("not stated", None, None)
    assert found.values[("gear", "R1", "left-main", "F_peak")][0] is None
    html = report_html(assessment)
    assert "The spec states no measurement uncertainty" in html
    assert "measurement uncertainties and the decision rule (uncertainty block)" in html
    assert "Input (an error, estimate 0)" not in html


SECOND = SEED.parent.parent / "lsa-main-gear-rig" / "campaign.yaml"


@pytest.mark.parametrize("spec", [SEED, SECOND], ids=["seed", "imperial-2kHz-rig"])
def test_remembered_measures_change_no_figure_and_read_a_changed_record_again(spec):
    # assess() probes with RepeatedMeasures (a gear's records read once while they are the
    # same arrays); the budgets must be those of probes that read every record every time,
    # on both examples (two main gears at 1 kHz in SI; a rig in US units at 2 kHz)
    from certkit.compliance.engine import evaluate
    from certkit.compliance.measures import measure_gear
    from certkit.compliance.uncertainty_inputs import RepeatedMeasures
    from certkit.compliance.verdict_uncertainty import budgets

    campaign = load_campaign(spec)
    remembered = assess(campaign).uncertainty
    plain = budgets(evaluate(campaign), evaluate)
    assert remembered.values == plain.values
    assert set(remembered.verdicts) == set(plain.verdicts) != set()
    for key, found in plain.verdicts.items():
        assert remembered.verdicts[key] == found, key

    signals = analytic_signals()
    time, load = signals["t_s"], signals["Fz_kN"] * 1e3
    stroke, tyre = signals["stroke_mm"] * 1e-3, signals["tyre_mm"] * 1e-3
    measure = RepeatedMeasures()
    first = measure(time, load, stroke, tyre, 4000.0)
    assert first == measure_gear(time, load, stroke, tyre, 4000.0)
    assert measure(time, load, stroke, tyre, 4000.0) is first
    # an equal copy is another record (it could have been changed): read again, same result
    again = measure(time, load.copy(), stroke, tyre, 4000.0)
    assert again is not first and again == first
    # a changed record and another static weight give other measures
    assert measure(time, 1.01 * load, stroke, tyre, 4000.0).peak_load == pytest.approx(
        1.01 * first.peak_load, rel=1e-12)
    assert measure(time, load, stroke, tyre, 4000.0 * 40).touchdown_time != \
        first.touchdown_time
