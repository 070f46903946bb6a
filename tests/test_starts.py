"""Further starts of a calibration (certkit.physics.starts): the Halton design worked out by
hand, and the choice between the first fit and the best further start checked against a
dense grid of the cost, computed here."""

import math

import numpy as np
import pytest

from certkit.physics.fitting import FitParameter, fit
from certkit.physics.starts import KEEP_MARGIN, _radical_inverse, best_of_starts, halton_starts


def test_van_der_corput_terms_by_hand():
    # base 2: 1 = 1₂ -> 0.1₂, 2 = 10₂ -> 0.01₂, 3 = 11₂ -> 0.11₂, 6 = 110₂ -> 0.011₂
    assert [_radical_inverse(i, 2) for i in (1, 2, 3, 6)] == [0.5, 0.25, 0.75, 0.375]
    # base 3: 1 -> 1/3, 2 -> 2/3, 3 = 10₃ -> 1/9, 5 = 12₃ -> 0.21₃ = 2/3 + 1/9
    assert [_radical_inverse(i, 3) for i in (1, 2, 3, 5)] == pytest.approx(
        [1 / 3, 2 / 3, 1 / 9, 7 / 9], abs=1e-15)


def test_halton_points_on_log_and_linear_scales():
    # a knob between 1 and 100 (both positive: log scale), one between -1 and 1 (linear)
    parameters = [FitParameter("k", "1", 10.0, 1.0, 100.0),
                  FitParameter("c", "1", 0.0, -1.0, 1.0)]
    points = halton_starts(parameters, 3)
    # point 1: q = 1/2 (base 2) -> 10^(2·1/2) = 10; q = 1/3 (base 3) -> -1 + 2/3 = -1/3
    # point 2: q = 1/4 -> 10^0.5; q = 2/3 -> 1/3.  point 3: q = 3/4 -> 10^1.5; q = 1/9 -> -7/9
    expected = [(10.0, -1 / 3), (10 ** 0.5, 1 / 3), (10 ** 1.5, -7 / 9)]
    for point, want in zip(points, expected):
        assert point == pytest.approx(want, rel=1e-12)
    assert halton_starts(parameters, 3) == points   # fixed: the same every call


def _two_basins(x):
    # cost (x/5 - 1)² + 9·sin²x: minima near π (cost ≈ 0.138) and 2π (≈ 0.066) in [0.5, 10]
    x = float(np.asarray(x).ravel()[0])
    return np.array([x / 5.0 - 1.0, 3.0 * math.sin(x)])


def _many(matrix):
    return np.array([_two_basins(row) for row in np.atleast_2d(matrix)])


def _rms_on_grid(low, high):
    grid = np.linspace(low, high, 400_001)
    cost = np.sqrt(((grid / 5.0 - 1.0) ** 2 + 9.0 * np.sin(grid) ** 2) / 2.0)
    return grid[np.argmin(cost)], float(cost.min())


def test_a_fit_stuck_in_the_worse_basin_is_replaced_by_the_best_start():
    parameters = [FitParameter("x", "1", 3.0, 0.5, 10.0)]
    first = fit(_two_basins, parameters, residuals_many=_many, tolerance=1e-10)
    assert first.estimate[0] == pytest.approx(math.pi, abs=0.1)   # the local minimum near π
    result, search = best_of_starts(first, parameters, _two_basins, _many, 4, 100, 1e-10)
    where, lowest = _rms_on_grid(0.5, 10.0)
    assert result.estimate[0] == pytest.approx(where, abs=1e-4)
    assert result.cost == pytest.approx(lowest, rel=1e-6)
    assert search.kept is not None and search.first_cost == first.cost
    assert len(search.points) == len(search.start_costs) == 4
    # the report's "nominal" stays the first start's: its value and its cost there
    assert result.parameters == tuple(parameters)
    assert result.cost_nominal == first.cost_nominal
    assert result.evaluations > first.evaluations


def test_one_basin_keeps_the_first_fit_exactly():
    parameters = [FitParameter("x", "1", 3.0, 2.0, 4.5)]   # only the basin of π inside
    first = fit(_two_basins, parameters, residuals_many=_many, tolerance=1e-10)
    result, search = best_of_starts(first, parameters, _two_basins, _many, 4, 100, 1e-10)
    assert search.kept is None
    assert result.estimate[0] == first.estimate[0] and result.cost == first.cost
    # every start reached the same minimum: none is more than the margin below the first
    assert min(search.start_costs) > first.cost * (1.0 - KEEP_MARGIN)
