"""The independent battery's load-cell crosstalk, sized twice (issue 27): by its whole load
change, most of which a load-cell gain reproduces, and by the part no gain explains; a
crosstalk that reads as a gain within the noise may be answered by the gain, any other
only by an abstention."""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))

import blind_independent as independent  # noqa: E402
import truthgen  # noqa: E402
from blindcheck import sizing  # noqa: E402
from blindcheck.battery import Settings  # noqa: E402

from certkit import load_campaign  # noqa: E402
from certkit.compliance.clauses import ideal_impact_velocity  # noqa: E402
from certkit.gap.phases import segment  # noqa: E402

EXAMPLE = "campaigns/seed-amphibian/campaign.yaml"


def _pulse(time, amplitude=10_000.0, width=0.15):
    """A half-sine load pulse from t = 0 (a drop's first compression, roughly)."""
    return np.where((time >= 0) & (time <= width), amplitude * np.sin(np.pi * time / width),
                    0.0)


def _crossing(time, signal, at):
    """When ``signal`` first rises through ``at``, between the two samples around it."""
    i = int(np.argmax(signal > at))
    return time[i - 1] + (at - signal[i - 1]) / (signal[i] - signal[i - 1]) * (
        time[i] - time[i - 1])


def _aligned(time, record, reference, at):
    """``record`` moved so that it rises through ``at`` when ``reference`` does."""
    shift = _crossing(time, record, at) - _crossing(time, reference, at)
    return np.interp(time + shift, time, record)


def _beyond_best_gain(changed, plain, windows, at):
    """The RMS that remains of ``changed`` beyond the best (1 + ε)·F of ``plain`` ((time, F)
    per run), both aligned on their rise through ``at``: a bounded search on ε written
    apart from the battery's."""
    def remains(gain):
        return math.sqrt(np.mean([np.mean((c[w] - _aligned(t, (1 + gain) * f, f, at)[w]) ** 2)
                                  for c, (t, f), w in zip(changed, plain, windows)]))
    return minimize_scalar(remains, bounds=(-0.5, 1.0), method="bounded",
                           options={"xatol": 1e-8}).fun


def _beyond_best_gain_unaligned(record, plain):
    """What the best gain leaves of ``record`` if nothing aligned it: the skew's own part."""
    return minimize_scalar(lambda g: math.sqrt(np.mean((record - (1 + g) * plain) ** 2)),
                           bounds=(-0.5, 1.0), method="bounded").fun


def test_on_the_touchdown_aligned_load_a_gain_with_a_skew_is_the_gain_alone():
    time = np.arange(-0.05, 0.4, 1e-3)
    plain = _pulse(time)
    at, window = 120.0, slice(None)
    for skew in (0.0, 4e-4, -7e-4):
        recorded = _aligned(time, 1.03 * _pulse(time - skew), plain, at)
        whole = math.sqrt(np.mean((recorded - plain) ** 2))        # about 3 % of the RMS load
        remains = sizing.beyond_gain([recorded], [(time, plain)], [window], at)
        # the skew is aligned away with the touchdown: what remains is the linear
        # interpolation's smoothing of the pulse's onset between samples (a few N of its
        # 10 kN), not the skew itself, which unaligned the best gain would leave (35-80 N)
        unaligned = _beyond_best_gain_unaligned(1.03 * _pulse(time - skew), plain)
        assert remains < 0.2 * unaligned or remains < 1e-3, (skew, remains, unaligned)
        assert unaligned > 0.25 * whole or skew == 0.0
    # a crosstalk of 10 % of the load 12 ms earlier: what remains is what a bounded search
    # written here finds
    crosstalk = plain + 0.1 * _pulse(time - 0.012)
    found = sizing.beyond_gain([crosstalk], [(time, plain)], [window], at)
    assert found == pytest.approx(_beyond_best_gain([crosstalk], [(time, plain)], [window], at),
                                  rel=1e-3)
    # it is what the crosstalk's timing adds: less than its whole change, not nothing
    whole = math.sqrt(np.mean((crosstalk - plain) ** 2))
    assert 0.05 * whole < found < 0.7 * whole
    # a shorter delay is more nearly a gain
    shorter = plain + 0.1 * _pulse(time - 0.004)
    assert sizing.beyond_gain([shorter], [(time, plain)], [window], at) < 0.5 * found


def test_a_crosstalk_sized_beyond_the_gain_leaves_its_multiple_of_the_noise_there():
    """The battery's size for a crosstalk of 12 ms at 2 × noise, measured by what no gain
    explains, checked by simulating the drops here, aligning them on the detector's level
    with a crossing search written here, and fitting the gain by a bounded search."""
    campaign = load_campaign(EXAMPLE)
    settings = Settings()
    shape = (("delay", 0.012),)
    size = sizing.effect_sizes(campaign, "left-main", "crosstalk", shape, [2.0], settings,
                               measure=sizing.BEYOND_GAIN)[2.0]
    whole = sizing.effect_sizes(campaign, "left-main", "crosstalk", shape, [2.0], settings)[2.0]
    # sized by its whole change, 2 × noise is a crosstalk of under 1 %; beyond the gain,
    # several times that
    assert whole < 0.01 and size > 3 * whole
    level = sizing.detector_level(campaign, "left-main", settings)
    changed, plain_runs, windows = [], [], []
    for index, run in enumerate(campaign.spec.runs):
        if "left-main" not in run.gear_units:
            continue
        gear = sizing.gear_of(campaign, run, "left-main")
        speed = ideal_impact_velocity(run.drop_height.si)
        plain = truthgen.simulate(gear, speed, 1000.0, drop_index=index)
        crossed = truthgen.simulate(gear, speed, 1000.0, drop_index=index,
                                    truths=(truthgen.Truth("crosstalk", size, shape),))
        changed.append(_aligned(plain.time, crossed.load, plain.load, level))
        plain_runs.append((plain.time, plain.load))
        cycle = {p.name: p for p in segment(plain.time, plain.load, plain.stroke,
                                            (gear.upper_mass + gear.lower_mass) * 9.80665)}
        windows.append(slice(cycle["tyre-only contact"].start, cycle["rebound"].stop))
    assert len(changed) >= 2
    remains = _beyond_best_gain(changed, plain_runs, windows, level)
    assert remains == pytest.approx(2.0 * settings.load_noise, rel=0.05)


def _outcome(forms, named, measure="load", ratio=2.0, beyond=None, harmed=False):
    outside = any(truthgen.FORMS[f].effect is None for f in forms)
    outcome = {"id": "x", "forms": list(forms), "measure": measure, "outside": outside,
               "truth": [truthgen.FORMS[f].effect for f in forms
                         if truthgen.FORMS[f].effect is not None],
               "ratio": ratio, "seed": 1, "named": named, "statement": "",
               "error": None, "skipped": None, "before": 100.0,
               "after": 50.0 if named else 100.0, "shrink": 0.5 if named else 0.0,
               "closed": 0.9 if named else None, "harmed": harmed, "harmed_any": harmed,
               "physical": {}}
    if beyond is not None:
        outcome["beyond_gain_noise"] = beyond
    return outcome


def test_a_crosstalk_that_reads_as_a_gain_within_the_noise_may_be_answered_by_the_gain():
    """Counted by hand.  Outside the library, right: an abstention (gas drift once, crosstalk
    three times), or the load-cell gain named first for a crosstalk of which less than
    2 × noise is beyond the gain (0.6 × and 1.99 ×), harming no held-out channel.  Wrong:
    friction for gas drift; sensor lag for a crosstalk within the gain's noise; the gain
    for crosstalk 2.0 × and 5 × beyond it (sized so, or by its whole change); the gain that
    harms a channel; the gain named second; the gain for a record without the measure.
    Answered right 6 of 14; abstained 4 of 14."""
    beyond = sizing.BEYOND_GAIN
    gain = "load-cell gain"
    outcomes = [
        _outcome(("lugre",), ["seal friction"]),
        _outcome(("gas-drift",), []),
        _outcome(("gas-drift",), ["seal friction"]),
        _outcome(("crosstalk",), [], beyond, beyond=2.0),
        _outcome(("crosstalk",), [gain], beyond, beyond=1.9999999999999658),   # as sized
        _outcome(("crosstalk",), [gain], beyond, 5.0, beyond=5.0),
        _outcome(("crosstalk",), [gain], beyond=0.6),
        _outcome(("crosstalk",), [gain], ratio=5.0, beyond=1.99),
        _outcome(("crosstalk",), [gain], ratio=5.0, beyond=2.3),
        _outcome(("crosstalk",), ["sensor lag"], beyond=0.7),
        _outcome(("crosstalk",), [gain], beyond=0.7, harmed=True),
        _outcome(("crosstalk",), [], beyond=0.5),
        _outcome(("crosstalk",), ["sensor lag", gain], ratio=5.0, beyond=1.2),
        _outcome(("crosstalk",), [gain]),                  # a record without the measure
    ]
    outcomes[-1].pop("beyond_gain_noise", None)
    outcomes.insert(4, _outcome(("crosstalk",), [], beyond, 5.0, beyond=5.0))
    result = independent.score(outcomes)
    m = result["metrics"]
    answered = m["outside_library_answered"]
    assert (answered["count"], answered["cases"]) == (6, 14)
    assert answered["met"] is False and answered["target"] == 0.8
    strict = m["abstention_out_of_library"]
    assert (strict["count"], strict["cases"]) == (4, 14) and strict["target"] is None
    rows = {row["form"]: row for row in result["forms"]}
    assert (rows["crosstalk"]["right"], rows["crosstalk"]["cases"]) == (3, 8)
    assert (rows["crosstalk (beyond gain)"]["right"],
            rows["crosstalk (beyond gain)"]["cases"]) == (2, 4)
    assert (rows["gas-drift"]["right"], rows["gas-drift"]["cases"]) == (1, 2)
    assert rows["crosstalk"]["effect"] is None
    assert "only an abstention is right" in rows["crosstalk (beyond gain)"]["label"]
    assert set(result["definitions"]) == {"abstention_out_of_library",
                                          "outside_library_answered"}
    assert "less than twice the load noise" in result["definitions"]["outside_library_answered"]


def test_every_plan_has_crosstalk_sized_both_ways_and_the_earlier_cases_keep_their_ids():
    from blindcheck.plans import S4

    cases = independent.battery(independent.PLANS["development"])
    # every plan but one restricted by itself to some forms (S8L: the sensor lag's)
    for plan in [p for p in independent.PLANS["development"] + independent.PLANS["sealed"]
                 if not p.only]:
        mine = independent.battery(plan)
        beyond = [c for c in mine if c.measure == sizing.BEYOND_GAIN]
        assert {(c.forms, c.ratio, c.seed) for c in beyond} == {
            (("crosstalk",), r, s) for r in plan.outside_ratios for s in plan.seeds}
        whole = {(c.forms, c.ratio, c.seed) for c in mine
                 if c.forms == ("crosstalk",) and c.measure == "load"}
        assert whole == {(c.forms, c.ratio, c.seed) for c in beyond}
        # a case sized beyond the gain has its own id and random streams
        assert not {c.id for c in beyond} & {c.id for c in mine if c.measure == "load"}
        assert not {c.key for c in beyond} & {c.key for c in mine if c.measure == "load"}
    # S4's record, run before crosstalk was sized beyond the gain, holds exactly the cases of
    # S4 sized by the load change, under the same ids
    record = BENCHMARKS / "records" / "seed-S4-2d308a8" / "blind-check.json"
    kept = [o["id"] for o in json.loads(record.read_text(encoding="utf-8"))["cases"]]
    assert kept == [c.id for c in cases if c.plan is S4 and c.measure == "load"]
