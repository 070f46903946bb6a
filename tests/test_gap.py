"""The gap diagnosis end to end: the training/held-out split and the input it refuses, the
residual map, the held-out error per channel and phase before and after the named effects,
the map that remains, and the blind check's record as a campaign input."""

import csv
import hashlib
import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from certkit import assess, load_campaign, render_report
from certkit.errors import CertkitInputError
from certkit.evidence import report as report_module
from certkit.gap.diagnosis import WHOLE, gap_diagnosis, gap_document, held_out_errors
from certkit.gap.holdout import split_for
from certkit.gap.phases import PHASES, Phase
from certkit.physics.calibration import AlignedRecord
from certkit.physics.drops import default_split
from certkit.physics.synthetic import simulate_campaign

BLIND = Path(__file__).parent / "data" / "blind_check.json"
# synthetic truth below: the spec's gear with these effects, none of them in the nominal model
TRUTH = {"rebound orifice", "seal friction", "tyre hysteresis"}


@pytest.fixture(scope="module")
def with_hysteresis(tmp_path_factory):
    from .conftest import PHYSICS_SPEC, write_campaign

    # truth: the spec's gear with 8 % tyre hysteresis on; the diagnosed model has none
    text = PHYSICS_SPEC.replace("      damping: 0.05 s/m\n",
                                "      damping: 0.05 s/m\n      hysteresis: 8 %\n").replace(
        "  effects: [rebound-orifice, seal-friction]",
        "  effects: [rebound-orifice, seal-friction, tyre-hysteresis]")
    root = tmp_path_factory.mktemp("gap")
    # 1.2 s of each drop: the impact, the rebound and the settling the diagnosis works on
    return simulate_campaign(load_campaign(write_campaign(root / "truth", text)), root / "runs",
                             seed=11, duration=1.2)


@pytest.fixture(scope="module")
def diagnosed(with_hysteresis):
    """The whole diagnosis of the synthetic campaign's gear (about 10 s), shared."""
    return gap_diagnosis(load_campaign(with_hysteresis), "left-main")


def variant(spec: Path, name: str, gap: str | None = None, heights: dict | None = None,
            extra: str = "") -> Path:
    """A copy of the generated spec beside it (same data files) with a model.gap block,
    changed drop heights or an extra run."""
    text = spec.read_text(encoding="utf-8")
    if gap is not None:
        assert "\ninstrumentation:\n" in text
        text = text.replace("\ninstrumentation:\n", f"\n  gap: {gap}\ninstrumentation:\n", 1)
    for old, new in (heights or {}).items():
        assert f"drop_height: {old}" in text
        text = text.replace(f"drop_height: {old}", f"drop_height: {new}")
    if extra:
        text = text.replace("\nassumptions:\n", f"\n{extra}assumptions:\n", 1)
    target = spec.parent / name
    target.write_text(text, encoding="utf-8")
    return target


# --------------------------------------------------------------------------- the split
def test_default_split_holds_out_the_highest_drop(with_hysteresis):
    assert default_split(load_campaign(with_hysteresis), "left-main") == (["D200", "D250"],
                                                                          ["D300"])


def test_a_declared_held_out_run_replaces_the_default(with_hysteresis):
    spec = variant(with_hysteresis, "declared.yaml", gap="{held_out: [D250]}")
    assert split_for(load_campaign(spec), "left-main") == (["D200", "D300"], ["D250"], True)
    assert split_for(load_campaign(with_hysteresis), "left-main") == (["D200", "D250"],
                                                                      ["D300"], False)


def test_an_unknown_gap_held_out_run_is_an_input_error_naming_the_key(with_hysteresis):
    spec = variant(with_hysteresis, "unknown.yaml", gap="{held_out: [D3OO]}")
    with pytest.raises(CertkitInputError) as error:
        load_campaign(spec)
    problem = error.value.problems[0]
    assert problem.key == "model.gap.held_out[0]" and "unknown run 'D3OO'" in problem.message
    line = next(n for n, text in enumerate(spec.read_text().splitlines(), 1) if "D3OO" in text)
    assert problem.line == line


def test_drops_at_one_height_are_refused_with_what_the_diagnosis_needs(with_hysteresis):
    spec = variant(with_hysteresis, "one-height.yaml",
                   heights={"200 mm": "300 mm", "250 mm": "300 mm"})
    with pytest.raises(CertkitInputError) as error:
        split_for(load_campaign(spec), "left-main")
    message = str(error.value)
    assert "one drop height only (D200 (300 mm), D250 (300 mm), D300 (300 mm))" in message
    assert "at two drop heights or more" in message and "holds out the highest" in message


def test_holding_out_every_drop_leaves_no_training_run(with_hysteresis):
    spec = variant(with_hysteresis, "all-held.yaml", gap="{held_out: [D200, D250, D300]}")
    with pytest.raises(CertkitInputError) as error:
        split_for(load_campaign(spec), "left-main")
    problem = error.value.problems[0]
    assert problem.key == "model.gap.held_out" and problem.line is not None
    assert "no training run is left" in problem.message


def test_a_held_out_run_without_this_gears_data_leaves_none_held_out(with_hysteresis):
    run = ("- id: D350\n  test_type: limit\n  gear_units: [left-main]\n  drop_height: 350 mm\n"
           "  drop_mass: 292.5 kg\n  lift: {method: none}\n")
    spec = variant(with_hysteresis, "no-data.yaml", gap="{held_out: [D350]}", extra=run)
    with pytest.raises(CertkitInputError) as error:
        split_for(load_campaign(spec), "left-main")
    problem = error.value.problems[0]
    assert problem.key == "model.gap.held_out"
    assert "no held-out run is" in problem.message and "D350" in problem.message


# --------------------------------------------------------------------------- where
def test_residual_map_covers_every_channel_phase_and_run(diagnosed):
    gap = diagnosed.before
    assert gap.training == ("D200", "D250") and gap.held_out == ("D300",)
    keys = {(c.run, c.channel, c.phase) for c in gap.cells}
    for run in ("D200", "D250", "D300"):
        for channel in ("load", "stroke", "tyre"):
            assert {(run, channel, phase) for phase in PHASES} <= keys
    # before contact both the model and the (zeroed) measurement are at rest: the free-fall
    # residual is sensor noise only (20 N load, 0.05 mm travel)
    free_fall = [c for c in gap.cells if c.phase == "free fall"]
    assert all(c.rms < (60.0 if c.channel == "load" else 1.5e-4) for c in free_fall)
    # the unmodelled tyre loop leaves a residual well above the noise somewhere after contact
    assert gap.largest is not None and gap.largest.phase != "free fall"
    assert gap.largest.run in gap.training and "largest disagreement" in gap.summary
    for shares in gap.bands.values():
        assert sum(shares.values()) == pytest.approx(1.0)


# --------------------------------------------------------------------------- how far
def test_held_out_errors_per_phase_on_a_record_worked_by_hand():
    time = np.arange(8) * 1e-3
    measured = np.array([0, 0, 10, 10, 10, 10, 0, 0], dtype=float)
    nominal = np.array([0, 0, 6, 6, 14, 14, 0, 0], dtype=float)      # residual ±4
    refitted = np.array([0, 0, 9, 9, 12, 12, 0, 0], dtype=float)     # residual 1, then −2
    after = time >= 2e-3
    phases = {"D9": [Phase("free fall", 0, 2), Phase("compression", 2, 4),
                     Phase("rebound", 4, 6), Phase("settling", 6, 8)]}
    before = {"D9": AlignedRecord(time, after, {"load": measured}, {"load": nominal})}
    later = {"D9": AlignedRecord(time, after, {"load": measured}, {"load": refitted})}
    rows = {r.phase: r for r in held_out_errors(before, later, phases)}
    # from touchdown (6 samples): residuals 4, 4, −4, −4, 0, 0 and 1, 1, −2, −2, 0, 0
    assert rows[WHOLE].samples == 6
    assert rows[WHOLE].before == pytest.approx(math.sqrt(64 / 6))
    assert rows[WHOLE].after == pytest.approx(math.sqrt(10 / 6))
    assert rows[WHOLE].shrink == pytest.approx(1 - math.sqrt(10 / 64))
    assert (rows["compression"].before, rows["compression"].after) == (4.0, 1.0)
    assert rows["compression"].shrink == pytest.approx(0.75)
    assert (rows["rebound"].before, rows["rebound"].after) == (4.0, 2.0)
    assert rows["rebound"].shrink == pytest.approx(0.5)
    # no error to shrink: no shrink, rather than 0/0
    assert rows["settling"].before == 0.0 and rows["settling"].shrink is None
    # without a named effect there is no "after"
    alone = held_out_errors(before, None, phases)
    assert all(r.after is None and r.shrink is None for r in alone)


def test_the_diagnosis_names_effects_of_the_truth_and_maps_what_remains(diagnosed):
    assert diagnosed.diagnosis.answer and set(diagnosed.diagnosis.answer) <= TRUTH
    assert not diagnosed.declared and diagnosed.held_out == ("D300",)
    after = diagnosed.after
    assert after is not None
    assert {(c.run, c.channel, c.phase) for c in after.cells} == \
        {(c.run, c.channel, c.phase) for c in diagnosed.before.cells}

    def energy(cells, runs):
        return sum(c.samples * (c.rms / c.scale) ** 2 for c in cells if c.run in runs)

    # the named effects were fitted on the training runs: their residual must fall there
    assert energy(after.cells, after.training) < 0.5 * energy(diagnosed.before.cells,
                                                              after.training)


def test_held_out_shrink_per_channel_and_phase(diagnosed):
    rows = diagnosed.held_out_errors
    assert {r.run for r in rows} == {"D300"}
    for row in rows:
        assert row.after is not None
        if row.before > 0:
            assert 100 * row.shrink == pytest.approx(100 * (1 - row.after / row.before))
    label = "with " + " and ".join(diagnosed.diagnosis.answer)
    for channel in ("load", "stroke", "tyre"):
        whole = next(r for r in rows if r.channel == channel and r.phase == WHOLE)
        # the same error computed by the diagnosis itself (attribution, another code path)
        assert whole.before == pytest.approx(
            diagnosed.diagnosis.held_out_rmse[("nominal", "D300", channel)], rel=1e-12)
        assert whole.after == pytest.approx(
            diagnosed.diagnosis.held_out_rmse[(label, "D300", channel)], rel=1e-12)
        # the phases after touchdown partition the record from touchdown, so their mean
        # squares, weighted by samples, make up the whole-record error
        parts = [r for r in rows if r.channel == channel and r.phase not in (WHOLE, "free fall")]
        assert sum(r.samples for r in parts) == whole.samples
        for attribute in ("before", "after"):
            combined = math.sqrt(sum(r.samples * getattr(r, attribute) ** 2 for r in parts)
                                 / whole.samples)
            assert combined == pytest.approx(getattr(whole, attribute), rel=1e-9)
    load = next(r for r in rows if r.channel == "load" and r.phase == WHOLE)
    assert load.after < 0.5 * load.before, load


def test_the_gap_results_are_plain_json_and_csv(diagnosed, with_hysteresis, tmp_path):
    from certkit.evidence.model_evidence import ModelEvidence
    from certkit.physics.calibration import Calibration

    document = gap_document(diagnosed)
    text = json.dumps(document, allow_nan=False)
    assert json.loads(text)["answer"] == list(diagnosed.diagnosis.answer)
    evidence = ModelEvidence(Calibration((), ()), "", gap={"left-main": diagnosed})
    campaign = load_campaign(with_hysteresis)
    report_module.write_tables(assess(campaign), tmp_path / "tables", evidence)
    with (tmp_path / "tables" / "gap.csv").open(encoding="utf-8") as handle:
        cells = list(csv.DictReader(handle))
    assert len(cells) == len(diagnosed.before.cells)
    with (tmp_path / "tables" / "gap_shrink.csv").open(encoding="utf-8") as handle:
        shrink = list(csv.DictReader(handle))
    assert len(shrink) == len(diagnosed.held_out_errors)
    for row in shrink:
        before, after = float(row["rmse_before"]), float(row["rmse_after"])
        if before > 0:
            assert float(row["shrink_percent"]) == pytest.approx(100 * (1 - after / before))
        assert row["unit"] == ("N" if row["channel"] == "load" else "m")


def test_the_gap_section_lays_out_the_diagnosis(diagnosed, with_hysteresis):
    from certkit.evidence.model_evidence import ModelEvidence
    from certkit.evidence.provenance import provenance
    from certkit.physics.calibration import Calibration

    campaign = load_campaign(with_hysteresis)
    evidence = ModelEvidence(Calibration((), ()), "", gap={"left-main": diagnosed},
                             gap_notes=("right-main: not diagnosed. Example note.",))
    html = report_module.render_html(report_module.build_view(
        assess(campaign), provenance(campaign.inputs), evidence))
    # an appendix after the body, which ends with the references
    section = html[html.index('<section id="gap" class="appendix">'):]
    assert html.index('<section id="references">') < html.index('<section id="model"')
    assert "Appendix C. Sim-to-real gap" in section and "10. Methods" in html
    assert "12. Provenance" in html
    assert "This appendix is not compliance evidence" in section
    assert diagnosed.diagnosis.statement in section
    assert "right-main: not diagnosed. Example note." in section
    # the map before, the held-out overlay, the missing force, the map that remains
    assert section.count("<svg") == 4
    assert "the force the calibrated bare model misses, from the records alone" in section
    assert "loop ∝ static curve × sign(δ̇)" in section      # the shapes' table
    assert ("the default (every drop at the highest drop height held out, and at the middle "
            "one from 4 heights up)") in section          # holdout.MIDDLE_FROM = 4
    # thresholds are the code's, not typed into the template
    from certkit.gap.selection import RELEVANT
    assert f"would remove at least {RELEVANT:g} σ" in section
    # no blind check recorded for this campaign: the section says how to make one
    assert "has not been recorded for this campaign" in section
    assert f"python benchmarks/blind_independent.py {with_hysteresis.name} -g GEAR -o DIR" \
        in section


# --------------------------------------------------------------------------- blind check
def _with_blind_check(spec: Path, record: Path, name: str) -> Path:
    folder = spec.parent / "blind"
    folder.mkdir(exist_ok=True)
    shutil.copyfile(record, folder / record.name)
    return variant(spec, name, gap=f"{{blind_check: blind/{record.name}}}")


def test_the_blind_check_record_is_a_hashed_input(with_hysteresis):
    campaign = load_campaign(_with_blind_check(with_hysteresis, BLIND, "blind.yaml"))
    item = next(i for i in campaign.inputs if i.name == "blind/blind_check.json")
    assert item.sha256 == hashlib.sha256(BLIND.read_bytes()).hexdigest()
    assert campaign.blind_check.metrics["top1"].judged is False   # 0.80 < 0.85


@pytest.mark.parametrize("change, words", [
    (lambda r: r["metrics"]["top1"].update(met=True), "metrics.top1: met is true"),
    (lambda r: r.update(kind="something else"), "kind: expected 'certkit blind check'"),
    (lambda r: r["confusion"]["counts"].pop(), "confusion: counts must have one row per truth"),
    (lambda r: r["metrics"]["harm_rate"].pop("cases"), "metrics.harm_rate.cases: field required"),
    (lambda r: r["metrics"]["top1"].update(interval=[0.5]),
     "interval must be (low, high) with 0 ≤ low ≤ high ≤ 1"),
    (lambda r: r["metrics"]["top1"].update(interval=[0.9, 0.2]),
     "interval must be (low, high) with 0 ≤ low ≤ high ≤ 1"),
    (lambda r: r["settings"].update(scored_from="2"), "settings.scored_from must be a number"),
])
def test_a_bad_blind_check_record_is_an_input_error_naming_the_key(with_hysteresis, tmp_path,
                                                                   change, words):
    record = json.loads(BLIND.read_text(encoding="utf-8"))
    change(record)
    bad = tmp_path / "bad_check.json"
    bad.write_text(json.dumps(record), encoding="utf-8")
    spec = _with_blind_check(with_hysteresis, bad, "bad-blind.yaml")
    with pytest.raises(CertkitInputError) as error:
        load_campaign(spec)
    problem = error.value.problems[0]
    assert problem.key == "model.gap.blind_check" and problem.line is not None
    assert words in problem.message.replace("Field required", "field required"), problem.message


def test_the_report_summarises_the_blind_check_and_says_what_falls_short(with_hysteresis,
                                                                         tmp_path):
    from certkit.evidence.model_evidence import ModelEvidence
    from certkit.physics.calibration import Calibration

    spec = _with_blind_check(with_hysteresis, BLIND, "blind-report.yaml")
    out = tmp_path / "out"
    # model evidence with no gear diagnosed: the gap appendix with the record, nothing else
    render_report(assess(load_campaign(spec)), out, model=ModelEvidence(Calibration((), ()), ""))
    html = (out / "report.html").read_text(encoding="utf-8")
    section = html[html.index("How far the diagnosis can be trusted"):]
    # the record's fractions as percentages: 24 of 30 = 80.0 % against at least 85 %
    assert "80.0 %" in section and "24 of 30 cases" in section and "at least 85.0 %" in section
    assert "NOT met" in section and section.count(">met<") == 3
    assert ("Short of target: top-1 accuracy 80.0 % against a target of at least 85.0 %"
            in section)
    assert "harm rate" in section and "3.0 %" in section and "at most 10.0 %" in section
    # the curve and the confusion matrix: the 5× row and the one case named "cannot tell apart"
    assert "90.0 %" in section and "cannot tell apart" in section
    # no gear unit was diagnosed: said, not hidden
    assert "No gear unit was diagnosed." in html
    record = json.loads((out / "results.json").read_text(encoding="utf-8"))["provenance"]
    names = {i["file"]: i["sha256"] for i in record["inputs"]}
    assert names["blind/blind_check.json"] == hashlib.sha256(BLIND.read_bytes()).hexdigest()


def test_the_report_gives_a_metric_as_its_record_defines_it(with_hysteresis, tmp_path):
    """A record that counts a metric its own way (the independent battery's abstention since
    crosstalk a gain reads as is scored apart) is printed with its own definition, not
    certkit's general one; a metric it does not define keeps the general one."""
    from certkit.evidence.model_evidence import ModelEvidence
    from certkit.physics.calibration import Calibration
    from certkit.spec.blind_record import METRICS

    record = json.loads(BLIND.read_text(encoding="utf-8"))
    record["definitions"] = {"harm_rate": "harm as this record counts it, stated here"}
    defined = tmp_path / "blind_check_defined.json"
    defined.write_text(json.dumps(record), encoding="utf-8")
    spec = _with_blind_check(with_hysteresis, defined, "blind-defined.yaml")
    out = tmp_path / "out"
    render_report(assess(load_campaign(spec)), out, model=ModelEvidence(Calibration((), ()), ""))
    html = (out / "report.html").read_text(encoding="utf-8")
    section = html[html.index("How far the diagnosis can be trusted"):]
    assert "harm as this record counts it, stated here" in section
    assert METRICS["harm_rate"][1] not in section
    assert METRICS["top1"][1] in section


def test_the_report_states_the_recorded_decisions_and_derives_none():
    # decisions whose figures and thresholds no rule of today's code has: the report must
    # state them as recorded, so a change of the rules can never be mis-described by it
    from types import SimpleNamespace

    from certkit.evidence.gap_view import _gap_steps
    from certkit.gap.attribution import Attribution, Decision, Score
    from certkit.spec.schema import DisplayUnits

    attribution = Attribution(
        scores=(Score("seal friction", 12.0, 1.0, 1.0, 0.5),
                Score("tyre hysteresis", 3.0, -1.0, 1.0, 0.1)),
        confusability={}, sigma2=1.0, profiles=None, relevant=(),
        decisions=(Decision("seal friction", "not leading", {"leading": 7}),
                   Decision("tyre hysteresis", "points the other way", {"gain": 0.77})),
        no_refit=Decision("", "none refitted", {"relevant": 4.5, "gain": 0.66}))
    fit = SimpleNamespace(effects=("seal friction",), strengths=(1.0,), strength_errors=(0.1,),
                          training_cost=0.95)
    diagnosis = SimpleNamespace(steps=[(attribution, [fit])], step_costs=(1.0,),
                                refit_decisions=((Decision("seal friction", "gain",
                                                           {"cut": 0.05, "gain": 0.33}),),),
                                answer=())
    gap = SimpleNamespace(diagnosis=diagnosis, refit_held_out={})
    step = _gap_steps(gap, DisplayUnits())[0]
    statuses = {s["effect"]: s["status"] for s in step["scores"]}
    assert statuses["tyre hysteresis"] == ("its score points the other way and its profile "
                                           "cuts the training cost by less than 77 %: not "
                                           "relevant")
    assert statuses["seal friction"] == ("relevant, not among the 7 effects with the best "
                                         "profiles")
    assert step["refits"][0]["outcome"] == ("cuts the training cost by 5.0 %, less than 33 %: "
                                            "not named")
    assert step["no_refit"] == ("No candidate would remove 4.5 σ or more, nor cut the training "
                                "cost by 66 % in its profile: none was refitted.")


def test_the_report_gives_the_sealed_figures_beside_the_development_ones(with_hysteresis,
                                                                           tmp_path):
    from certkit.evidence.model_evidence import ModelEvidence
    from certkit.physics.calibration import Calibration

    development = json.loads(BLIND.read_text(encoding="utf-8"))
    development["battery"] = "development"
    sealed = json.loads(BLIND.read_text(encoding="utf-8"))
    sealed["battery"] = "sealed"
    # the sealed battery's top-1: 17 of 25 = 68.0 % (interval from the record as written)
    sealed["metrics"]["top1"].update(value=0.68, count=17, cases=25, interval=[0.485, 0.83])
    folder = with_hysteresis.parent / "blind"
    folder.mkdir(exist_ok=True)
    (folder / "dev.json").write_text(json.dumps(development), encoding="utf-8")
    (folder / "sealed.json").write_text(json.dumps(sealed), encoding="utf-8")
    spec = variant(with_hysteresis, "blind-sealed.yaml",
                   gap="{blind_check: blind/dev.json, sealed_blind_check: blind/sealed.json}")
    campaign = load_campaign(spec)
    # both records are hashed inputs
    assert {"blind/dev.json", "blind/sealed.json"} <= {i.name for i in campaign.inputs}
    out = tmp_path / "out"
    render_report(assess(campaign), out, model=ModelEvidence(Calibration((), ()), ""))
    html = (out / "report.html").read_text(encoding="utf-8")
    section = html[html.index("Sealed battery (held out) beside the development battery"):]
    row = section[section.index("top-1 accuracy"):section.index("</tr>",
                                                                section.index("top-1 accuracy"))]
    # development 24 of 30 (the record's), sealed 17 of 25 with its interval; the sealed
    # verdict against at least 85 %
    assert "80.0 % (24 of 30" in row and "68.0 % (17 of 25; 95 % interval 48.5 %–83.0 %)" in row
    assert "NOT met" in row
    assert "These cases are a sealed battery" in html
    results = json.loads((out / "results.json").read_text(encoding="utf-8"))
    assert results["model"]["gap"]["sealed_blind_check"]["metrics"]["top1"]["count"] == 17
    assert results["model"]["gap"]["sealed_blind_check"]["battery"] == "sealed"
    # naming the records leaves the template's fingerprint as it was
    from certkit.spec.blind_record import template_fingerprint
    assert template_fingerprint(campaign) == template_fingerprint(load_campaign(with_hysteresis))


def test_a_bad_sealed_record_is_an_input_error_naming_its_own_key(with_hysteresis, tmp_path):
    record = json.loads(BLIND.read_text(encoding="utf-8"))
    record["kind"] = "something else"
    folder = with_hysteresis.parent / "blind"
    folder.mkdir(exist_ok=True)
    (folder / "bad-sealed.json").write_text(json.dumps(record), encoding="utf-8")
    spec = variant(with_hysteresis, "bad-sealed.yaml",
                   gap="{sealed_blind_check: blind/bad-sealed.json}")
    with pytest.raises(CertkitInputError) as error:
        load_campaign(spec)
    problem = error.value.problems[0]
    assert problem.key == "model.gap.sealed_blind_check" and problem.line is not None
    assert "expected 'certkit blind check'" in problem.message


def test_the_method_text_says_which_shapes_the_refits_fit():
    # before: it called the gain memoryless and said nothing of the skew (fitted since
    # 2026-11-26) or of the tyre loop's onset (fitted since 2026-11-27)
    from certkit import load_campaign
    from certkit.evidence.methods import gap_method

    from .conftest import SEED

    units = load_campaign(SEED).spec.report.units   # mm and ms, as the seed displays them
    text = " ".join(str(v) for v in gap_method(units).values())
    assert "without memory" not in text
    assert "the load-cell gain with its channel's skew (within ±1.000 ms" in text
    assert "with its onset (the deflection over which it switches, 0.5000 mm to 10.00 mm)" \
        in text


def test_results_json_states_every_threshold_of_the_diagnosis_and_its_starts():
    """Each numeric rule constant of the naming rules (certkit.gap.selection's __all__) and
    of the further starts is in results.json's thresholds under its own key, with its
    value: a reviewer reads there what the decisions were judged against."""
    import numbers

    from certkit.gap import selection
    from certkit.gap.diagnosis import THRESHOLDS
    from certkit.physics import starts
    from certkit.physics.drops import MIDDLE_FROM

    keys = {"RELEVANT": "relevant_explained_rms_noise_units",
            "LEADING": "leading_candidates_refitted",
            "GAIN": "gain_training_cost_share",
            "TIE_COST": "tie_training_cost_ratio",
            "DETECTABLE": "detectable_noise_variances_removed",
            "TIMING_SHARE": "timing_share_of_channel_mean_square",
            "PULSE_SHARE": "load_pulse_share_of_peak",
            "RECALIBRATE": "recalibrate_training_cost_share",
            "RESTARTS": "calibrations_again_at_most",
            "NOMINAL_STARTS": "nominal_calibration_further_starts",
            "START_EVALUATIONS": "further_start_evaluations_at_most",
            "KEEP_MARGIN": "further_start_keep_margin_share"}
    rules = {name for name, value in vars(selection).items()
             if name.isupper() and isinstance(value, numbers.Real)
             and not isinstance(value, bool)}
    assert rules == set(keys) - {"START_EVALUATIONS", "KEEP_MARGIN"}, rules ^ set(keys)
    for name, key in keys.items():
        value = getattr(selection, name, None)
        value = getattr(starts, name) if value is None else value
        assert THRESHOLDS[key] == value, name
    assert THRESHOLDS["middle_height_held_out_from_heights"] == MIDDLE_FROM
    assert len(THRESHOLDS) == len(keys) + 1


def test_a_blind_check_setting_left_unset_reads_as_a_dash():
    """The record's ``only: []`` (the battery ran whole) is "—" in the settings table, not
    an empty cell; other settings read as before."""
    from certkit.evidence.gap_view import plain_setting

    assert plain_setting([]) == plain_setting(None) == plain_setting({}) == "—"
    assert plain_setting(["gain-skew", "none"]) == "gain-skew, none"
    assert plain_setting({"S1": [1.0, 2.0], "S2": 3}) == "S1: 1 + 2; S2: 3"
    assert plain_setting(0.25) == "0.25" and plain_setting(0) == "0"
