"""Verdict paths: failing heights, reserve drops, lift devices, dynamic tests and the outcome."""

import pytest

from certkit import assess, load_campaign
from certkit.results import FAIL, NOT_SHOWN, PASS

G = 9.80665
# The analytic campaign: W/S = 600 kg * g / 12 m^2 = 490.33 Pa = 10.2407 lb/ft^2,
# h_req = 3.6*sqrt(10.2407) in = 11.5205 in = 292.62 mm; 1.44 h_req = 421.37 mm;
# 2.25 h_req = 658.39 mm.
H_REQ = 3.6 * (600 * G / 12 / 47.880259) ** 0.5 * 0.0254


def edit(spec, old, new):
    text = spec.read_text(encoding="utf-8")
    assert old in text
    spec.write_text(text.replace(old, new, 1), encoding="utf-8")


def verdicts(spec):
    assessment = assess(load_campaign(spec))
    return assessment, {v.id: v for v in assessment.verdicts}


def test_required_height_by_hand():
    assert H_REQ == pytest.approx(0.29262, abs=1e-5)


def test_limit_drop_below_the_required_height_fails_with_negative_margin(timeseries_campaign):
    edit(timeseries_campaign, "drop_height: 300 mm", "drop_height: 250 mm")
    assessment, found = verdicts(timeseries_campaign)
    verdict = found["CFR23.725a-limit-drop-height/R1"]
    assert verdict.verdict == FAIL
    assert verdict.margin == pytest.approx(0.250 - H_REQ, abs=1e-6)
    assert assessment.outcome == "NOT COMPLIANT"


def test_reserve_drop_with_reduced_mass_uses_23_727b(timeseries_campaign):
    edit(timeseries_campaign, "test_type: limit", "test_type: reserve")
    edit(timeseries_campaign, "drop_height: 300 mm", "drop_height: 430 mm")
    assessment, found = verdicts(timeseries_campaign)
    gear = assessment.runs[0].gears[0]
    # W_e = W*h/(h + d) = 2600*0.43/(0.43 + 0.12) = 2032.73 N
    assert gear.get("W_e") == pytest.approx(2600 * 0.43 / 0.55, rel=1e-9)
    assert found["CFR23.727a-reserve-drop-height/R1"].verdict == PASS
    assert found["CFR23.727a-reserve-drop-height/R1"].margin == pytest.approx(0.430 - 1.44 * H_REQ, abs=1e-6)
    assert found["CFR23.723b-reserve-no-failure/R1"].verdict == PASS
    assert found["CFR23.725a-limit-drop-height"].verdict == NOT_SHOWN  # no limit drop left
    # 250 kg·g = 2451.66 N ≥ W_e = 2032.73 N, cited as 23.727(b) (issue 12, defect 6)
    reserve = found["CFR23.727b-reserve-effective-weight/R1/left-main"]
    assert reserve.clause == "14 CFR 23.727(b)" and reserve.verdict == PASS
    assert reserve.limit == pytest.approx(2600 * 0.43 / 0.55, rel=1e-9)
    assert found["CFR23.725b-effective-weight"].verdict == NOT_SHOWN


def test_reserve_drop_without_lift_drops_the_full_weight(timeseries_campaign):
    edit(timeseries_campaign, "test_type: limit", "test_type: reserve")
    edit(timeseries_campaign, "lift: {method: reduced_mass, ratio: 0.667}", "lift: {method: none}")
    assessment, found = verdicts(timeseries_campaign)
    gear = assessment.runs[0].gears[0]
    assert gear.get("W_e") == 2600.0
    # 250 kg * g = 2451.66 N < 2600 N: the article was dropped lighter than W
    # a reserve drop's effective weight is 14 CFR 23.727(b)'s, not 23.725(b)'s (issue 12, defect 6)
    verdict = found["CFR23.727b-reserve-effective-weight/R1/left-main"]
    assert verdict.clause == "14 CFR 23.727(b)"
    assert "CFR23.725b-effective-weight/R1/left-main" not in found
    assert verdict.verdict == FAIL and verdict.margin == pytest.approx(250 * G - 2600, abs=1e-9)


def test_lift_device_run_counts_lift_once(timeseries_campaign):
    edit(timeseries_campaign, "lift: {method: reduced_mass, ratio: 0.667}",
         "lift: {method: lift_device, ratio: 0.5}")
    edit(timeseries_campaign, "drop_mass: 250 kg", "drop_mass: 265.123 kg")
    assessment, found = verdicts(timeseries_campaign)
    gear = assessment.runs[0].gears[0]
    run = assessment.runs[0]
    # n = n_j*W_drop/W, the device's lift already in n_j; no + L
    assert gear.get("n") == pytest.approx(run.get("n_j") * 265.123 * G / 2600, rel=1e-12)
    # energy: W_drop*(h + d) - L*W_drop*d = 2600.0*(0.42) - 0.5*2600.0*0.12 (W_drop = 265.123 kg*g)
    w_drop = 265.123 * G
    assert gear.get("E_avail") == pytest.approx(w_drop * 0.42 - 0.5 * w_drop * 0.12, rel=1e-12)
    assert found["CFR23.725b-effective-weight/R1"].verdict == PASS  # L = 0.5 <= 0.667
    # full weight dropped: 265.123 kg * g = 2599.95 N < 2600 N by 0.05 N
    assert found["CFR23.725b-effective-weight/R1/left-main"].verdict == FAIL


def test_lift_ratio_above_0_667_fails_23_725b(timeseries_campaign):
    edit(timeseries_campaign, "lift: {method: reduced_mass, ratio: 0.667}",
         "lift: {method: lift_device, ratio: 0.9}")
    _, found = verdicts(timeseries_campaign)
    verdict = found["CFR23.725b-effective-weight/R1"]
    assert verdict.verdict == FAIL and verdict.margin == pytest.approx(0.667 - 0.9)


def test_dynamic_drop_by_height_or_by_load_factor(timeseries_campaign):
    edit(timeseries_campaign, "  - requirement_set: 14CFR23-amdt62",
         "  - requirement_set: 14CFR23-amdt62\n    ground_load_dynamic_test: true")
    edit(timeseries_campaign, "test_type: limit", "test_type: dynamic")
    _, found = verdicts(timeseries_campaign)
    # 300 mm < 2.25 h_req = 658.4 mm; n = 5.28238 < 1.5 * 5.5 = 8.25: option (2) fails too
    verdict = found["CFR23.726-dynamic-drop-height/R1"]
    assert verdict.verdict == FAIL and verdict.limit == pytest.approx(8.25)
    edit(timeseries_campaign, "drop_height: 300 mm", "drop_height: 660 mm")
    _, found = verdicts(timeseries_campaign)
    assert found["CFR23.726-dynamic-drop-height/R1"].verdict == PASS


def test_data_quality_error_prevents_a_compliant_outcome(timeseries_campaign):
    # ASTM set only (drop height; energy method n = (0.3 + 0.12/3)/(0.5*0.04 + 0.65*0.08) + 2/3
    # = 5.389 <= 5.5): every criterion passes; but with a 200 kg drop mass the 851 J absorbed
    # exceeds the 200*g*0.42 = 823.8 J available
    edit(timeseries_campaign, "  - requirement_set: 14CFR23-amdt62", "  - requirement_set: ASTM-F2245")
    edit(timeseries_campaign, "drop_mass: 250 kg", "drop_mass: 200 kg")
    assessment, found = verdicts(timeseries_campaign)
    assert {v.verdict for v in assessment.verdicts} == {PASS}
    assert found["F2245-energy-load-factor/R1/left-main"].value == pytest.approx(
        0.34 / 0.072 + 2 / 3, rel=1e-9)
    assert any(f.check == "energy-exceeds-available" and f.severity == "error"
               for f in assessment.findings)
    assert assessment.outcome == "COMPLIANCE NOT SHOWN"
    assert any("data-quality error" in reason for reason in assessment.outcome_reasons())


def test_verdicts_on_unconfirmed_values_are_compliant_only_subject_to_confirmation(timeseries_campaign):
    edit(timeseries_campaign, "  - requirement_set: 14CFR23-amdt62", "  - requirement_set: ASTM-F2245")
    assessment, found = verdicts(timeseries_campaign)
    assert {v.verdict for v in assessment.verdicts} == {PASS}
    assert assessment.outcome == "COMPLIANT SUBJECT TO CONFIRMATION"


def test_accelerometer_disagreeing_with_the_load_cells_is_flagged(timeseries_campaign):
    # declaring the kinematic channel as a specific-force reading drops n_j by exactly 1
    edit(timeseries_campaign, "reference: kinematic", "reference: specific_force")
    assessment, _ = verdicts(timeseries_campaign)
    finding = next(f for f in assessment.findings if f.check == "acceleration-vs-load")
    # n_j = 38.193/g = 3.8947 vs F0/(m g) = 4.8947
    assert finding.values["n_j"] == pytest.approx(12000 / (250 * G) - 1, rel=1e-9)
    assert finding.values["from_load"] == pytest.approx(12000 / (250 * G), rel=1e-9)


def test_stroke_not_zero_at_touchdown_is_flagged(timeseries_campaign):
    edit(timeseries_campaign, "strut_stroke: {column: stroke_mm, unit: mm}",
         "strut_stroke: {column: stroke_mm, unit: mm, offset: -3}")
    assessment, _ = verdicts(timeseries_campaign)
    finding = next(f for f in assessment.findings if f.check == "strut-not-zero-at-touchdown")
    assert finding.values["value"] == pytest.approx(0.003)
