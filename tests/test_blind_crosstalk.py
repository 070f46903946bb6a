"""The independent battery's load-cell crosstalk, sized twice (issue 27): by its whole load
change, most of which a load-cell gain with a skew reproduces, and by the part no gain
with a skew explains; only the second is a case outside the library that must abstain."""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import CubicSpline
from scipy.optimize import minimize_scalar

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))

import blind_independent as independent  # noqa: E402
import truthgen  # noqa: E402
from blindcheck.battery import Settings  # noqa: E402

from certkit import load_campaign  # noqa: E402
from certkit.compliance.clauses import ideal_impact_velocity  # noqa: E402
from certkit.gap.phases import segment  # noqa: E402

EXAMPLE = "campaigns/seed-amphibian/campaign.yaml"


def _pulse(time, amplitude=10_000.0, width=0.15):
    """A half-sine load pulse from t = 0 (a drop's first compression, roughly)."""
    return np.where((time >= 0) & (time <= width), amplitude * np.sin(np.pi * time / width),
                    0.0)


def _best_gain_and_skew(changed, plain_of, windows):
    """The RMS that remains of ``changed`` beyond the best (1 + ε)·F(t − τ), |τ| ≤ 1 ms,
    found by a bounded scalar search on τ (ε by least squares), with F(t − τ) from
    ``plain_of(run, τ)``: written apart from the battery's grid search."""
    def remains(skew):
        moved = [plain_of(k, skew)[w] for k, w in enumerate(windows)]
        target = [c[w] for c, w in zip(changed, windows)]
        scale = sum(m @ c for m, c in zip(moved, target)) / sum(m @ m for m in moved)
        return math.sqrt(np.mean([np.mean((c - scale * m) ** 2)
                                  for m, c in zip(moved, target)]))
    found = minimize_scalar(remains, bounds=(-1e-3, 1e-3), method="bounded",
                            options={"xatol": 1e-7})
    return min(found.fun, remains(-1e-3), remains(1e-3))


def test_a_gain_with_a_skew_leaves_nothing_beyond_itself_and_a_crosstalk_leaves_its_curvature():
    time = np.arange(-0.05, 0.4, 1e-3)
    plain = _pulse(time)
    window = slice(None)
    # a 3 % gain lagging 0.4 ms (on the battery's 25 µs grid of skews): nothing remains
    gained = 1.03 * np.interp(time - 4e-4, time, plain)
    assert independent.beyond_gain([gained], [(time, plain)], [window]) < 1e-9
    # a crosstalk of 10 % of the load 12 ms earlier: what remains is what a bounded search
    # on the exact pulse finds, to the grid's step
    crosstalk = plain + 0.1 * _pulse(time - 0.012)
    found = independent.beyond_gain([crosstalk], [(time, plain)], [window])
    reference = _best_gain_and_skew([crosstalk], lambda k, skew: _pulse(time - skew), [window])
    assert found == pytest.approx(reference, rel=0.02)
    # it is second order in the delay: about (2π·d/T)²/… of the crosstalk's whole change,
    # far less than the change itself, and more than nothing
    whole = math.sqrt(np.mean((crosstalk - plain) ** 2))
    assert 0.02 * whole < found < 0.5 * whole
    # a shorter delay leaves less beyond the gain
    shorter = plain + 0.1 * _pulse(time - 0.004)
    assert independent.beyond_gain([shorter], [(time, plain)], [window]) < 0.3 * found


def test_a_crosstalk_sized_beyond_the_gain_leaves_its_multiple_of_the_noise_there():
    """The battery's size for a crosstalk of 12 ms at 2 × noise, measured by what no gain
    with a skew explains, checked by simulating the drops here, aligning them on the
    detector's level with a crossing search written here, and fitting the gain and skew by
    a bounded search on a cubic spline of the record."""
    campaign = load_campaign(EXAMPLE)
    settings = Settings()
    shape = (("delay", 0.012),)
    size = independent._sizes(campaign, "left-main", "crosstalk", shape, [2.0], settings,
                              measure=independent.BEYOND_GAIN)[2.0]
    whole = independent._sizes(campaign, "left-main", "crosstalk", shape, [2.0], settings)[2.0]
    # sized by its whole change, 2 × noise is a crosstalk of under 1 %; beyond the gain,
    # several times that
    assert whole < 0.01 and size > 5 * whole
    level = independent.detector_level(campaign, "left-main", settings)

    def crossing(time, signal, at):
        i = int(np.argmax(signal > at))
        return time[i - 1] + (at - signal[i - 1]) / (signal[i] - signal[i - 1]) * (
            time[i] - time[i - 1])

    changed, splines, windows = [], [], []
    for index, run in enumerate(campaign.spec.runs):
        if "left-main" not in run.gear_units:
            continue
        gear = independent.gear_of(campaign, run, "left-main")
        speed = ideal_impact_velocity(run.drop_height.si)
        plain = truthgen.simulate(gear, speed, 1000.0, drop_index=index)
        crossed = truthgen.simulate(gear, speed, 1000.0, drop_index=index,
                                    truths=(truthgen.Truth("crosstalk", size, shape),))
        time = plain.time
        shift = crossing(time, crossed.load, level) - crossing(time, plain.load, level)
        changed.append(np.interp(time + shift, time, crossed.load))
        splines.append((time, CubicSpline(time, plain.load)))
        cycle = {p.name: p for p in segment(time, plain.load, plain.stroke,
                                            (gear.upper_mass + gear.lower_mass) * 9.80665)}
        windows.append(slice(cycle["tyre-only contact"].start, cycle["rebound"].stop))
    assert len(changed) >= 2
    remains = _best_gain_and_skew(changed, lambda k, skew: splines[k][1](splines[k][0] - skew),
                                  windows)
    assert remains == pytest.approx(2.0 * settings.load_noise, rel=0.05)


def _outcome(forms, named, measure="load", ratio=2.0, statement=""):
    outside = any(truthgen.FORMS[f].effect is None for f in forms)
    return {"id": "x", "forms": list(forms), "measure": measure, "outside": outside,
            "truth": [truthgen.FORMS[f].effect for f in forms
                      if truthgen.FORMS[f].effect is not None],
            "ratio": ratio, "seed": 1, "named": named, "statement": statement,
            "error": None, "skipped": None, "before": 100.0, "after": 50.0 if named else 100.0,
            "shrink": 0.5 if named else 0.0, "closed": 0.8 if named else None,
            "harmed": False, "harmed_any": False, "physical": {}}


def test_crosstalk_within_a_gains_reach_is_scored_apart_from_the_abstentions():
    """Counted by hand: gas drift abstains once and names friction once; a crosstalk sized
    beyond the gain abstains once and names sensor lag once; crosstalk sized by its whole
    change is answered by an abstention or by the gain (2 of 3), not by sensor lag."""
    beyond = independent.BEYOND_GAIN
    outcomes = [
        _outcome(("lugre",), ["seal friction"]),
        _outcome(("gas-drift",), []),
        _outcome(("gas-drift",), ["seal friction"]),
        _outcome(("crosstalk",), [], beyond),
        _outcome(("crosstalk",), ["sensor lag"], beyond, 5.0),
        _outcome(("crosstalk",), ["load-cell gain"]),
        _outcome(("crosstalk",), []),
        _outcome(("crosstalk",), ["sensor lag"], ratio=5.0),
        _outcome(("crosstalk",), [], ratio=1.0),        # below 2 × noise: not scored
    ]
    assert "lugre" in truthgen.FORMS
    result = independent.score(outcomes)
    m = result["metrics"]
    abstention = m["abstention_out_of_library"]
    assert (abstention["count"], abstention["cases"]) == (2, 4)
    assert abstention["value"] == 0.5 and abstention["met"] is False
    within = m["crosstalk_within_gain"]
    assert (within["count"], within["cases"]) == (2, 3)
    assert within["target"] is None and within["met"] is None
    rows = {row["form"]: row for row in result["forms"]}
    assert (rows["crosstalk"]["right_scored"], rows["crosstalk"]["scored"]) == (2, 3)
    assert rows["crosstalk"]["effect"].startswith("load-cell gain or none")
    assert (rows["crosstalk (beyond gain)"]["right"],
            rows["crosstalk (beyond gain)"]["cases"]) == (1, 2)
    assert rows["crosstalk (beyond gain)"]["effect"] is None
    assert "what no gain with a skew explains" in rows["crosstalk (beyond gain)"]["label"]
    # an older record's outcomes have no measure: sized by the load change
    old = {k: v for k, v in _outcome(("crosstalk",), ["load-cell gain"]).items()
           if k != "measure"}
    assert independent.gain_alike(old)


def test_every_plan_has_crosstalk_sized_both_ways_and_the_earlier_cases_keep_their_ids():
    from blindcheck.plans import S4

    cases = independent.battery(independent.PLANS["development"])
    for plan in independent.PLANS["development"] + independent.PLANS["sealed"]:
        mine = independent.battery(plan)
        beyond = [c for c in mine if c.measure == independent.BEYOND_GAIN]
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
