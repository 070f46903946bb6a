"""No model stage can take the compliance evidence down: a calibration, identification or
gap diagnosis that fails for a gear unit is stated in its appendix (why, and what to change),
the other stages and units go on, and the report with its body is written."""

from __future__ import annotations

from dataclasses import replace
from html import unescape

import pytest

from certkit import assess, load_campaign
from certkit.evidence import model_evidence as stages
from certkit.evidence.report import render_report
from certkit.physics.fitting import FitError

from .conftest import SEED


@pytest.fixture
def failing(monkeypatch):
    """Every model stage of the seed example raising, each its own way, in this process."""
    monkeypatch.setenv("CERTKIT_WORKERS", "1")

    def calibration(campaign, gear_id, *args, **kwargs):
        raise FitError(f"4 of 9 residuals are not finite at gas-precharge = 1.2e5 Pa "
                       f"({gear_id})")

    def identification(campaign, gear_id, calibration=None):
        raise ZeroDivisionError("float division by zero")

    def diagnosis(campaign, gear_id):
        if gear_id == "left-main":
            raise ValueError("heat transfer needs τ > 0 and γ > 1")
        raise FitError("the refit met non-finite residuals")

    monkeypatch.setattr(stages, "calibrate_gear", calibration)
    monkeypatch.setattr(stages, "identify_gear", identification)
    monkeypatch.setattr(stages, "gap_diagnosis", diagnosis)
    return load_campaign(SEED)


def test_each_failed_stage_is_recorded_with_its_reason_and_remedy(failing):
    evidence = stages.model_evidence(failing)
    found = {(f.stage, f.gear): f for f in evidence.failures}
    assert sorted(found) == sorted((stage, gear) for stage in
                                   ("calibration", "identification", "gap diagnosis")
                                   for gear in ("left-main", "right-main"))
    calibration = found[("calibration", "left-main")]
    assert "failed numerically" in calibration.reason and "gas-precharge" in calibration.reason
    assert "model.calibration.parameters" in calibration.remedy and not calibration.internal
    # an error certkit cannot attribute to the campaign is its own bug, and says so
    bug = found[("identification", "right-main")]
    assert bug.internal and "ZeroDivisionError" in bug.reason and "report it" in bug.remedy
    assert found[("gap diagnosis", "left-main")].internal
    assert "model.gap.held_out" in found[("gap diagnosis", "right-main")].remedy
    assert evidence.calibration.gears == () and evidence.gap == {}


def test_the_report_is_written_with_each_failure_in_its_appendix(failing, tmp_path):
    assessment = assess(failing)
    render_report(assessment, tmp_path / "out", model=stages.model_evidence(failing))
    html = unescape((tmp_path / "out" / "report.html").read_text(encoding="utf-8"))
    # the body, whole
    for heading in ("5. Results per run", "6. Compliance findings", "7. Measurement uncertainty and decision rule", "11. Conclusions"):
        assert heading in html
    # each appendix states what was not computed, for which unit, why and what to change
    for anchor in ("model", "identification", "gap"):
        section = html[html.index(f'<section id="{anchor}" class="appendix">'):]
        assert section.count('class="not-computed"') >= 2, anchor
    assert ("left-main: not computed. The calibration failed numerically: 4 of 9 residuals "
            "are not finite") in html
    assert "To change: check the drop model's nominal parameters" in html
    assert (tmp_path / "out" / "report.pdf").stat().st_size > 0
    # and results.json lists them for a CI job
    import json

    failures = json.loads((tmp_path / "out" / "results.json").read_text(encoding="utf-8"))[
        "model"]["failures"]
    assert len(failures) == 6
    assert {f["stage"] for f in failures} == {"calibration", "identification", "gap diagnosis"}
    assert [f["certkit_error"] for f in failures if f["stage"] == "identification"] == [True] * 2


def test_an_isothermal_calibration_skips_the_heat_transfer_form_with_its_reason():
    from certkit.physics.effects import CANDIDATES
    from certkit.physics.gear_model import drop_model_for

    campaign = load_campaign(SEED)
    spec = campaign.spec
    model = drop_model_for(spec, spec.runs[0], "left-main")
    heat = next(c for c in CANDIDATES if c.name == "heat transfer")
    assert heat.why_not(model) == ""                     # n = 1.2: the form is built
    heat.add(model, 1.0)
    isothermal = replace(model, gas=replace(model.gas, exponent=1.0))
    reason = heat.why_not(isothermal)
    assert "n = 1" in reason and "isothermal" in reason
    # every other form has nothing against the isothermal model
    assert [c.key for c in CANDIDATES if c.why_not(isothermal)] == ["heat transfer"]


def test_a_worker_process_that_dies_costs_its_stages_not_the_report(monkeypatch):
    import os

    def dies(campaign, gear_id):
        os._exit(9)               # as a process the kernel kills for want of memory

    def fails(campaign, gear_id, *args, **kwargs):
        raise FitError("not finite")

    monkeypatch.setattr(stages, "workers", lambda tasks: 2)     # worker processes, forked
    monkeypatch.setattr(stages, "gap_diagnosis", dies)
    monkeypatch.setattr(stages, "calibrate_gear", fails)
    monkeypatch.setattr(stages, "identify_gear", fails)
    evidence = stages.model_evidence(load_campaign(SEED))
    lost = [f for f in evidence.failures if "ended without a result" in f.reason]
    # the gap diagnoses died with their processes; whatever the broken pool could not
    # finish is stated the same way, and everything finished is kept
    assert {("gap diagnosis", "left-main"), ("gap diagnosis", "right-main")} <= \
        {(f.stage, f.gear) for f in lost}
    assert all("CERTKIT_WORKERS=1" in f.remedy for f in lost)
    assert len(evidence.failures) == 6
