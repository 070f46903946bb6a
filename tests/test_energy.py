"""Energy integrals against load-travel curves whose area is known in closed form."""

import math

import numpy as np
import pytest

from certkit.energy import absorbed_energy, efficiency


def test_triangle_load_stroke_curve_is_integrated_exactly():
    # F = k*s on a sinusoidal stroke history: E = k*s_max^2/2
    t = np.linspace(0.0, 0.05, 51)
    s = 0.09 * np.sin(math.pi * t / 0.1)
    k = 3.0e5
    assert absorbed_energy(t, k * s, s) == pytest.approx(k * 0.09 ** 2 / 2, rel=1e-6)


def test_half_sine_load_stroke_curve_to_one_part_per_million():
    # F = F0 sin(pi s/s_max): E = 2 F0 s_max/pi; 60 samples over the loading stroke (1 kHz, 60 ms)
    t = np.linspace(0.0, 0.06, 61)
    s = 0.09 * np.sin(math.pi * t / 0.12)
    load = 15000.0 * np.sin(math.pi * s / 0.09)
    assert absorbed_energy(t, load, s) == pytest.approx(2 * 15000.0 * 0.09 / math.pi, rel=1e-6)


def test_only_the_loading_stroke_counts():
    # after maximum travel the element unloads; energy is taken up to the maximum only
    t = np.linspace(0.0, 0.2, 201)
    s = 0.05 * np.sin(math.pi * t / 0.2)   # max at t = 0.1
    load = 1.0e5 * s
    assert absorbed_energy(t, load, s) == pytest.approx(1.0e5 * 0.05 ** 2 / 2, rel=1e-6)


def test_efficiency_of_a_linear_element_is_one_half():
    assert efficiency(0.5 * 1000.0 * 0.1, 1000.0, 0.1) == pytest.approx(0.5)
    assert efficiency(10.0, 0.0, 0.1) is None
