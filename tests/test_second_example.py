"""The second example campaign (campaigns/lsa-main-gear-rig): a planning campaign of one main
gear on a drop rig, in imperial units at 2 kHz.  Its logger files are what synthesise.py
writes, it validates, every value and predicted verdict comes from its synthetic time series,
the numbers follow 14 CFR 23.725-23.727 worked by hand, and its report carries nothing of the
seed paper."""

import csv
import filecmp
import math
import re
import subprocess
import sys

import pytest
import yaml

from certkit import assess, load_campaign

from .conftest import REPO, SEED_FIGURES, load_script
from .conftest import report_html as html_of

SPEC = REPO / "campaigns" / "lsa-main-gear-rig" / "campaign.yaml"
PLANNING = "PLANNING ONLY: NOT COMPLIANCE EVIDENCE"

# exact conversion factors (NIST SP 811, appendix B)
INCH = 0.0254                 # m
LBF = 4.4482216152605         # N

# The regulation worked by hand for the spec's aircraft (W = 1320 lb, S = 120 ft^2):
#   W/S = 1320/120 = 11.0 lbf/ft^2
#   23.725(a): h = 3.6·√(W/S) in = 3.6 × 3.3166248 = 11.939849 in (inside [9.2, 18.7] in)
#   23.727(a): h_reserve = 1.44·h = 17.193383 in
# so the 12.5 in limit drop and the 17.5 in reserve drop are high enough.
H_REQ = 3.6 * math.sqrt(1320.0 / 120.0) * INCH
H_RESERVE = 1.44 * H_REQ
W_UNIT = 594.0 * LBF          # gear_units[main-right].static_weight
LIFT = 0.667                  # runs[].lift.ratio


@pytest.fixture(scope="module")
def synthesise():
    return load_script(SPEC.parent / "synthesise.py", "synthesise_lsa")


@pytest.fixture(scope="module")
def raw_spec():
    return yaml.safe_load(SPEC.read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def assessment():
    return assess(load_campaign(SPEC))


@pytest.fixture(scope="module")
def report_html(assessment):
    return html_of(assessment)   # no model


def _travel_from_the_file(raw_run: dict) -> float:
    """d = max(stroke + tyre deflection) [m], read from the logger file with the csv module
    and the offsets the spec declares (a vertical strut: cos θ = 1)."""
    channels = raw_run["data"]["gears"]["main-right"]
    stroke, tyre = channels["strut_stroke"], channels["tyre_deflection"]
    with (SPEC.parent / raw_run["data"]["file"]).open(encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    return INCH * max((float(r[stroke["column"]]) - stroke["offset"])
                      + (float(r[tyre["column"]]) - tyre["offset"]) for r in rows)


def test_committed_data_are_what_synthesise_py_produces(synthesise, raw_spec, tmp_path):
    blocks = synthesise.generate(tmp_path / "data")
    runs = [run["id"] for run in raw_spec["runs"]]
    assert sorted(blocks) == sorted(runs)
    for run in runs:
        assert filecmp.cmp(tmp_path / "data" / f"{run}.csv", SPEC.parent / "data" / f"{run}.csv",
                           shallow=False), run
    # column mapping and zero offsets as the generator wrote them
    assert {run["id"]: run["data"] for run in raw_spec["runs"]} == blocks


def test_the_logger_files_are_imperial_at_2_khz(raw_spec):
    with (SPEC.parent / "data" / "D12.5.csv").open(encoding="utf-8") as handle:
        rows = list(csv.reader(handle))
    assert rows[0] == ["time_ms", "Fz_lbf", "stroke_in", "tyre_in", "acc_g", "disp_in"]
    times = [float(row[0]) for row in rows[1:]]
    assert {round(b - a, 9) for a, b in zip(times, times[1:])} == {0.5}   # ms: 2 kHz
    assert raw_spec["instrumentation"]["sampling_rate"] == "2000 Hz"


def test_the_campaign_validates():
    result = subprocess.run([sys.executable, "-m", "certkit.cli", "validate", str(SPEC)],
                            cwd=REPO, capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "4 with time series" in result.stdout


def test_a_planning_campaign_predicts_every_verdict_from_its_time_series(assessment):
    assert assessment.outcome == PLANNING
    for run in assessment.runs:
        for gear in run.gears:
            assert gear.basis.startswith("time series"), (run.run.id, gear.basis)
    states = {verdict.id: verdict.verdict for verdict in assessment.verdicts}
    # the one thing no simulation predicts: whether the gear fails in the reserve drop
    # (23.723(b) is found by inspection after it)
    assert states.pop("CFR23.723b-reserve-no-failure/D17.5") == "NOT SHOWN"
    # nor whether the attitude and drag loads represent the landing (23.725(c))
    assert states.pop("CFR23.725c-attitude-and-drag") == "NOT SHOWN"
    # the plan was sized to meet each other criterion (drop heights, ballast, n_limit = 4.0)
    assert set(states.values()) == {"PASS"}, states
    assert set(states) == {
        "CFR23.725a-limit-drop-height/D12.5", "CFR23.725b-effective-weight/D12.5",
        "CFR23.725b-effective-weight/D12.5/main-right",
        "CFR23.727b-reserve-effective-weight/D17.5/main-right",
        "CFR23.725f-load-factor/D12.5/main-right", "CFR23.727a-reserve-drop-height/D17.5",
        "CFR23.473g-design-load-factor"}


def test_required_drop_heights_are_those_of_the_regulation(assessment):
    (basis,) = assessment.basis
    assert basis.values["h_req"].value == pytest.approx(H_REQ, rel=1e-9)
    assert basis.values["h_reserve"].value == pytest.approx(H_RESERVE, rel=1e-9)
    verdicts = {v.id: v for v in assessment.verdicts}
    assert verdicts["CFR23.725a-limit-drop-height/D12.5"].limit == pytest.approx(H_REQ, rel=1e-9)
    assert verdicts["CFR23.727a-reserve-drop-height/D17.5"].limit == pytest.approx(
        H_RESERVE, rel=1e-9)


def test_effective_weights_follow_23_725b_and_23_727b_with_the_recorded_d(assessment, raw_spec):
    # By hand, with d read off the files (6.612 in in D12.5, 6.800 in in D17.5):
    #   23.725(b): W_e = 594·(12.5 + 0.333·6.612)/(12.5 + 6.612) = 594·14.7018/19.112 = 456.93 lbf
    #   23.727(b): W_e = 594·17.5/(17.5 + 6.800) = 427.78 lbf
    # against 475 lb and 435 lb dropped.
    runs = {run["id"]: run for run in raw_spec["runs"]}
    verdicts = {v.id: v for v in assessment.verdicts}
    # limit drop, 23.725(b): W_e = W·(h + (1 − L)·d)/(h + d)
    h, d = 12.5 * INCH, _travel_from_the_file(runs["D12.5"])
    limit = verdicts["CFR23.725b-effective-weight/D12.5/main-right"]
    assert limit.limit == pytest.approx(W_UNIT * (h + (1 - LIFT) * d) / (h + d), rel=1e-9)
    assert limit.value == pytest.approx(475 * 0.45359237 * 9.80665, rel=1e-12)  # 475 lb
    # reserve drop, 23.727(b): W_e = W·h/(h + d)
    h, d = 17.5 * INCH, _travel_from_the_file(runs["D17.5"])
    reserve = verdicts["CFR23.727b-reserve-effective-weight/D17.5/main-right"]
    assert reserve.clause == "14 CFR 23.727(b)"
    assert reserve.limit == pytest.approx(W_UNIT * h / (h + d), rel=1e-9)
    assert reserve.value == pytest.approx(435 * 0.45359237 * 9.80665, rel=1e-12)  # 435 lb
    assert (limit.limit / LBF, reserve.limit / LBF) == pytest.approx((456.93, 427.78), abs=0.01)


def test_the_load_factor_comes_from_the_carriage_accelerometer(assessment, raw_spec):
    # 23.725(e): n_j is the accelerometer's peak in g (it reads specific force, so no +1);
    # n = n_j·W_e/W + L with W_e the 475 lb actually dropped and W = 594 lbf
    run = next(r for r in raw_spec["runs"] if r["id"] == "D12.5")
    with (SPEC.parent / run["data"]["file"]).open(encoding="utf-8") as handle:
        n_j = max(float(row["acc_g"]) for row in csv.DictReader(handle))
    verdict = next(v for v in assessment.verdicts
                   if v.id == "CFR23.725f-load-factor/D12.5/main-right")
    assert verdict.value == pytest.approx(n_j * 475.0 / 594.0 + LIFT, rel=1e-9)
    assert verdict.limit == 4.0


def test_the_report_shows_imperial_units_and_no_seed_paper_figure(report_html):
    text = re.sub(r"<svg.*?</svg>", "", report_html, flags=re.S)   # coordinates are digits
    for figure in SEED_FIGURES:
        assert figure not in text, figure
    assert "PLANNING ON SYNTHETIC DATA" in report_html and PLANNING in report_html
    assert ">lbf<" in report_html and ">in<" in report_html      # unit cells of the tables
    assert "11.94 in" in report_html and "17.19 in" in report_html


def test_the_report_does_not_name_the_seed_paper(report_html):
    assert "seed" not in report_html.lower()
