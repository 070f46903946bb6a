"""The blind check (benchmarks/blindcheck, benchmarks/blind_*.py: battery machinery kept out of
certkit): its battery, its truths withheld and sized, its scoring by hand, and the same
outcome on a process pool and on a dask cluster."""

import json
import math
import statistics
import sys
from pathlib import Path

import numpy as np
import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))

from blindcheck.battery import (TRUTHS, Case, Settings, battery, blind_check,  # noqa: E402
                                run_case, size_for, write_case)
from blindcheck.scoring import score as _score  # noqa: E402

from certkit import load_campaign  # noqa: E402
from certkit.compliance.clauses import ideal_impact_velocity  # noqa: E402
from certkit.physics.gear_model import drop_model_for  # noqa: E402
from certkit.physics.simulation import simulate_reference  # noqa: E402


def score(outcomes, effects=tuple(TRUTHS)):
    return _score(outcomes, effects)

EXAMPLE = "campaigns/seed-amphibian/campaign.yaml"


def test_the_default_battery_meets_the_issues_minimum_and_hides_the_truth():
    cases = battery()
    single = [c for c in cases if len(c.truths) == 1]
    # ≥ 5 effects × ≥ 6 cases at effect/noise ≥ 2, plus ≥ 6 no-effect cases
    at_two = {e: sum(c.truths == (e,) and c.ratio >= 2 for c in single) for e in TRUTHS}
    assert len(at_two) >= 5 and min(at_two.values()) >= 6, at_two
    assert sum(not c.truths for c in cases) >= 6
    assert any(len(c.truths) == 2 for c in cases)
    assert {c.ratio for c in single} >= {1.0, 2.0, 5.0}
    # case ids are hashes: nothing in them (nor their order) says what the truth is
    for case in cases:
        assert case.id.startswith("case-") and len(case.id) == 15
        assert not any(word in case.id for name in TRUTHS for word in name.split())
    assert battery() == cases and len({c.id for c in cases}) == len(cases)
    # every case has its own seed for noise, offsets and scatter
    assert len({c.key for c in cases}) == len(cases)


def test_every_truth_differs_from_its_candidate_where_the_library_allows():
    from certkit.gap.attribution import CANDIDATES

    assert set(TRUTHS) <= {c.name for c in CANDIDATES}
    differs = [name for name, t in TRUTHS.items() if "own form" not in t.form]
    assert len(differs) >= 5, differs


def _outcome(truth, ratio, named, before=100.0, after=50.0, statement="", closed=None,
             error=None):
    return {"id": "x", "truth": truth, "ratio": ratio, "named": named, "statement": statement,
            "before": before, "after": after, "shrink": 1 - after / before, "closed": closed,
            "harmed": bool(named) and after > before, "harmed_any": bool(named) and after > before,
            "error": error}


def test_scores_counted_by_hand():
    tie = "tyre hysteresis and seal friction cannot be told apart with these channels"
    outcomes = [
        _outcome(["seal friction"], 2.0, ["seal friction"], 100, 40, closed=0.9),     # right
        _outcome(["seal friction"], 5.0, ["seal friction", "sensor lag"], 100, 20,
                 closed=1.0),                                                  # right, not exact
        _outcome(["tyre hysteresis"], 2.0, ["rebound orifice"], 100, 90, closed=0.2),  # wrong
        _outcome(["tyre hysteresis"], 5.0, [], 100, 100, tie),                 # a tie: wrong
        _outcome(["sensor lag"], 1.0, [], 100, 100),                           # below 2: curve only
        _outcome([], None, [], 20, 20),                                        # clean abstention
        _outcome([], None, ["heat transfer"], 20, 21),                         # false, harmful
        _outcome([], None, [], 20, 20, tie),                                   # a tie: false
        _outcome([], None, [], 20, 20, "failed: X", error="X"),                # a failure: false
        _outcome(["seal friction", "tyre hysteresis"], 5.0, ["seal friction", "leg flexibility"],
                 100, 70, closed=0.5),
    ]
    outcomes[8].update(before=None, after=None)          # as run_case leaves a failure
    result = score(outcomes, ("seal friction", "tyre hysteresis", "rebound orifice",
                              "sensor lag", "heat transfer", "leg flexibility"))
    m = result["metrics"]
    assert (m["top1"]["count"], m["top1"]["cases"]) == (2, 4) and m["top1"]["value"] == 0.5
    assert m["top1"]["met"] is False                         # 50 % < 85 %
    assert (m["exact"]["count"], m["exact"]["cases"]) == (1, 4)
    # no-effect cases: one clean abstention of four
    assert (m["false_attribution"]["count"], m["false_attribution"]["cases"]) == (3, 4)
    assert m["false_attribution"]["met"] is False            # 75 % > 10 %
    # pair: named {friction, leg}, truth {friction, hysteresis}: 1 of 2 right each way
    assert m["set_precision"]["value"] == 0.5 and m["set_recall"]["value"] == 0.5
    # single-effect cases at ratio ≥ 2: shrinks 0.6, 0.8, 0.1 and the tie's 0 → median 0.35
    assert m["median_shrink"]["value"] == pytest.approx(0.35)
    assert m["median_shrink"]["cases"] == 4 and m["median_shrink"]["met"] is False
    assert m["median_shrink_pairs"]["value"] == pytest.approx(0.3)
    # gap closed: 0.9, 1.0, 0.2 and the tie's nothing (0) → median 0.55
    assert m["median_gap_closed"]["value"] == pytest.approx(0.55)
    # harmed: the false attribution (21 > 20), out of the 5 cases that named an effect
    assert (m["harm_rate"]["count"], m["harm_rate"]["cases"]) == (1, 5)
    curve = {point["ratio"]: point for point in result["curve"]}
    assert curve[1.0]["cases"] == 1 and curve[1.0]["top1"] == 0.0
    assert curve[2.0]["top1"] == 0.5 and curve[2.0]["median_shrink"] == pytest.approx(
        statistics.median([0.6, 0.1]))
    confusion = result["confusion"]
    row = confusion["truths"].index("tyre hysteresis")
    counts = dict(zip(confusion["named"], confusion["counts"][row]))
    assert counts["rebound orifice"] == 1 and counts["cannot tell apart"] == 1
    none = dict(zip(confusion["named"], confusion["counts"][confusion["truths"].index("none")]))
    assert none["none"] == 1 and none["heat transfer"] == 1
    assert none["cannot tell apart"] == 1 and none["failed"] == 1
    # every single-effect and no-effect case is in the matrix once
    assert sum(map(sum, confusion["counts"])) == 9
    assert result["failed"] == ["x"]


@pytest.mark.parametrize("name", ["tyre hysteresis", "sensor lag"])
def test_an_effect_is_sized_to_its_multiple_of_the_noise(name):
    """Sized with the fast path; checked with the reference integrator (LSODA), over each
    run's first compression and rebound (touchdown to the end of the rebound, as
    certkit.gap.phases finds them on the run without the effect)."""
    from certkit.gap.phases import segment

    campaign = load_campaign(EXAMPLE)
    runs = [r for r in campaign.spec.runs if "left-main" in r.gear_units]
    models = [drop_model_for(campaign.spec, r, "left-main", effects=[]) for r in runs]
    speeds = [ideal_impact_velocity(r.drop_height.si) for r in runs]
    truth = TRUTHS[name]
    size = size_for(truth, models, speeds, 40.0, 1000.0, 2.0)
    squares = []
    for model, speed in zip(models, speeds):
        plain = simulate_reference(model, speed, 2.0, 1000.0, lead=0.0)
        changed = simulate_reference(truth.model(model, size), speed, 2.0, 1000.0, lead=0.0)
        load, time = changed.load, changed.time
        phases = {p.name: p for p in segment(time, plain.load, plain.stroke,
                                             model.total_mass * 9.80665)}
        cycle = slice(phases["tyre-only contact"].start, phases["rebound"].stop)
        if truth.sensor:
            # the recorder's delay is absorbed by aligning on the touchdown (2 % of the
            # unit's weight, found here by a plain search for the first sample above it)
            recorded = truth.recorder(size).apply(time, load)
            level = 0.02 * (model.upper_mass + model.lower_mass) * 9.80665

            def crossing(signal):
                i = int(np.argmax(signal > level))
                return time[i - 1] + (level - signal[i - 1]) / (signal[i] - signal[i - 1]) * (
                    time[i] - time[i - 1])

            shift = crossing(recorded) - crossing(plain.load)
            aligned = np.interp(time + shift, time, recorded)
            squares.append(np.mean((aligned[cycle] - plain.load[cycle]) ** 2))
        else:
            squares.append(np.mean((load[cycle] - plain.load[cycle]) ** 2))
    assert np.sqrt(np.mean(squares)) == pytest.approx(40.0, rel=0.05)


def test_a_written_case_names_no_effect_and_carries_the_sized_truth(tmp_path):
    settings = Settings()
    case = Case("case-007", ("tyre hysteresis",), 5.0, 3)
    spec, sizes = write_case(EXAMPLE, "left-main", case, settings, tmp_path)
    text = spec.read_text(encoding="utf-8")
    template_text = open(EXAMPLE, encoding="utf-8").read()
    for name in TRUTHS:       # no more mentions than the template's own (model.effects)
        for spelling in (name, name.replace(" ", "-")):
            assert text.count(spelling) <= template_text.count(spelling), spelling
    written = load_campaign(spec)
    template = load_campaign(EXAMPLE)
    assert written.spec.model.effects == template.spec.model.effects   # the spec as given
    assert all(r.data.origin == "synthetic" for r in written.spec.runs)
    assert sizes["tyre hysteresis"] > 0
    # the zero offsets written into the spec are off by at most the zero error, plus the
    # scatter of a 50-sample median of the noise: its standard error is 1.2533·σ/√50, and
    # 4·σ/7 is 3.2 of those
    loads = [written.series[r.id].gears["left-main"].load for r in written.spec.runs]
    assert max(abs(np.median(x[:50])) for x in loads) < \
        settings.load_zero_error + 4 * settings.load_noise / 7


@pytest.fixture(scope="module")
def pool_outcome():
    case = Case("case-001", ("seal friction",), 5.0, 1)
    return case, blind_check(EXAMPLE, "left-main", cases=[case], workers=1)


@pytest.mark.slow   # a battery case, tens of seconds: CI runs it
def test_a_strong_effect_is_named_and_the_held_out_error_shrinks(pool_outcome):
    _, document = pool_outcome
    outcome = document["cases"][0]
    assert outcome["named"][:1] == ["seal friction"], outcome["statement"]
    # the truth's load change is 5 × 20 N RMS over the runs; the held-out error after the
    # effect is added comes down towards the 20 N noise
    assert outcome["before"] > 60 and outcome["after"] < 0.5 * outcome["before"]
    assert document["metrics"]["top1"]["cases"] == 1


@pytest.mark.slow
def test_a_dask_cluster_gives_the_same_outcome_as_the_process_pool(pool_outcome):
    distributed = pytest.importorskip("distributed")
    case, document = pool_outcome
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        remote = blind_check(EXAMPLE, "left-main", cases=[case],
                             scheduler=cluster.scheduler_address)
    assert json.dumps(remote, sort_keys=True) == json.dumps(document, sort_keys=True)


@pytest.mark.slow   # a battery case, tens of seconds: CI runs it
def test_run_case_without_an_effect_abstains():
    outcome = run_case(EXAMPLE, "left-main", Case("case-002", (), None, 100))
    assert outcome["named"] == [], outcome["statement"]
    assert outcome["after"] == outcome["before"]


@pytest.mark.slow   # a battery case, tens of seconds: CI runs it
def test_an_effect_whose_score_points_the_wrong_way_is_found_by_its_profile():
    """Fast heat exchange of a γ = 1.4 gas: at zero strength the candidate's signature
    (γ = the calibrated n) points away from the residual, so the score test ranks it last;
    the profile over finite strengths, with the knobs' re-tuning projected out, finds it
    and the refit recovers the truth's size (strength = 1/τ in 1/s)."""
    outcome = run_case(EXAMPLE, "left-main", Case("case-034", ("heat transfer",), 5.0, 1))
    assert outcome["named"] == ["heat transfer"], outcome["statement"]
    assert outcome["after"] < 0.5 * outcome["before"]


def test_wilson_intervals_match_their_closed_forms():
    from blindcheck.scoring import wilson

    z2 = 1.959964 ** 2
    # none of n: upper bound z²/(n + z²); all of n: lower bound n/(n + z²)
    assert wilson(0, 12) == pytest.approx([0.0, z2 / (12 + z2)])
    assert wilson(36, 36) == pytest.approx([36 / (36 + z2), 1.0])
    # one of three (Wilson 1927 form, worked by hand): centre (1/3 + z²/6)/(1 + z²/3) =
    # 0.42692, half-width 0.36542
    low, high = wilson(1, 3)
    assert low == pytest.approx(0.06149, abs=1e-4) and high == pytest.approx(0.79234, abs=1e-4)
    assert wilson(0, 0) is None


@pytest.mark.slow   # a battery case, tens of seconds: CI runs it
def test_the_record_and_its_case_table_are_written_as_the_report_reads_them(pool_outcome,
                                                                            tmp_path):
    import csv

    from blindcheck.record import write_blind_check
    from certkit.spec.blind_record import BlindCheckRecord

    _, document = pool_outcome
    write_blind_check(document, tmp_path)
    text = (tmp_path / "blind-check.json").read_text(encoding="utf-8")
    record = BlindCheckRecord.model_validate_json(text)       # the report's own schema
    assert record.metrics["top1"].count == 1 and record.template.gear == "left-main"
    rows = list(csv.DictReader((tmp_path / "blind-check-cases.csv").open(encoding="utf-8")))
    outcome = document["cases"][0]
    assert rows[0]["truth"] == "seal friction" and rows[0]["case"] == "case-001"
    assert float(rows[0]["shrink [%]"]) == pytest.approx(
        100 * (1 - outcome["after"] / outcome["before"]), rel=1e-3)
    # the same document gives the same bytes
    second = tmp_path / "second"
    second.mkdir()
    write_blind_check(json.loads(text), second)
    assert (second / "blind-check.json").read_bytes() == \
        (tmp_path / "blind-check.json").read_bytes()


@pytest.mark.parametrize("option, value", [("--seeds", "one,two"), ("--ratios", "")])
def test_bad_battery_options_exit_2_with_a_message(option, value):
    import subprocess

    done = subprocess.run([sys.executable, str(BENCHMARKS / "blind_own.py"), EXAMPLE,
                           option, value, "-o", "unused"], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2
    assert option in done.stderr and "comma-separated numbers" in done.stderr


def test_battery_options_are_checked_before_the_battery_runs(tmp_path, monkeypatch, capsys):
    import blind_own

    def ran(*args, **kwargs):
        raise AssertionError("the battery ran before its options were checked")

    monkeypatch.setattr(blind_own, "blind_check", ran)
    monkeypatch.setattr(sys, "argv", ["blind_own.py", EXAMPLE, "--workers", "0",
                                      "-o", str(tmp_path / "bc")])
    with pytest.raises(SystemExit) as stop:
        blind_own.main()
    assert stop.value.code == 2
    assert "--workers: expected a whole number ≥ 1, found 0" in capsys.readouterr().err
    # an output folder that would swallow the campaign is refused at once, not after hours
    monkeypatch.setattr(sys, "argv", ["blind_own.py", EXAMPLE, "-o",
                                      str(Path(EXAMPLE).parent)])
    assert blind_own.main() == 2
    assert "would contain the input" in capsys.readouterr().err


def test_only_picks_forms_and_the_no_effect_cases_and_a_plans_own_restriction_stays(
        monkeypatch, capsys):
    """``--only gain-skew,none``: each plan's gain-with-skew cases, then its no-effect cases,
    the same cases (ids, seeds) as the whole battery holds; without ``--only`` a plan
    restricted by itself keeps its restriction, and the command names no ``--only``."""
    from dataclasses import replace

    import blind_independent as independent
    from blindcheck.plans import PLANS, Plan

    whole = independent.battery(independent.plans_of("development"))
    plans = independent.plans_of("development", ("gain-skew", "none"))
    picked = independent.battery(plans)
    expected = [c.id for c in whole if c.forms == ("gain-skew",) and c.measure == "load"
                or (c.forms == () and c.ratio is None)]
    assert [c.id for c in picked] == expected
    per_plan = {p.name: [c for c in picked if c.plan.name == p.name] for p in plans}
    for plan in PLANS["development"]:
        cases = per_plan[plan.name]
        # 3 ratios × 2 seeds, then the plan's 20 no-effect cases in their seeds' order
        assert [c.forms for c in cases] == [("gain-skew",)] * 6 + [()] * plan.null_cases
        assert [c.seed for c in cases[6:]] == list(range(plan.null_seeds,
                                                         plan.null_seeds + plan.null_cases))
    assert independent._command("x/c.yaml", "g", plans) == \
        "python benchmarks/blind_independent.py c.yaml -g g --battery development " \
        "--only gain-skew,none -o DIR"

    own = Plan(battery="sealed", name="T", seeds=(5, 6), only=("bessel-delay",))
    monkeypatch.setitem(PLANS, "sealed", (PLANS["sealed"][0], own))
    kept = independent.plans_of("sealed")
    assert kept[1] is own and kept[0] is PLANS["sealed"][0]
    assert {c.forms for c in independent.battery(kept[1])} == {("bessel-delay",)}
    assert "--only" not in independent._command("c.yaml", "g", kept)
    # --only keeps of a plan's own restriction only what it holds, and leaves out a plan
    # that holds none of it: the cases picked are always cases of the whole battery
    assert independent.plans_of("sealed", ("gain-skew",)) == (
        replace(PLANS["sealed"][0], only=("gain-skew",)),)
    both = independent.plans_of("sealed", ("bessel-delay", "gain-skew"))
    assert [p.only for p in both] == [("bessel-delay", "gain-skew"), ("bessel-delay",)]
    whole_sealed = {c.id for c in independent.battery(kept)}
    assert {c.id for c in independent.battery(both)} <= whole_sealed
    # the command names the --only given, though the plans are restricted differently
    assert independent._command("c.yaml", "g", both, only=("bessel-delay", "gain-skew")) == \
        "python benchmarks/blind_independent.py c.yaml -g g --battery sealed " \
        "--only bessel-delay,gain-skew -o DIR"

    monkeypatch.setattr(sys, "argv", ["blind_independent.py", EXAMPLE, "-g", "left-main",
                                      "--only", "gain-skew,nothing", "-o", "unused"])
    with pytest.raises(SystemExit) as refused:
        independent.main()
    assert refused.value.code == 2
    assert "--only: unknown forms ['nothing']" in capsys.readouterr().err


def test_the_lsa_rigs_no_effect_record_holds_the_development_batterys_no_effect_cases():
    """benchmarks/records/lsa-none-development: the development battery's no-effect cases
    of every plan, in order, as --only none makes them; its false attribution is the count
    of its cases that named an effect."""
    import blind_independent as independent

    record = json.loads((BENCHMARKS / "records" / "lsa-none-development" /
                         "blind-check.json").read_text(encoding="utf-8"))
    cases = independent.battery(independent.plans_of("development", ("none",)))
    assert [o["id"] for o in record["cases"]] == [c.id for c in cases]
    assert len(cases) == 120 and all(o["forms"] == [] for o in record["cases"])
    assert record["run_by"]["command"].endswith("--battery development --only none -o DIR")
    named = sum(1 for o in record["cases"] if o["named"])
    metric = record["metrics"]["false_attribution"]
    assert (metric["count"], metric["cases"]) == (named, 120)


RECORD = "campaigns/seed-amphibian/blind-check/blind-check.json"


@pytest.mark.slow
def test_the_examples_blind_check_record_is_what_this_code_gives():
    """The committed record (the independent battery of benchmarks/blind_independent.py,
    its development plan and the spent sealed set S1, about 200 cases, 15 minutes) is
    spot-checked: two of its cases are run again here, and its metrics are those its score()
    gives for its cases (a check that the file was not edited by hand)."""
    import blind_independent as independent

    with open(RECORD, encoding="utf-8") as handle:
        record = json.load(handle)
    from certkit.gap.code import code_fingerprint
    from certkit.spec.blind_record import template_fingerprint

    # made from this spec (its content without the key naming the record); whether by this
    # code the report says in words (code_fingerprint), the two cases below check outcomes
    assert record["template"]["sha256"] == template_fingerprint(load_campaign(EXAMPLE))
    assert len(record["template"]["code"]) == len(code_fingerprint()) == 64
    assert "benchmarks/truthgen" in record["truths"]
    cases = {c.id: c for c in independent.battery(independent.PLANS["development"])}
    assert record["settings"]["cases"] == len(cases)
    assert [o["id"] for o in record["cases"]] == list(cases)
    picked = [c for c in cases.values()
              if (c.forms, c.ratio, c.seed) in ((("dahl",), 2.0, 31),
                                                (("bessel-delay",), 2.0, 7101))]
    assert len(picked) == 2
    template = str(Path(EXAMPLE).resolve())
    for case in picked:
        kept = next(o for o in record["cases"] if o["id"] == case.id)
        again = independent.run_case(template, "left-main", case, Settings())
        assert again["named"] == kept["named"] and again["truth"] == kept["truth"]
        assert again["contact_phases"] == kept["contact_phases"]
        for key in ("before", "after", "shrink", "closed"):
            assert again[key] == pytest.approx(kept[key], rel=1e-6), key
        assert again["sizes"] == pytest.approx(kept["sizes"], rel=1e-6)
    rescored = independent.score(record["cases"])
    assert json.dumps(rescored["metrics"], sort_keys=True) == json.dumps(record["metrics"],
                                                                        sort_keys=True)
    assert rescored["confusion"] == record["confusion"]


SEALED_RECORD = "campaigns/seed-amphibian/blind-check-sealed/blind-check.json"
#: S5's record, run once while S5 was sealed and kept as it was measured
KEPT_SEALED = BENCHMARKS / "records" / "seed-S5-c8840fe" / "blind-check.json"


def _s5_sealed_again(monkeypatch) -> Path:
    """The sealed battery made S5 again, for the checks of the runner's machinery that read
    a kept sealed record (they need not move when a new sealed set is drawn); returns the
    record's path."""
    from dataclasses import replace

    from blindcheck.plans import PLANS, S5

    monkeypatch.setitem(PLANS, "sealed", (replace(S5, battery="sealed"),))
    return KEPT_SEALED


@pytest.mark.slow
def test_the_examples_sealed_record_is_what_this_code_gives():
    """The sealed record (run once): its cases are the sealed plan's, one drawn case run
    again gives its answer and numbers, and its metrics are what score() gives."""
    import blind_independent as independent

    with open(SEALED_RECORD, encoding="utf-8") as handle:
        record = json.load(handle)
    assert record["battery"] == "sealed"
    cases = {c.id: c for c in independent.battery(independent.PLANS["sealed"])}
    assert [o["id"] for o in record["cases"]] == list(cases)
    # a friction case, and a gain whose load lags by nearly a sample (0.95 ms in S3's draw)
    seeds = independent.PLANS["sealed"][0].seeds
    template = str(Path(EXAMPLE).resolve())
    for forms, seed in ((("lugre",), seeds[-1]), (("gain-skew",), seeds[0])):
        case = next(c for c in cases.values() if (c.forms, c.ratio, c.seed) == (forms, 5.0, seed))
        kept = next(o for o in record["cases"] if o["id"] == case.id)
        again = independent.run_case(template, "left-main", case, Settings())
        assert again["named"] == kept["named"] and again["shapes"] == kept["shapes"]
        assert again["statement"] == kept["statement"]
        for key in ("before", "after", "shrink"):
            assert again[key] == pytest.approx(kept[key], rel=1e-6), key
    rescored = independent.score(record["cases"])
    assert json.dumps(rescored["metrics"], sort_keys=True) == json.dumps(record["metrics"],
                                                                        sort_keys=True)


def test_a_template_the_diagnosis_cannot_use_exits_2_before_any_case_runs(monkeypatch, capsys,
                                                                          tmp_path):
    import blind_own

    monkeypatch.setattr(sys, "argv", ["blind_own.py", EXAMPLE, "-g", "nose",
                                      "-o", str(tmp_path / "bc")])
    assert blind_own.main() == 2
    assert "gear unit nose has no drop with time histories" in capsys.readouterr().err
    assert not (tmp_path / "bc").exists()


def test_a_rescore_keeps_who_ran_the_cases(tmp_path, monkeypatch):
    """A record scored again by other code still says who ran its cases: the run's
    fingerprint, commit and date stay, and only scored_by is the scoring certkit's."""
    import blind_independent as independent

    from certkit.gap.code import code_fingerprint
    from certkit.spec.blind_record import read_blind_check

    example = BENCHMARKS.parent / EXAMPLE

    committed = _s5_sealed_again(monkeypatch)
    earlier = json.loads(committed.read_text(encoding="utf-8"))
    ran = {"certkit": "0.0.9", "code": "a" * 64, "commit": "b" * 40, "date": "2026-01-02",
           "files": {"gap/selection.py": "c" * 64}, "command": "the run's command"}
    earlier["run_by"] = ran
    earlier["template"]["code"] = ran["code"]
    source = tmp_path / "earlier.json"
    source.write_text(json.dumps(earlier), encoding="utf-8")
    monkeypatch.setattr(sys, "argv", ["blind_independent.py", str(example), "-g", "left-main",
                                      "--battery", "sealed", "-o", str(tmp_path / "out"),
                                      "--rescore", str(source)])
    assert independent.main() == 0
    record = read_blind_check(tmp_path / "out" / "blind-check.json")
    assert record.run_by.model_dump(exclude_none=True) == ran and record.template.code == "a" * 64
    assert record.scored_by.code == code_fingerprint() != record.run_by.code
    assert record.scored_by.command.endswith("--rescore RECORD")
    # the cases are the earlier ones, untouched
    assert record.cases == earlier["cases"]


def _resumable_battery(monkeypatch):
    """blind_independent with its cases run in this process by a fake that returns the
    sealed record's outcome of each case (with tuples, as a fresh case's lists need not be),
    stopping after ``stop[0]`` cases when that is set; and a function running the quick
    sealed battery into a folder.  The source tree is taken as committed (a developer's
    may not be, and a run from such a tree is not resumed)."""
    import blind_independent as independent
    import blindcheck.record

    monkeypatch.setattr(blindcheck.record, "git_commit", lambda: "c" * 40)

    kept = {o["id"]: o for o in json.loads(
        _s5_sealed_again(monkeypatch).read_text(encoding="utf-8"))["cases"]}
    calls, stop = [], [None]

    def fake(template, gear_id, case, settings):
        calls.append(case.id)
        if stop[0] is not None and len(calls) > stop[0]:
            raise KeyboardInterrupt("the session ended")
        return dict(kept[case.id], forms=tuple(kept[case.id]["forms"]),
                    named=tuple(kept[case.id]["named"]))

    monkeypatch.setattr(independent, "run_case", fake)

    def run(folder, *extra):
        monkeypatch.setattr(sys, "argv", ["blind_independent.py", EXAMPLE, "-g", "left-main",
                                          "--battery", "sealed", "--quick", "--workers", "1",
                                          "-o", str(folder), *extra])
        return independent.main()

    return run, calls, stop


def _stopped_run(run, calls, stop, folder, after):
    """Run into ``folder`` stopped after ``after`` cases; its progress file's lines."""
    from blindcheck.progress import NAME

    calls.clear()
    stop[0] = after
    with pytest.raises(KeyboardInterrupt):
        run(folder)
    stop[0] = None
    assert not (folder / "blind-check.json").exists()
    lines = (folder / NAME).read_text(encoding="utf-8").splitlines()
    assert len(lines) == 1 + after
    return lines


def test_a_run_stopped_part_way_resumes_into_the_record_one_run_makes(tmp_path, monkeypatch,
                                                                     capsys):
    """A battery stopped twice and resumed twice runs each case once, and its record holds
    the cases and figures one uninterrupted run gives; a line the stop cut short is dropped
    and its case run again; the run's provenance names the day it started and the day of
    each resume, and is the uninterrupted run's in every other respect."""
    from blindcheck.progress import NAME

    run, calls, stop = _resumable_battery(monkeypatch)
    assert run(tmp_path / "whole") == 0
    whole = json.loads((tmp_path / "whole" / "blind-check.json").read_text(encoding="utf-8"))
    cases = len(calls)
    assert cases == whole["settings"]["cases"] > 4
    assert whole["run_by"]["command"].endswith("--battery sealed --quick -o DIR")
    assert not (tmp_path / "whole" / NAME).exists()

    folder = tmp_path / "part"
    lines = _stopped_run(run, calls, stop, folder, 2)
    head = json.loads(lines[0])
    head["run_by"]["date"] = "2000-01-01"          # the run began on another day
    progress = folder / NAME
    progress.write_text("\n".join([json.dumps(head)] + lines[1:]) + "\n" + '{"id": "case-cut',
                        encoding="utf-8")

    # resumed, stopped again after one more case, resumed again
    calls.clear()
    stop[0] = 1
    with pytest.raises(KeyboardInterrupt):
        run(folder, "--resume")
    stop[0] = None
    lines = progress.read_text(encoding="utf-8").splitlines()
    assert len(lines) == 1 + 3
    # the resume wrote its day into the header: a later resume keeps it
    assert json.loads(lines[0])["run_by"]["date"] == f"2000-01-01 and {whole['run_by']['date']}"
    calls.clear()
    capsys.readouterr()
    assert run(folder, "--resume") == 0
    assert len(calls) == cases - 3
    assert "(resumed: 3 cases had run before)" in capsys.readouterr().out
    resumed = json.loads((folder / "blind-check.json").read_text(encoding="utf-8"))
    assert not progress.exists()
    assert resumed["cases"] == whole["cases"]
    assert resumed["metrics"] == whole["metrics"]
    assert resumed["run_by"]["date"] == f"2000-01-01 and {whole['run_by']['date']}"
    assert {k: v for k, v in resumed["run_by"].items() if k != "date"} == \
        {k: v for k, v in whole["run_by"].items() if k != "date"}


@pytest.mark.parametrize("change, differing", [
    (lambda h: h["run_by"].update(code="f" * 64), "run_by.code"),
    (lambda h: h["run_by"]["files"].update({"gap/selection.py": "0" * 64}), "run_by.files"),
    (lambda h: h["run_by"]["battery_files"].update({"truthgen/forms.py": "0" * 64}),
     "run_by.battery_files"),
    (lambda h: h["run_by"].update(commit="1" * 40), "run_by.commit"),
    (lambda h: h["run_by"].update(command="python benchmarks/blind_independent.py x"),
     "run_by.command"),
    (lambda h: h["run_by"].update(certkit="0.0.1"), "run_by.certkit"),
    (lambda h: h.update(template="0" * 64), "template"),
    (lambda h: h.update(gear="right-main"), "gear"),
    (lambda h: h["environment"].update(python="3.10.0"), "environment"),
    (lambda h: h["environment"].update(numpy="1.0.0"), "environment"),
    (lambda h: h.update(cases=h["cases"][:-1]), "cases"),
])
def test_a_stopped_run_resumes_only_as_itself(tmp_path, monkeypatch, capsys, change, differing):
    """A resume by other code, command, template, environment or battery exits 2 naming
    what differs, and so does a new run over a stopped one; the progress is kept."""
    from blindcheck.progress import NAME

    run, calls, stop = _resumable_battery(monkeypatch)
    folder = tmp_path / "part"
    lines = _stopped_run(run, calls, stop, folder, 2)
    capsys.readouterr()
    with pytest.raises(SystemExit) as refused:
        run(folder)
    assert refused.value.code == 2
    assert "--resume continues it" in capsys.readouterr().err
    head = json.loads(lines[0])
    change(head)
    text = "\n".join([json.dumps(head)] + lines[1:]) + "\n"
    (folder / NAME).write_text(text, encoding="utf-8")
    with pytest.raises(SystemExit) as refused:
        run(folder, "--resume")
    assert refused.value.code == 2
    assert f"is another run than this one (differing: {differing})" in capsys.readouterr().err
    assert (folder / NAME).read_text(encoding="utf-8") == text
    assert len(calls) == 3             # the stopped run's: the refused ones ran no case


def test_a_run_from_a_tree_with_uncommitted_changes_is_not_resumed(tmp_path, monkeypatch,
                                                                   capsys):
    from blindcheck.progress import NAME

    run, calls, stop = _resumable_battery(monkeypatch)
    folder = tmp_path / "part"
    lines = _stopped_run(run, calls, stop, folder, 2)
    head = json.loads(lines[0])
    head["run_by"]["commit"] = "a" * 40 + "-dirty"
    (folder / NAME).write_text(json.dumps(head) + "\n", encoding="utf-8")
    capsys.readouterr()
    with pytest.raises(SystemExit) as refused:
        run(folder, "--resume")
    assert refused.value.code == 2
    assert "started from a source tree with uncommitted changes" in capsys.readouterr().err


def test_the_report_names_the_files_that_differ_from_the_running_certkit():
    from certkit.evidence.gap_view import _made_by
    from certkit.gap.code import code_files, code_fingerprint
    from certkit.spec.blind_record import Provenance

    files = code_files()
    now = Provenance(certkit="0.1.0", code=code_fingerprint(), files=files, date="2026-11-26")
    assert _made_by("Its cases were run", now, code_fingerprint()) == \
        "Its cases were run by certkit 0.1.0 on 2026-11-26, with this certkit's diagnosis code."
    other = dict(files, **{"gap/selection.py": "0" * 64})
    other.pop("gap/phases.py")
    then = Provenance(certkit="0.0.9", code="f" * 64, files=other, commit="1234567890abcdef")
    sentence = _made_by("They were scored", then, code_fingerprint())
    assert sentence.startswith("They were scored by certkit 0.0.9 at commit 1234567890ab, "
                               "with other diagnosis code than this certkit's (the files that "
                               "differ: gap/phases.py, gap/selection.py)")
    # what the reader can do: run a development battery again; a sealed set is run once,
    # so its record is not to be run again: the next sealed set measures this code
    assert sentence.endswith("so the figures describe that code: run the command again to "
                             "measure this one.")
    from certkit.evidence.gap_view import DRAW_ANEW
    assert _made_by("Its cases were run", then, code_fingerprint(), DRAW_ANEW).endswith(
        "so the figures describe that code: a sealed set is run once, so a new sealed set, "
        "drawn for this code, will measure this one.")
    # a run from a source tree with uncommitted changes says so (the commit alone would not)
    dirty = Provenance(certkit="0.1.0", code=code_fingerprint(), files=files,
                       commit="1234567890abcdef-dirty")
    assert _made_by("Its cases were run", dirty, code_fingerprint()) == (
        "Its cases were run by certkit 0.1.0 at commit 1234567890ab (with uncommitted changes "
        "in the source tree), with this certkit's diagnosis code.")
    older = Provenance(certkit="0.0.9", code="f" * 64)     # a record from before per-file hashes
    assert "which files differ is not recorded" in _made_by("Its cases were run", older,
                                                            code_fingerprint())


def test_the_sealed_battery_is_drawn_apart_from_the_development_one():
    import blind_independent as independent
    import truthgen
    from blindcheck.plans import NUISANCE_RANGES, S1, S2, S3, S4, S5, S6, S8, S8L, draws

    development, sealed = independent.PLANS["development"], independent.PLANS["sealed"]
    dev_cases, sealed_cases = independent.battery(development), independent.battery(sealed)
    # S1 to S6, spent, are part of the development battery with their own seeds; S8 and
    # its supplement S8L are sealed (S7, run once by code lost before it landed, is in no
    # battery and its seeds are not reused)
    assert {S1, S2, S3, S4, S5, S6} <= set(development) and sealed == (S8, S8L)
    assert {c.seed for c in dev_cases if c.plan is S1} == {7101, 7102} | set(range(7500, 7520))
    assert {c.seed for c in dev_cases if c.plan is S2} == {9101, 9102} | set(range(9500, 9520))
    assert {c.seed for c in dev_cases if c.plan is S3} == {9301, 9302} | set(range(9700, 9720))
    assert {c.seed for c in dev_cases if c.plan is S4} == {12401, 12402} | set(range(12800,
                                                                                   12820))
    assert {c.seed for c in dev_cases if c.plan is S5} == {14401, 14402} | set(range(14800,
                                                                                   14820))
    assert {c.seed for c in dev_cases if c.plan is S6} == {16401, 16402} | set(range(16800,
                                                                                   16820))
    assert {c.seed for c in sealed_cases} == {20401, 20402, 20403, 20404} | set(range(20800,
                                                                                     20820))
    assert not {c.seed for c in dev_cases + sealed_cases} & (set(range(18401, 18405))
                                                              | set(range(18800, 18820)))
    # S8L holds the sensor lag's two forms only, so the sealed battery holds the 8 cases of
    # sensor lag at 2 × noise issue 27's target counts
    assert {c.forms for c in sealed_cases if c.plan is S8L} == {("bessel-delay",),
                                                               ("butterworth-delay",)}
    lag = [c for c in sealed_cases if c.forms in (("bessel-delay",), ("butterworth-delay",))
           and c.ratio == 2.0]
    assert len(lag) == 8 and len(sealed_cases) == 110 + 12
    # S5's record, kept as it was run while S5 was sealed, holds exactly S5's cases, in order
    kept = BENCHMARKS / "records" / "seed-S5-c8840fe" / "blind-check.json"
    assert [o["id"] for o in json.loads(kept.read_text(encoding="utf-8"))["cases"]] == \
        [c.id for c in dev_cases if c.plan is S5]
    # at least as many cases as a development plan; no seed, no case id in common
    assert len(sealed_cases) >= len(independent.battery(development[0])) >= 106
    assert not {c.seed for c in dev_cases} & {c.seed for c in sealed_cases}
    assert not {c.id for c in dev_cases} & {c.id for c in sealed_cases}
    # the development plan uses every form's development shape and nuisances
    for case in dev_cases[:5]:
        shapes, nuisances = draws(case.key, case.forms, case.plan)
        assert all(shape == () for shape in shapes) and nuisances == truthgen.Nuisances()
    # a drawn case draws every shape parameter inside its plan's range, and the same again
    drawn = {}
    for case in sealed_cases + [c for c in dev_cases if c.plan in (S1, S2, S3, S4, S5, S6)]:
        shapes, nuisances = draws(case.key, case.forms, case.plan)
        assert (shapes, nuisances) == draws(case.key, case.forms, case.plan)
        for form_id, shape in zip(case.forms, shapes):
            ranges = {n: (lo, hi) for n, lo, hi in case.plan.shape_ranges(form_id)}
            assert set(dict(shape)) == set(ranges)
            for name, value in shape:
                assert ranges[name][0] <= value <= ranges[name][1], (form_id, name, value)
                if name == "order":
                    assert value == int(value)       # a filter's order is a whole number
                drawn.setdefault((case.plan.name, form_id, name), set()).add(value)
        for name, low, high in NUISANCE_RANGES:
            assert low <= getattr(nuisances, name) <= high
    # ... and not one value: the shapes vary from case to case
    assert all(len(values) > 1 for values in drawn.values()), drawn
    # S2's own ranges where its change concerned them: the skew may lead, the filters differ
    assert min(drawn[("S2", "gain-skew", "skew")]) < 0 < max(drawn[("S2", "gain-skew", "skew")])
    assert S2.shape_ranges("bessel-delay") == (("order", 3, 8), ("delay_share", 0.25, 1.5))
    # S3's: the skew leads or lags by up to 1 ms; the filters' ranges are S2's
    assert dict((n, (lo, hi)) for n, lo, hi in S3.shape_ranges("gain-skew"))["skew"] == \
        (-1e-3, 1e-3)
    assert S3.shape_ranges("bessel-delay") == S2.shape_ranges("bessel-delay")
    assert all(S4.shape_ranges(f) == S3.shape_ranges(f) == S5.shape_ranges(f)
               == S6.shape_ranges(f) == S8.shape_ranges(f) == S8L.shape_ranges(f)
               for f in truthgen.FORMS)
    assert S1.shape_ranges("bessel-delay") == truthgen.FORMS["bessel-delay"].shape_ranges


def test_every_case_has_its_own_contact_phases_between_two_samples():
    """A logger's clock is not the drop's: each drop's contact falls anywhere between two
    samples, drawn from the case's seed, the same for the same case."""
    import blind_independent as independent
    from blindcheck.plans import contact_phases

    cases = independent.battery(independent.PLANS["sealed"])
    phases = [contact_phases(c.key, 3) for c in cases]
    assert phases[0] == contact_phases(cases[0].key, 3)
    values = np.array(phases).ravel()
    assert np.all((values >= 0) & (values < 1))
    # spread over the sample interval, not all on a sample
    assert np.histogram(values, bins=4, range=(0, 1))[0].min() > 0.15 * values.size


def test_a_truth_reads_its_own_shape_or_its_forms_development_value():
    import truthgen

    default = truthgen.Truth("lugre", 10.0)
    assert default.value("static_ratio") == 1.4 and default.value("stribeck_speed") == 0.02
    own = truthgen.Truth("lugre", 10.0, (("static_ratio", 1.9),))
    assert own.value("static_ratio") == 1.9 and own.value("stribeck_speed") == 0.02


def test_the_independent_battery_sizes_an_effect_where_the_diagnosis_aligns():
    """An effect's "2 × noise" is what an analysis that aligns on the measured touchdown can
    see: the load change over the first cycle with the touchdowns aligned where the
    diagnosis's detector reads them, on records sampled as the logger samples them.  Here:
    the detector's level on the battery's records is 6 × √(20² + 1²/12) N = 120.0125 N (the
    noise and its 1 N quantisation; 2 % of 292.5 kgf is only 57.4 N), and a Bessel lag sized
    for 2 × 20 N moves the first cycle by 40 N once the two records are aligned there by a
    plain crossing search written here; aligned at 2 % of the weight, as the battery did
    before, the same lag shows more than that."""
    import truthgen
    from blindcheck import sizing

    campaign = load_campaign(EXAMPLE)
    level = sizing.detector_level(campaign, "left-main", Settings())
    assert level == pytest.approx(6 * math.sqrt(20.0 ** 2 + 1.0 / 12), abs=1e-9)
    phases = (0.37, 0.81, 0.12)
    size = sizing.effect_sizes(campaign, "left-main", "bessel-delay", (), [2.0], Settings(),
                               truthgen.Nuisances(), phases)[2.0]
    from certkit.gap.phases import segment

    def crossing(time, signal, at):
        i = int(np.argmax(signal > at))
        return time[i - 1] + (at - signal[i - 1]) / (signal[i] - signal[i - 1]) / 1000.0

    changes = {level: [], 0.02 * 292.5 * 9.80665: []}
    runs = [r for r in campaign.spec.runs if "left-main" in r.gear_units]
    for index, run in enumerate(campaign.spec.runs):
        if run not in runs:
            continue
        gear = sizing.gear_of(campaign, run, "left-main")
        speed = ideal_impact_velocity(run.drop_height.si)
        plain = truthgen.simulate(gear, speed, 1000.0, drop_index=index, phase=phases[index])
        lagged = truthgen.simulate(gear, speed, 1000.0, drop_index=index, phase=phases[index],
                                   truths=(truthgen.Truth("bessel-delay", size),))
        time = plain.time
        cycle = {p.name: p for p in segment(time, plain.load, plain.stroke,
                                            (gear.upper_mass + gear.lower_mass) * 9.80665)}
        window = slice(cycle["tyre-only contact"].start, cycle["rebound"].stop)
        for at, squares in changes.items():
            shift = crossing(time, lagged.load, at) - crossing(time, plain.load, at)
            aligned = np.interp(time + shift, time, lagged.load)
            squares.append(np.mean((aligned[window] - plain.load[window]) ** 2))
    at_detector, at_two_percent = (math.sqrt(np.mean(v)) for v in changes.values())
    assert at_detector == pytest.approx(40.0, rel=0.03)
    assert at_two_percent > 1.2 * at_detector


@pytest.mark.slow
def test_a_tyre_loop_beside_friction_that_harms_the_load_is_stated_undecided():
    """S2's pair of LuGre friction and a Bouc–Wen tyre loop at 5 × (seed 9101, now in the
    development battery), written by the independent simulator: the diagnosis names the
    friction; the loop's refit cuts the training cost further but makes the training load
    worse beyond its noise, so it is not named and the answer says the records cannot tell
    whether it is present too (through a real diagnosis, not only the rule's sentence)."""
    import blind_independent as independent
    from blindcheck.plans import S2

    case = next(c for c in independent.battery(independent.PLANS["development"])
                if c.plan is S2 and c.forms == ("lugre", "tyre-bouc-wen") and c.seed == 9101)
    outcome = independent.run_case(str(Path(EXAMPLE).resolve()), "left-main", case,
                                   Settings())
    assert outcome["truth"] == ["seal friction", "tyre hysteresis"]
    assert outcome["named"] == ["seal friction"]
    assert outcome["undecided"] == ["tyre hysteresis"]
    assert ("Beside seal friction, tyre hysteresis" in outcome["statement"]
            and "it is not named, and these records cannot tell whether it is present too"
            in outcome["statement"])


@pytest.mark.slow
def test_a_nominal_calibration_in_a_local_minimum_is_escaped_before_effects_are_judged():
    """S3's no-effect case of seed 9706 (now in the development battery), written by the
    independent simulator: its top-out pad compresses 1.6 mm under the preload (the case's
    drawn nuisance), and the calibration from the spec's values alone stops with the pad's
    compression near its lower bound, a local minimum: started instead from the truth's
    pad compression (a start the diagnosis does not know), the same calibration fits the
    training runs more than 2 % better.  The diagnosis named tyre hysteresis here once (it
    closed 86 % of the held-out gap, on no effect).  Its nominal calibration, from the
    spec's values and NOMINAL_STARTS further starts, reaches the truth-started fit's cost,
    and the diagnosis names nothing; handed the stuck calibration, it names nothing either.
    (The rule that calibrates again from a refit's parameters is checked on costs set by
    hand in test_attribution: on this case, since the fits' step and the further starts
    changed, no refit leaves the stuck calibration's basin by its 2 %.)"""
    import tempfile

    import blind_independent as independent
    from blindcheck.plans import S3, draws

    from certkit.gap.holdout import split_for
    from certkit.gap.selection import diagnose, nominal_calibration
    from certkit.physics.calibration import calibrate_gear
    from certkit.physics.synthetic import SensorModel

    case = next(c for c in independent.battery(independent.PLANS["development"])
                if c.plan is S3 and c.forms == () and c.seed == 9706)
    _, nuisances = draws(case.key, (), S3)
    assert nuisances.pad == pytest.approx(1.596e-3, rel=1e-3)
    settings = Settings()
    noisy = SensorModel(settings.load_noise, settings.load_step, settings.load_offset,
                        settings.travel_noise, settings.travel_step, settings.travel_offset,
                        load_zero_error=settings.load_zero_error,
                        travel_zero_error=settings.travel_zero_error)
    with tempfile.TemporaryDirectory() as folder:
        written = independent.write_case(str(Path(EXAMPLE).resolve()), "left-main", case, (),
                                         Path(folder), noisy, "noisy", nuisances)
        campaign = load_campaign(written)
        training = list(split_for(campaign, "left-main")[0])
        stuck = calibrate_gear(campaign, "left-main", effects=[], run_ids=training)
        names = [knob.name for knob in stuck.knobs]
        start = list(stuck.fit.estimate)
        start[names.index("top-out-compression")] = nuisances.pad
        from_truth = calibrate_gear(campaign, "left-main", effects=[], run_ids=training,
                                    start=start)
        production = nominal_calibration(campaign, "left-main", training)
        handed = diagnose(campaign, "left-main", calibration=stuck)
        diagnosis = diagnose(campaign, "left-main", calibration=production)
    assert stuck.fit.estimate[names.index("top-out-compression")] < 0.1e-3
    assert from_truth.fit.cost < 0.98 * stuck.fit.cost
    assert production.fit.cost <= 1.001 * from_truth.fit.cost
    assert diagnosis.answer == () and diagnosis.recalibrated == ()
    assert diagnosis.statement.endswith("No effect in the library explains the gap.")
    assert handed.answer == ()


def test_the_floor_is_the_better_of_two_calibrations_of_the_bare_case(monkeypatch):
    """The floor of a case is the nominal model calibrated on its bare records from the
    nominal values (and the diagnosis's further starts) or from where the diagnosis's
    calibration ended, whichever fits better (the diagnosis's own calibration may have
    been done again out of a poorer fit)."""
    from types import SimpleNamespace

    from blindcheck import truth_gap

    from certkit.gap.selection import NOMINAL_STARTS

    made = []

    def calibrate_gear(campaign, gear_id, knobs=None, effects=None, run_ids=None, start=None,
                       starts=0):
        made.append((knobs, run_ids, start, starts))
        return SimpleNamespace(fit=SimpleNamespace(cost=costs[len(made) - 1]))

    monkeypatch.setattr(truth_gap, "calibrate_gear", calibrate_gear)
    diagnosis = SimpleNamespace(training=("D1", "D2"), calibration=SimpleNamespace(
        knobs=(SimpleNamespace(name="k1"),), fit=SimpleNamespace(estimate=(7.0,))))
    costs = [0.02, 0.01]
    assert truth_gap.floor_calibration("bare", "g", diagnosis).fit.cost == 0.01
    assert NOMINAL_STARTS == 16
    assert made == [(None, ["D1", "D2"], None, 16), (["k1"], ["D1", "D2"], [7.0], 0)]
    made.clear()
    costs = [0.01, 0.02]
    assert truth_gap.floor_calibration("bare", "g", diagnosis).fit.cost == 0.01
