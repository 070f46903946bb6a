"""Residual statistics on constructed disagreements whose size, place and timing are known."""

import numpy as np
import pytest

from certkit.gap.phases import Phase
from certkit.gap.residuals import (band_shares, describe, largest, residual_cells, shifted_fit,
                                   timing_lag)

STEP = 0.001
TIME = np.arange(0.0, 1.0, STEP)
PHASES = [Phase("compression", 0, 300), Phase("rebound", 300, 600), Phase("settling", 600, 1000)]


def pulse(centre: float) -> np.ndarray:
    return np.exp(-((TIME - centre) / 0.03) ** 2)


def test_an_offset_confined_to_one_phase_is_its_bias_and_nowhere_else():
    model = pulse(0.2)
    measured = model.copy()
    measured[300:600] += 0.05
    cells = residual_cells("D1", TIME, {"load": measured}, {"load": model}, PHASES)
    by_phase = {c.phase: c for c in cells}
    assert by_phase["rebound"].bias == pytest.approx(0.05)
    assert by_phase["rebound"].rms == pytest.approx(0.05)
    assert by_phase["compression"].rms == 0.0 and by_phase["settling"].rms == 0.0
    assert largest(cells).phase == "rebound"
    assert "during rebound of run D1" in describe(largest(cells), 1.0, "N")


@pytest.mark.parametrize("delay", [0.003, -0.0045, 0.0102])
def test_a_delayed_simulation_shows_its_delay(delay):
    measured, late = pulse(0.3), pulse(0.3 + delay)
    assert timing_lag(measured, late, STEP) == pytest.approx(delay, abs=2e-4)


def test_a_ripple_puts_its_energy_in_the_structural_band():
    ripple = 0.1 * np.sin(2 * np.pi * 40.0 * TIME)      # 40 Hz: structural / tyre band
    drift = 0.1 * np.sin(2 * np.pi * 3.0 * TIME)        # 3 Hz: rigid-body band
    shares = band_shares(ripple, STEP)
    assert shares["structural and tyre modes"] > 0.99
    assert band_shares(drift, STEP)["rigid-body"] > 0.99
    assert sum(shares.values()) == pytest.approx(1.0)


def test_a_correction_that_fits_later_shows_its_shift_and_an_instant_one_none():
    rng = np.random.default_rng(5)
    force = [1000.0 * pulse(0.3), 1500.0 * pulse(0.25)]
    noise = [rng.normal(0.0, 2.0, TIME.size) for _ in force]
    # simulated − measured when the record carries 5 % of the force 12 ms late; a gain
    # refit's correction raises the simulated load by 5 % at the same instant
    late = [-0.05 * np.interp(TIME - 0.012, TIME, f) - n for f, n in zip(force, noise)]
    gain = [0.05 * f for f in force]
    shift, share = shifted_fit(late, gain, STEP)
    assert shift == pytest.approx(0.012, abs=1e-9)        # fits best delayed by 12 ms
    # delayed by 12 ms the correction leaves the noise alone: the share is what the noise
    # is not, of the mean square left at the same instant
    at_once = np.mean(np.concatenate([r + g for r, g in zip(late, gain)]) ** 2)
    assert share == pytest.approx(1 - np.mean(np.concatenate(noise) ** 2) / at_once, rel=0.02)
    assert share > 0.5
    # a record that is truly 5 % high: the correction fits at the same instant
    high = [-0.05 * f - n for f, n in zip(force, noise)]
    shift, share = shifted_fit(high, gain, STEP)
    assert shift == 0.0 and share == 0.0
