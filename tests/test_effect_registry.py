"""The effect registry is the one definition of every effect, and an effect added through it
alone (the load-cell gain) reaches the spec, the model, calibration, the diagnosis and the
blind check."""

from __future__ import annotations

import math
import typing

import numpy as np
import pytest

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from blindcheck.battery import TRUTHS as BLIND_TRUTHS  # noqa: E402
from blindcheck.battery import Settings  # noqa: E402

from certkit.gap.attribution import CANDIDATES as DIAGNOSIS_CANDIDATES  # noqa: E402
from certkit.physics.calibration import DEFAULT_KNOBS, KNOBS  # noqa: E402
from certkit.physics.effects import BY_NAME, CANDIDATES, EFFECTS, TRUTHS, LoadCellGain  # noqa: E402
from certkit.physics.gear_model import drop_model_for  # noqa: E402
from certkit.physics.simulation import simulate_batch, simulate_reference  # noqa: E402
from certkit.spec.campaign import load_campaign  # noqa: E402
from certkit.spec.schema import CalibrationParameter, Effect  # noqa: E402

from .test_drop_model import seed_gear  # noqa: E402

G = 9.80665


def test_the_spec_accepts_exactly_the_registered_effects():
    assert list(typing.get_args(Effect)) == list(BY_NAME)


def test_the_spec_accepts_exactly_the_calibration_knobs():
    assert set(typing.get_args(CalibrationParameter)) == set(KNOBS)


def test_every_effect_has_one_label_and_one_name():
    labels = [effect.label for effect in EFFECTS]
    names = [effect.name for effect in EFFECTS if effect.name]
    assert len(set(labels)) == len(labels) and len(set(names)) == len(names)


def test_each_part_of_an_effect_is_filed_under_its_own_label():
    for effect in EFFECTS:
        for candidate in effect.candidates:
            assert candidate.name == effect.label
        keys = [c.key for c in effect.candidates]   # an effect's forms are told apart
        assert len(set(keys)) == len(keys)
        assert all(c.form for c in effect.candidates) or len(effect.candidates) <= 1
        if effect.truth:
            assert effect.truth.candidate == effect.label
        for knob in effect.knobs:
            assert knob.needs == effect.label


def test_the_stages_read_the_registry():
    assert DIAGNOSIS_CANDIDATES is CANDIDATES and BLIND_TRUTHS is TRUTHS
    assert tuple(Settings().effects) == tuple(TRUTHS)
    assert all(KNOBS[knob.name] is knob for effect in EFFECTS for knob in effect.knobs)


# ----------------------------------------------------------------- the effect added through it
def test_a_load_cell_gain_scales_the_recorded_load_only():
    # by hand: the load cells read (1 + ε)·F; the mechanics, hence stroke and tyre, unchanged
    nominal = seed_gear()
    gained = nominal.with_effect(LoadCellGain(0.03))
    velocity = math.sqrt(2 * G * 0.25)
    a, b = simulate_reference(nominal, velocity), simulate_reference(gained, velocity)
    np.testing.assert_allclose(b.load, 1.03 * a.load, rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(b.stroke, a.stroke)
    np.testing.assert_array_equal(b.tyre, a.tyre)
    fast = simulate_batch([nominal, gained], velocity, duration=0.3)
    np.testing.assert_allclose(fast.load[1], 1.03 * fast.load[0], rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(fast.stroke[1], fast.stroke[0])


def test_the_diagnosis_candidate_and_the_blind_truth_have_their_stated_sizes():
    model = seed_gear()
    velocity = math.sqrt(2 * G * 0.25)
    plain = simulate_reference(model, velocity)
    candidate = next(c for c in CANDIDATES if c.name == "load-cell gain")
    # "a load channel reading 5 % high" at strength 1
    with_candidate = simulate_reference(candidate.add(model, 1.0), velocity)
    assert with_candidate.load.max() == pytest.approx(1.05 * plain.load.max(), rel=1e-12)
    # the truth at size s reads 0.1 %·s high
    assert TRUTHS["load-cell gain"].model(model, 20.0).effect("load-cell gain").gain == \
        pytest.approx(0.02)


def test_a_spec_switches_the_gain_on_and_calibration_fits_it(seed_copy):
    text = seed_copy.read_text(encoding="utf-8")
    assert "  effects: [rebound-orifice, seal-friction]" in text
    spec = seed_copy
    spec.write_text(text.replace("  effects: [rebound-orifice, seal-friction]",
                                 "  effects: [rebound-orifice, seal-friction, load-cell-gain]"),
                    encoding="utf-8")
    campaign = load_campaign(spec)
    model = drop_model_for(campaign.spec, campaign.spec.runs[0], "left-main")
    assert model.effect("load-cell gain") == LoadCellGain(0.0)   # starts at no error
    assert "load-cell-gain" in DEFAULT_KNOBS                     # and is fitted by default
    assert KNOBS["load-cell-gain"].bounds(0.0) == (-0.1, 0.1)


def test_a_load_channel_skew_delays_the_load_record_only():
    # a ramp delayed by half a sample (0.5 ms at 1 kHz) reads k − 0.5 from its second
    # sample on, its first held; times (1 + ε) with ε = 0.1
    ramp = np.arange(6.0)
    term = LoadCellGain(0.1, 0.5e-3)
    assert np.allclose(term.recorded(1e-3, "load", ramp),
                       1.1 * np.array([0.0, 0.5, 1.5, 2.5, 3.5, 4.5]))
    # a negative skew (the load ahead): k + 0.5, the last held
    ahead = LoadCellGain(0.0, -0.5e-3).recorded(1e-3, "load", ramp)
    assert np.allclose(ahead, [0.5, 1.5, 2.5, 3.5, 4.5, 5.0])
    # rows of a batch alike; other channels untouched
    batch = np.vstack([ramp, 2 * ramp])
    assert np.allclose(term.recorded(1e-3, "load", batch)[1],
                       2.2 * np.array([0.0, 0.5, 1.5, 2.5, 3.5, 4.5]))
    assert np.array_equal(term.recorded(1e-3, "stroke", ramp), ramp)
