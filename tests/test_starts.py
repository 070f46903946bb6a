"""Further starts of a calibration (certkit.physics.starts): the Sobol points worked out by
hand, and the choice between the first fit and the best further start checked against a
dense grid of the cost, computed here."""

import math

import numpy as np
import pytest

from certkit.physics.fitting import DEFAULT_RELATIVE_STEP, FitParameter, fit
from certkit.physics.starts import (KEEP_MARGIN, MOST_STARTS, best_of_starts, sobol_starts,
                                    starts_document)


def test_sobol_points_on_log_and_linear_scales():
    # Sobol's sequence in two dimensions begins (0, 0), (1/2, 1/2), (3/4, 1/4), (1/4, 3/4)
    # (the first direction numbers, m = 1 in both dimensions); point 0 is left out.
    # A knob between 1 and 100 (both positive: log scale), one between -1 and 1 (linear).
    parameters = [FitParameter("k", "1", 10.0, 1.0, 100.0),
                  FitParameter("c", "1", 0.0, -1.0, 1.0)]
    points = sobol_starts(parameters, 3)
    expected = [(10.0, 0.0), (10 ** 1.5, -0.5), (10 ** 0.5, 0.5)]
    for point, want in zip(points, expected):
        assert point == pytest.approx(want, rel=1e-12, abs=1e-15)
    assert sobol_starts(parameters, 3) == points   # fixed: the same every call
    assert sobol_starts(parameters, 0) == []
    with pytest.raises(ValueError, match="0 to"):
        sobol_starts(parameters, MOST_STARTS + 1)
    with pytest.raises(ValueError, match="0 to"):
        sobol_starts(parameters, -1)


@pytest.mark.parametrize("knobs", [6, 8, 10])
def test_every_knob_is_started_in_both_halves_of_its_range(knobs):
    # on [0, 1] (linear) a coordinate is its own share of the range
    parameters = [FitParameter(f"k{i}", "1", 0.5, 0.0, 1.0) for i in range(knobs)]
    points = np.array(sobol_starts(parameters, 8))
    assert points.shape == (8, knobs)
    for column in points.T:
        assert (column < 0.5).sum() >= 3 and (column >= 0.5).sum() >= 3, column
        assert len(set(column)) == 8       # no two starts share a knob's value


def _two_basins(x):
    # cost (x/5 - 1)² + 9·sin²x: minima near 0 (cost 1), π (≈ 0.138), 2π (≈ 0.066), 3π
    x = float(np.asarray(x).ravel()[0])
    return np.array([x / 5.0 - 1.0, 3.0 * math.sin(x)])


def _many(matrix):
    return np.array([_two_basins(row) for row in np.atleast_2d(matrix)])


def _grid_minimum(low, high):
    grid = np.linspace(low, high, 400_001)
    cost = np.sqrt(((grid / 5.0 - 1.0) ** 2 + 9.0 * np.sin(grid) ** 2) / 2.0)
    return grid[np.argmin(cost)], float(cost.min())


def test_a_fit_stuck_in_the_worse_basin_is_replaced_by_the_best_start():
    # bounds [0, 10] (linear): starts at 5, 7.5, 2.5, 3.75 (Sobol's 1/2, 3/4, 1/4, 3/8);
    # 5 and 7.5 lie in the basin of 2π (3π/2 to 5π/2), the first of them is start 1
    parameters = [FitParameter("x", "1", 3.0, 0.0, 10.0)]
    first = fit(_two_basins, parameters, residuals_many=_many, tolerance=1e-10)
    assert first.estimate[0] == pytest.approx(math.pi, abs=0.1)   # the local minimum near π
    result, search = best_of_starts(first, parameters, _two_basins, _many, 4, 100, 1e-10,
                                    step=DEFAULT_RELATIVE_STEP)
    assert [p[0] for p in search.points] == [5.0, 7.5, 2.5, 3.75]
    where, lowest = _grid_minimum(0.0, 10.0)
    assert where == pytest.approx(2 * math.pi, abs=0.05)
    assert result.estimate[0] == pytest.approx(where, abs=1e-4)
    assert result.cost == pytest.approx(lowest, rel=1e-6)
    assert search.kept == 0 and search.failures == ()
    # starts 1 and 2 reach the 2π minimum, 3 and 4 the π one
    costs = search.start_costs
    assert costs[0] == pytest.approx(lowest, rel=1e-4) == costs[1]
    assert costs[2] == pytest.approx(first.cost, rel=1e-4) == costs[3]
    # the report's "nominal" stays the first start's: its value and its cost there
    assert result.parameters == tuple(parameters)
    assert result.cost_nominal == first.cost_nominal


def test_one_basin_keeps_the_first_fit_exactly():
    parameters = [FitParameter("x", "1", 3.0, 2.0, 4.5)]   # only the basin of π inside
    first = fit(_two_basins, parameters, residuals_many=_many, tolerance=1e-10)
    result, search = best_of_starts(first, parameters, _two_basins, _many, 4, 100, 1e-10,
                                    step=DEFAULT_RELATIVE_STEP)
    assert search.kept is None
    assert result.estimate[0] == first.estimate[0] and result.cost == first.cost
    assert all(c == pytest.approx(first.cost, rel=1e-6) for c in search.start_costs)
    document = starts_document(search)
    assert document["kept_start"] is None and len(document["points"]) == 4
    assert document["first_training_cost"] == first.cost


def test_a_start_that_cannot_be_fitted_is_passed_over():
    # residuals not finite beyond x = 7.2: the start at 7.5 fails, the one at 5 does not
    def partly(x):
        value = float(np.asarray(x).ravel()[0])
        return _two_basins(x) if value <= 7.2 else np.array([np.nan, np.nan])

    def many(matrix):
        return np.array([partly(row) for row in np.atleast_2d(matrix)])

    parameters = [FitParameter("x", "1", 3.0, 0.0, 10.0)]
    first = fit(partly, parameters, residuals_many=many, tolerance=1e-10)
    result, search = best_of_starts(first, parameters, partly, many, 2, 100, 1e-10,
                                    step=DEFAULT_RELATIVE_STEP)
    assert search.start_costs[1] is None and search.failures[0].startswith("start 2: ")
    assert search.kept == 0
    assert result.estimate[0] == pytest.approx(_grid_minimum(0.0, 10.0)[0], abs=1e-4)
    assert starts_document(search)["failures"] == list(search.failures)


def test_when_every_start_fails_the_first_fit_stands():
    def only_near_pi(x):
        value = float(np.asarray(x).ravel()[0])
        return _two_basins(x) if 2.0 <= value <= 4.5 else np.array([np.inf, 0.0])

    def many(matrix):
        return np.array([only_near_pi(row) for row in np.atleast_2d(matrix)])

    parameters = [FitParameter("x", "1", 3.0, 0.0, 10.0)]
    first = fit(only_near_pi, parameters, residuals_many=many, tolerance=1e-10)
    # the starts at 5 and 7.5 cannot be evaluated at all
    result, search = best_of_starts(first, parameters, only_near_pi, many, 2, 100, 1e-10,
                                    step=DEFAULT_RELATIVE_STEP)
    assert search.kept is None and search.start_costs == (None, None)
    assert len(search.failures) == 2
    assert result.estimate[0] == first.estimate[0]


def test_the_texts_that_state_the_margin_and_the_limit_state_the_code_s():
    """The spec's description and the command's help spell the margin and the most starts
    out (they are read without loading the physics); the method text takes them from the
    code."""
    from typer.testing import CliRunner

    from certkit.cli import app
    from certkit.display import percent
    from certkit.evidence.methods import model_method
    from certkit.spec.settings import CalibrationSpec

    from certkit.physics.starts import START_EVALUATIONS

    margin = percent(KEEP_MARGIN, 1)
    field = CalibrationSpec.model_fields["starts"]
    assert f"more than {margin} below" in field.description
    assert f"a fit of at most {START_EVALUATIONS} evaluations" in field.description
    assert [m.le for m in field.metadata if hasattr(m, "le")] == [MOST_STARTS]
    help_text = " ".join(CliRunner().invoke(app, ["calibrate", "--help"],
                                            terminal_width=200).output.split())
    assert f"0 to {MOST_STARTS}; the best is kept when its training cost is more than " \
        f"{margin} below" in help_text
    assert f"more than {margin} below the fit from the spec's values" in model_method(2)


def test_the_report_says_what_the_starts_found_in_each_case():
    from certkit.evidence.model_view import starts_words
    from certkit.physics.starts import StartSearch

    # costs as the report prints every number: four significant digits
    points = ((1.0,), (2.0,), (3.0,))
    kept = starts_words(StartSearch(points, (0.5, 0.1, 0.3), 0.9, 1))
    assert kept.startswith("The fit from the spec's values reached a training cost "
                           "(normalised RMS residual) of 0.9000. It was also tried from 3 "
                           "further starts")
    assert "start 2 reached 0.1000 and, fitted again from where it stopped, came more than " \
        "0.1 % lower: that calibration is kept." in kept
    none_lower = starts_words(StartSearch(points, (0.9, 1.2, None), 0.9, None,
                                          ("start 3: not finite",)))
    assert "the lowest reached 0.9000 and, fitted again, came no more than 0.1 % below the " \
        "fit from the spec's values, which is kept." in none_lower
    assert "(values in SI): start 3: not finite." in none_lower
    refit_failed = starts_words(StartSearch(points, (0.5, 0.2, 0.3), 0.9, None,
                                            ("start 2, fitted again: stiff",)))
    assert "the best of them (the earliest within 0.1 % of the lowest, 0.2000) could not be " \
        "fitted again, so the fit from the spec's values is kept. Fits that failed and were " \
        "passed over (values in SI): start 2, fitted again: stiff." in refit_failed
    # a near-tie: start 1 is within the margin of start 2, the lowest, so start 1 was the
    # one fitted again; the words must not name start 2 for it
    near_tie = starts_words(StartSearch(points, (1.0005, 1.0, 2.0), 1.2, None,
                                        ("start 1, fitted again: stiff",)))
    assert "start 2" not in near_tie and "start 1, fitted again: stiff" in near_tie
    all_failed = starts_words(StartSearch(points, (None, None, None), 0.9, None,
                                          ("a", "b", "c")))
    assert "none of them could be fitted, so the fit from the spec's values is kept." \
        in all_failed
    again = starts_words(StartSearch(points, (0.9, 1.2, 1.0), 0.9, None), again_cost=0.4)
    assert again.endswith("The model was then calibrated again from a refit's parameters "
                          "(training cost 0.4000), and that calibration is the one used.")
    assert starts_words(None) == ""


def test_a_failed_start_s_evaluations_are_counted():
    """Every parameter set evaluated counts, those of a fit that failed too: counted here by
    the residual function itself, apart from the fit's own count."""
    calls = []

    def partly(x):
        value = float(np.asarray(x).ravel()[0])
        calls.append(value)
        return _two_basins(x) if value <= 7.2 else np.array([np.nan, np.nan])

    def many(matrix):
        return np.array([partly(row) for row in np.atleast_2d(matrix)])

    parameters = [FitParameter("x", "1", 3.0, 0.0, 10.0)]
    first = fit(partly, parameters, residuals_many=many, tolerance=1e-10)
    result, search = best_of_starts(first, parameters, partly, many, 2, 100, 1e-10,
                                    step=DEFAULT_RELATIVE_STEP)
    assert search.start_costs[1] is None     # the start at 7.5 failed at once
    assert result.evaluations == len(calls)


def test_every_start_is_fitted_over_the_step_with_the_first_start_s_sizes(monkeypatch):
    import certkit.physics.starts as starts

    seen = []

    def recording(single, parameters, **options):
        seen.append(([p.size for p in parameters], options.get("relative_step")))
        return fit(single, parameters, **options)

    monkeypatch.setattr(starts, "fit", recording)
    parameters = [FitParameter("x", "1", 3.0, 0.0, 10.0, size=0.5)]

    def many(matrix):
        return np.array([_two_basins(row) for row in np.atleast_2d(matrix)])

    first = fit(_two_basins, parameters, residuals_many=many, tolerance=1e-10)
    best_of_starts(first, parameters, _two_basins, many, 3, 100, 1e-10, step=3e-3)
    assert len(seen) == 4   # three starts and the best one fitted again
    assert all(sizes == [0.5] and step == 3e-3 for sizes, step in seen)
