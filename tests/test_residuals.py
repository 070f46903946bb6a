"""Residual statistics on constructed disagreements whose size, place and timing are known."""

import numpy as np
import pytest

from certkit.gap.phases import Phase
from certkit.gap.residuals import band_shares, describe, largest, residual_cells, timing_lag

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
