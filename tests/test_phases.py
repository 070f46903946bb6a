"""Phases of a drop: the same segmentation on simulated and noisy measured channels,
checked against the simulator's own events."""

import math

import numpy as np
import pytest

from certkit.gap.phases import PHASES, segment
from certkit.physics.simulation import simulate_reference

from .test_drop_model import seed_gear

G = 9.80665


@pytest.fixture(scope="module")
def drop():
    return simulate_reference(seed_gear(), math.sqrt(2 * G * 0.3), duration=1.9, lead=0.1)


def test_phases_cover_the_record_in_order(drop):
    phases = segment(drop.time, drop.load, drop.stroke, 292.5 * G)
    assert [p.name for p in phases] == list(PHASES)
    assert phases[0].start == 0 and phases[-1].stop == drop.time.size
    assert all(a.stop == b.start for a, b in zip(phases, phases[1:]))


def test_events_match_the_simulators_own(drop):
    phases = {p.name: p for p in segment(drop.time, drop.load, drop.stroke, 292.5 * G)}
    contact = int(np.flatnonzero(drop.time >= 0.0)[0])          # the simulation's t = 0
    assert 0 <= phases["tyre-only contact"].start - contact <= 2  # 2 % of W within 2 ms
    # breakout: the first sample the stroke exceeds 0.5 mm, from the simulated stroke itself
    breakout = int(np.flatnonzero(drop.stroke > 0.5e-3)[0])
    assert phases["strut breakout"].start == breakout
    assert phases["compression"].stop - 1 == int(np.argmax(drop.load))
    top = int(np.argmax(drop.stroke))
    assert phases["rebound"].start <= top < phases["rebound"].stop
    assert np.all(np.diff(drop.stroke[top:phases["rebound"].stop]) <= 1e-6)  # extending


def test_noise_moves_the_boundaries_by_a_few_samples_at_most(drop):
    rng = np.random.default_rng(0)
    clean = segment(drop.time, drop.load, drop.stroke, 292.5 * G)
    noisy = segment(drop.time, drop.load + rng.normal(0, 20.0, drop.load.size),
                    drop.stroke + rng.normal(0, 5e-5, drop.stroke.size), 292.5 * G)
    assert [p.name for p in noisy] == [p.name for p in clean]
    for a, b in zip(clean[:-2], noisy[:-2]):   # rebound's end is a shallow minimum
        assert abs(a.start - b.start) <= 3, (a, b)


def test_a_strut_that_never_breaks_out_has_no_strut_phases():
    from dataclasses import replace

    base = seed_gear()
    stiff = replace(base, gas=replace(base.gas, precharge=8e6))
    drop = simulate_reference(stiff, math.sqrt(2 * G * 0.1), duration=0.5, lead=0.1)
    names = [p.name for p in segment(drop.time, drop.load, drop.stroke, 292.5 * G)]
    assert names == ["free fall", "tyre-only contact"]


def test_a_noisy_plateau_at_maximum_stroke_is_not_the_end_of_the_extension():
    # 1 kHz: contact at 100 ms; the stroke rises to 130 mm by 200 ms, is held there by its
    # seals for 100 ms (where 0.05 mm of sensor noise makes local minima), extends
    # linearly to 30 mm by 500 ms and stays: the extension ends at 500 ms, not on the plateau
    t = np.arange(0.0, 1.0, 1e-3)
    stroke = np.interp(t, [0.0, 0.1, 0.2, 0.3, 0.5, 1.0], [0.0, 0.0, 0.130, 0.130, 0.030, 0.030])
    stroke = stroke + np.random.default_rng(3).normal(0.0, 5e-5, t.size)
    load = np.interp(t, [0.0, 0.1, 0.15, 0.5, 1.0], [0.0, 0.0, 8000.0, 2500.0, 2500.0])
    phases = {p.name: p for p in segment(t, load, stroke, 2500.0)}
    end = phases["rebound"].stop - 1
    assert 0.490 <= t[end] <= 0.515, t[end]
