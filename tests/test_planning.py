"""Planning campaigns (campaign.purpose: planning): the whole time-series path on synthetic
histories, marked everywhere, never mistaken for compliance (issue 12)."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from certkit import assess, load_campaign
from certkit.cli import app
from certkit.compliance.assessment import PLANNING

from .conftest import ANALYTIC_STRUT_ENERGY, ANALYTIC_TYRE_ENERGY, report_html

runner = CliRunner()
MARK = "PLANNING ON SYNTHETIC DATA: NOT COMPLIANCE EVIDENCE"


def _synthetic(spec, planning: bool):
    text = spec.read_text(encoding="utf-8")
    assert "\n      file: data/r1.csv\n" in text
    text = text.replace("\n      file: data/r1.csv\n",
                        "\n      file: data/r1.csv\n      origin: synthetic\n")
    if planning:
        text = text.replace("campaign: {id: TS-TEST, title: Analytic single-gear campaign}",
                            "campaign: {id: TS-TEST, title: Analytic single-gear campaign, "
                            "purpose: planning}")
    spec.write_text(text, encoding="utf-8")
    return spec


def test_a_planning_campaign_computes_every_value_from_its_synthetic_histories(
        timeseries_campaign):
    assessment = assess(load_campaign(_synthetic(timeseries_campaign, planning=True)))
    gear = assessment.runs[0].gears[0]
    assert gear.basis.startswith("time series")
    # the analytic energies of conftest: 2·F0·s_max/π and F0·δ_max/2
    assert gear.get("E_s") == pytest.approx(ANALYTIC_STRUT_ENERGY, rel=2e-3)
    assert gear.get("E_t") == pytest.approx(ANALYTIC_TYRE_ENERGY, rel=2e-3)
    assert assessment.outcome == PLANNING
    assert "predictions for the planned drops" in assessment.outcome_reasons()[0]
    # the verdicts themselves are there, as predictions
    assert {v.verdict for v in assessment.verdicts} >= {"PASS"}
    assert [f.severity for f in assessment.findings if f.check == "synthetic-data"] == ["info"]


def test_the_same_synthetic_runs_outside_planning_are_no_evidence(timeseries_campaign):
    assessment = assess(load_campaign(_synthetic(timeseries_campaign, planning=False)))
    assert assessment.runs[0].gears[0].basis == "no data"
    assert assessment.outcome == "COMPLIANCE NOT SHOWN"


def test_every_page_and_table_says_planning_and_strict_never_passes(timeseries_campaign,
                                                                    tmp_path):
    spec = _synthetic(timeseries_campaign, planning=True)
    page = report_html(assess(load_campaign(spec)))
    # the running header, which the PDF repeats on every page (templates/report.css @page)
    assert f'<header class="running" id="running-header"><span class="planning-mark">{MARK}' \
        in page
    assert "not a compliance report" in page and PLANNING in page
    result = runner.invoke(app, ["report", str(spec), "-o", str(tmp_path / "o2"), "--no-model",
                                 "--strict"])
    assert result.exit_code == 1, result.output
    assert result.stdout.startswith(PLANNING)      # the progress lines go to stderr
    result = runner.invoke(app, ["audit", str(spec), "--junit", str(tmp_path / "a.xml")])
    assert MARK in result.output and "criteria predicted to pass" in result.output
    # no CI job turns green on predictions: exit 1, and a failing planning row in every table
    assert result.exit_code == 1, result.output
    junit = (tmp_path / "a.xml").read_text(encoding="utf-8")
    assert '<testcase name="planning"' in junit and 'type="PLANNING"' in junit
    result = runner.invoke(app, ["audit", str(spec), "--format", "csv"])
    assert result.output.splitlines()[1].startswith("planning,planning,campaign.purpose,")
