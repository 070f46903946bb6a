"""The calibration core against closed forms: ordinary least squares, the linearised
covariance of a nonlinear model, models that determine only a product or a ratio, an
analytically known correlation and a bound that decides a parameter.

Every expected value is computed here from the model's own algebra (design matrices,
analytic derivatives, closed-form constrained estimates), not from certkit.physics.fitting."""

import math
from dataclasses import replace

import numpy as np
import pytest

import certkit.physics.fitting as fitting
from certkit.physics.fitting import FitError, FitParameter, fit, jacobian_at, singular_cutoff

SIGMA = 0.2  # noise standard deviation; residuals are normalised by it


def ols(design, y):
    """Closed-form weighted OLS: estimate, standard errors and correlation."""
    xw, yw = design / SIGMA, y / SIGMA
    beta = np.linalg.solve(xw.T @ xw, xw.T @ yw)
    rss = np.sum((xw @ beta - yw) ** 2)
    cov = rss / (len(y) - design.shape[1]) * np.linalg.inv(xw.T @ xw)
    se = np.sqrt(np.diag(cov))
    return beta, se, cov / np.outer(se, se)


# --------------------------------------------------------------------------- linear model
@pytest.mark.parametrize("unit_of_a, a_true, a_nominal", [
    (1.0, 1.5, 0.0),          # zero nominal: the bound magnitude sets the scale
    (1e-6, 1.5e6, 8.0e5),     # a pressure in Pa next to an O(1) slope
])
def test_linear_model_matches_closed_form_ols(unit_of_a, a_true, a_nominal):
    rng = np.random.default_rng(7)
    t = np.linspace(0.0, 10.0, 40)
    y = a_true * unit_of_a - 0.7 * t + SIGMA * rng.standard_normal(t.size)
    design = np.column_stack([np.full_like(t, unit_of_a), t])
    beta, se, corr = ols(design, y)

    parameters = [FitParameter("a", "Pa", a_nominal, -10 * a_true, 10 * a_true),
                  FitParameter("b", "1", -0.3, -5.0, 5.0)]
    result = fit(lambda x: (design @ x - y) / SIGMA, parameters)

    assert result.success
    np.testing.assert_allclose(result.estimate, beta, rtol=1e-6)
    np.testing.assert_allclose(result.standard_error, se, rtol=1e-6)
    np.testing.assert_allclose(result.correlation, corr, rtol=1e-6, atol=1e-9)
    rms = np.sqrt(np.mean(((design @ beta - y) / SIGMA) ** 2))
    assert result.cost == pytest.approx(rms, rel=1e-9)
    nominal = np.array([a_nominal, -0.3])
    assert result.cost_nominal == pytest.approx(
        np.sqrt(np.mean(((design @ nominal - y) / SIGMA) ** 2)), rel=1e-12)
    assert result.at_bound == () and result.warnings == ()


# --------------------------------------------------------------------------- exponential decay
T = np.linspace(0.0, 1.5, 60)
A_TRUE, TAU_TRUE = 5.0, 0.3
NOISE = np.random.default_rng(3).standard_normal(T.size)
Y = A_TRUE * np.exp(-T / TAU_TRUE) + SIGMA * NOISE
DECAY = [FitParameter("amplitude A", "m", 3.0, 0.1, 100.0),
         FitParameter("time constant tau", "s", 0.5, 0.01, 10.0)]


def decay_residuals(x):
    return (x[0] * np.exp(-T / x[1]) - Y) / SIGMA


def decay_residuals_many(xs):
    return (xs[:, :1] * np.exp(-T[None, :] / xs[:, 1:]) - Y[None, :]) / SIGMA


def decay_jacobian(x):
    """Analytic ∂r/∂(A, τ) of r = (A·exp(−t/τ) − y)/σ."""
    e = np.exp(-T / x[1])
    return np.column_stack([e, x[0] * T / x[1] ** 2 * e]) / SIGMA


def test_exponential_decay_recovers_truth_with_linearised_errors():
    result = fit(decay_residuals, DECAY)
    assert result.success
    # the truth lies within a few standard errors
    assert np.all(np.abs(result.estimate - [A_TRUE, TAU_TRUE]) < 3 * result.standard_error)
    # standard errors and correlation: s²(JᵀJ)⁻¹ with the analytic J at the estimate
    jac = decay_jacobian(result.estimate)
    r = decay_residuals(result.estimate)
    cov = r @ r / (T.size - 2) * np.linalg.inv(jac.T @ jac)
    se = np.sqrt(np.diag(cov))
    np.testing.assert_allclose(result.standard_error, se, rtol=1e-6)
    assert result.correlation[0, 1] == pytest.approx(cov[0, 1] / (se[0] * se[1]), rel=1e-6)
    # the optimum is stationary: the analytic gradient Jᵀr vanishes
    assert np.max(np.abs(jac.T @ r)) < 1e-5 * np.linalg.norm(jac) * np.linalg.norm(r)


def test_batched_and_analytic_routes_agree_with_the_single_route():
    batches = []

    def many(xs):
        batches.append(xs.shape)
        return decay_residuals_many(xs)

    single = fit(decay_residuals, DECAY)
    batched = fit(decay_residuals, DECAY, residuals_many=many)
    analytic = fit(decay_residuals, DECAY, jacobian=decay_jacobian)

    np.testing.assert_allclose(batched.estimate, single.estimate, rtol=1e-6)
    np.testing.assert_allclose(analytic.estimate, single.estimate, rtol=1e-6)
    np.testing.assert_allclose(batched.standard_error, single.standard_error, rtol=1e-6)
    np.testing.assert_allclose(analytic.standard_error, single.standard_error, rtol=1e-6)
    # each Jacobian is one batched call over the 2p stencil points (+ the base point if a
    # one-sided stencil needs it)
    assert batches and all(shape in {(4, 2), (5, 2)} for shape in batches)
    assert batched.evaluations == single.evaluations


def test_finite_differences_stay_within_bounds_when_the_nominal_is_on_a_bound():
    seen = []

    def residuals(x):
        seen.append(x.copy())
        return decay_residuals(x)

    parameters = [FitParameter("amplitude A", "m", 0.1, 0.1, 100.0),  # nominal on the bound
                  FitParameter("time constant tau", "s", 0.5, 0.01, 10.0)]
    result = fit(residuals, parameters)
    seen = np.array(seen)
    assert np.all(seen >= [0.1, 0.01]) and np.all(seen <= [100.0, 10.0])
    assert result.estimate[0] == pytest.approx(fit(decay_residuals, DECAY).estimate[0], rel=1e-6)


# --------------------------------------------------------------------------- identifiability
def product_parameters(*names):
    return [FitParameter(n, "1", 1.0 + i, 0.1, 10.0) for i, n in enumerate(names)]


def noisy(values):
    return values + SIGMA * np.random.default_rng(11).standard_normal(values.size)


def test_only_the_product_is_determined():
    t = np.linspace(0.0, 1.0, 30)
    y = noisy(6.0 * t)
    result = fit(lambda x: (x[0] * x[1] * t - y) / SIGMA, product_parameters("k", "m"))
    assert result.estimate[0] * result.estimate[1] == pytest.approx(
        np.sum(t * y) / np.sum(t * t), rel=1e-6)   # the product itself is the OLS slope
    assert np.all(np.isnan(result.standard_error))
    assert np.all(np.isnan(result.correlation))
    [warning] = result.warnings
    assert "product k·m" in warning and "k and m" in warning


def test_only_the_ratio_is_determined():
    t = np.linspace(0.0, 1.0, 30)
    y = noisy(0.5 * t)
    result = fit(lambda x: (x[0] / x[1] * t - y) / SIGMA, product_parameters("k", "m"))
    assert np.all(np.isnan(result.standard_error))
    [warning] = result.warnings
    assert "ratio k/m" in warning


def test_undetermined_parameters_do_not_spoil_the_determined_one():
    t = np.linspace(0.0, 1.0, 30)
    y = noisy(6.0 * t + 0.5)
    design = np.column_stack([t, np.ones_like(t)])
    beta, se, _ = ols(design, y)
    parameters = product_parameters("k", "m") + [FitParameter("c", "m", 0.0, -5.0, 5.0)]
    result = fit(lambda x: (x[0] * x[1] * t + x[2] - y) / SIGMA, parameters)
    assert np.isnan(result.standard_error[:2]).all()
    assert result.estimate[2] == pytest.approx(beta[1], rel=1e-6)
    # s² uses m − p with p = 3 fitted parameters, as stated for the Gauss-Newton covariance
    assert result.standard_error[2] == pytest.approx(se[1] * math.sqrt(28 / 27), rel=1e-6)
    assert result.correlation[2, 2] == 1.0 and np.isnan(result.correlation[0, 2])
    assert len(result.warnings) == 1 and "product k·m" in result.warnings[0]


def test_three_parameter_cases():
    t = np.linspace(0.0, 1.0, 30)
    y = noisy(6.0 * t)
    triple = fit(lambda x: (x[0] * x[1] * x[2] * t - y) / SIGMA,
                 product_parameters("k", "m", "c"))
    assert np.isnan(triple.standard_error).all()
    assert any("product k·m·c" in w for w in triple.warnings)

    # k·m and k·c are both determined, so one combination of the three is not
    y2 = noisy(2.0 * t + 3.0 * t ** 2)
    general = fit(lambda x: (x[0] * x[1] * t + x[0] * x[2] * t ** 2 - y2) / SIGMA,
                  product_parameters("k", "m", "c"))
    assert np.isnan(general.standard_error).all()
    [warning] = general.warnings
    assert "k, m and c" in warning and "separately" in warning


def test_strong_but_finite_correlation_is_reported():
    t = np.linspace(10.0, 11.0, 30)       # narrow range far from t = 0
    y = noisy(1.0 + 2.0 * t)
    design = np.column_stack([np.ones_like(t), t])
    inverse = np.linalg.inv(design.T @ design)
    expected_r = inverse[0, 1] / math.sqrt(inverse[0, 0] * inverse[1, 1])
    assert expected_r < -0.95
    result = fit(lambda x: (design @ x - y) / SIGMA,
                 [FitParameter("offset a", "m", 0.5, -100.0, 100.0),
                  FitParameter("slope b", "m/s", 1.0, -100.0, 100.0)])
    assert result.correlation[0, 1] == pytest.approx(expected_r, rel=1e-6)
    assert np.all(np.isfinite(result.standard_error))
    [warning] = result.warnings
    assert "offset a and slope b are strongly correlated" in warning
    assert f"r = {expected_r:.3f}" in warning


@pytest.mark.parametrize("b_true, side, bound", [(3.0, "upper", 2.0), (-1.0, "lower", 0.0)])
def test_truth_outside_the_bounds_ends_on_the_bound(b_true, side, bound):
    t = np.linspace(0.0, 1.0, 30)
    y = noisy(1.0 + b_true * t)
    seen = []

    def residuals(x):
        seen.append(x[1])
        return (x[0] + x[1] * t - y) / SIGMA

    result = fit(residuals, [FitParameter("a", "m", 0.5, -10.0, 10.0),
                             FitParameter("b", "m/s", 1.0, 0.0, 2.0)])
    assert result.estimate[1] == pytest.approx(bound, abs=1e-6)
    # with b fixed on its bound, a is the mean of y − b·t
    assert result.estimate[0] == pytest.approx(np.mean(y - bound * t), rel=1e-6)
    assert result.at_bound == ("b",)
    assert any(w.startswith(f"b ended on its {side} bound") and "the bound, not the data" in w
               for w in result.warnings)
    assert min(seen) >= 0.0 and max(seen) <= 2.0


# --------------------------------------------------------------------------- bad inputs
@pytest.mark.parametrize("kwargs, words", [
    ({"nominal": 20.0, "lower": 0.0, "upper": 10.0}, "outside its bounds"),
    ({"nominal": 1.0, "lower": 10.0, "upper": 0.0}, "lower bound"),
    ({"nominal": 1.0, "lower": 1.0, "upper": 1.0}, "lower bound"),
    ({"nominal": float("nan"), "lower": 0.0, "upper": 10.0}, "nominal must be a finite"),
    ({"nominal": 1.0, "lower": 0.0, "upper": float("inf")}, "upper must be a finite"),
])
def test_bad_parameters_raise_naming_the_parameter(kwargs, words):
    with pytest.raises(ValueError, match=f"'orifice C_d'.*{words}"):
        FitParameter("orifice C_d", "1", **kwargs)


def test_bad_fit_arguments():
    good = FitParameter("k", "N/m", 1.0, 0.0, 2.0)
    with pytest.raises(ValueError, match="repeated: k"):
        fit(lambda x: x, [good, good])
    with pytest.raises(ValueError, match="at least one"):
        fit(lambda x: x, [])


def test_non_finite_residuals_raise_fit_error_naming_the_values():
    t = np.linspace(0.0, 1.0, 10)

    def residuals(x):   # the "simulator" fails above 3 N/m; the data want 5
        return np.log(3.0 - x[0]) * 0 + (x[0] * t - 5.0 * t)

    parameters = [FitParameter("stiffness", "N/m", 1.0, 0.0, 10.0)]
    with np.errstate(invalid="ignore"), pytest.raises(FitError, match=r"stiffness = \S+ N/m"):
        fit(residuals, parameters)
    assert issubclass(FitError, ValueError)

    def many(xs):
        return np.full((len(xs), t.size), np.nan)

    with pytest.raises(FitError, match="stiffness = "):
        fit(lambda x: x[0] * t - 5.0 * t, parameters, residuals_many=many)


def test_the_solver_says_why_it_stopped_in_words():
    """scipy's status, not its raw message ("`ftol` termination condition is satisfied"):
    a converged fit names the tolerance it met, one cut off at the evaluation limit says
    it did not converge."""
    converged = fit(decay_residuals, DECAY)
    assert converged.success and converged.message.startswith("converged: ")
    assert "1×10⁻⁸" in converged.message and "`" not in converged.message
    cut = fit(decay_residuals, DECAY, max_evaluations=2)
    assert not cut.success
    assert cut.message == "stopped at the limit of 2 model evaluations, not converged."


# --------------------------------------------------------------------------- steps and sizes
def test_a_parameter_has_one_size_wherever_it_starts():
    """The size defaults to |nominal| (the larger bound magnitude for a zero nominal), is
    kept by ``replace`` when only the start moves, and must be positive and finite."""
    assert FitParameter("k", "N/m", -3.0, -5.0, 5.0).size == 3.0
    assert FitParameter("c", "1", 0.0, -2.0, 0.5).size == 2.0
    moved = replace(FitParameter("k", "N/m", 3.0, 0.0, 10.0), nominal=8.0)
    assert moved.nominal == 8.0 and moved.size == 3.0
    for bad in (0.0, -1.0, math.inf, math.nan, "1", True):
        with pytest.raises(ValueError, match="'k'.*size must be a positive finite"):
            FitParameter("k", "N/m", 3.0, 0.0, 10.0, size=bad)
    numpy_sized = FitParameter("k", "N/m", 3.0, 0.0, 10.0, size=np.float32(2.0))
    assert numpy_sized.size == 2.0 and type(numpy_sized.size) is float


def test_a_parameter_started_above_its_size_fits_the_same_whatever_its_size():
    """The solver's unit is max(|start|, size) and the step's floor the size: where a fit
    starts and stays above the size, the size plays no part, to the last bit.  (With the
    size as the solver's unit, a start 256 sizes out loosened the solver's step test for
    every parameter.)"""
    sized = [[replace(p, size=p.nominal * share) for p in DECAY] for share in (0.1, 1e-2, 1e-4)]
    fits = [fit(decay_residuals, parameters, relative_step=3e-3) for parameters in sized]
    for other in fits[1:]:
        assert np.array_equal(other.estimate, fits[0].estimate)
        assert other.evaluations == fits[0].evaluations
    # the amplitude moves from 3 m to about 4.9 m, the time constant from 0.5 s to about
    # 0.30 s: both stay above a tenth of their start, the largest size tried
    assert fits[0].estimate[0] > 0.3 and fits[0].estimate[1] > 0.05


def test_the_differences_step_a_share_of_the_value_or_of_the_size_if_larger():
    """jacobian_at on a linear map r = A·x: the stencil points worked out by hand (central
    where x ± h fits the bounds, (x, x + h, x + 2h) next to the lower bound, h = 0.01 ·
    max(|x|, size)), and the Jacobian is A to rounding."""
    a = np.array([[1.0, 2.0, -1.0], [0.5, -3.0, 4.0], [2.0, 0.0, 1.0], [1.0, 1.0, 1.0]])
    seen = []

    def many(xs):
        seen.extend(map(tuple, xs))
        return xs @ a.T

    parameters = [FitParameter("p", "Pa", 2.0e5, 1.0e5, 3.0e5),   # size 2e5, x above it
                  FitParameter("q", "m", 4.0, 0.0, 10.0, size=20.0),  # x below its size
                  FitParameter("r", "1", 0.5, 0.5, 2.0)]             # on its lower bound
    x = np.array([2.5e5, 4.0, 0.5])
    jac = jacobian_at(many, parameters, x, relative_step=0.01)
    np.testing.assert_allclose(jac, a, rtol=1e-9)
    hp, hq, hr = 0.01 * 2.5e5, 0.01 * 20.0, 0.01 * 0.5
    expected = {(2.5e5 - hp, 4.0, 0.5), (2.5e5 + hp, 4.0, 0.5),
                (2.5e5, 4.0 - hq, 0.5), (2.5e5, 4.0 + hq, 0.5),
                (2.5e5, 4.0, 0.5 + hr), (2.5e5, 4.0, 0.5 + 2 * hr), (2.5e5, 4.0, 0.5)}
    assert len(seen) == len(expected)
    for point in seen:
        assert any(np.allclose(point, e, rtol=1e-12, atol=0) for e in expected), point


def test_the_cutoff_allows_for_the_truncation_of_the_step():
    """10·h² (central) or 10·h (forward), never below 1e-6: worked out by hand."""
    assert singular_cutoff(3e-3) == pytest.approx(9e-5, rel=1e-12)
    assert singular_cutoff(3e-3, "forward") == pytest.approx(3e-2, rel=1e-12)
    assert singular_cutoff(fitting.DEFAULT_RELATIVE_STEP) == 1e-6
    with pytest.raises(ValueError, match="differences"):
        singular_cutoff(1e-3, "backward")


@pytest.mark.parametrize("differences", ["central", "forward"])
@pytest.mark.parametrize("combination, truth, kind", [
    (lambda k, m: k / m, 0.5, "ratio k/m"), (lambda k, m: k * m ** 2, 6.0, "k^0.5·m")])
def test_a_degeneracy_differenced_over_a_long_step_is_still_reported(
        monkeypatch, differences, combination, truth, kind):
    """r = exp(−q·t) − y with q = k/m or k·m²: only q is determined.  Differenced over 3e-3
    of sizes below the values, the two columns of ∂r/∂ln x differ by the step's truncation
    (a singular value of about 2e-6 to 4e-6 of the largest, above the 1e-6 floor), so the
    floor alone reports a strong correlation with finite errors; the cutoff that allows for
    the step reports the combination."""
    t = np.linspace(0.0, 3.0, 30)
    y = np.exp(-truth * t) + 0.02 * np.random.default_rng(11).standard_normal(t.size)
    parameters = [FitParameter("k", "1", 1.0, 0.1, 10.0), FitParameter("m", "1", 2.0, 0.1, 10.0,
                                                                         size=1.0)]

    def run():
        return fit(lambda x: (np.exp(-combination(*x) * t) - y) / 0.02, parameters,
                   relative_step=3e-3, differences=differences)

    result = run()
    assert np.all(np.isnan(result.standard_error))
    assert any(kind in w and "is determined by the data" in w for w in result.warnings)
    monkeypatch.setattr(fitting, "TRUNCATION_MARGIN", 0.0)
    floor_only = run()
    assert np.all(np.isfinite(floor_only.standard_error))
    assert not any("is determined by the data" in w for w in floor_only.warnings)


def test_an_undetermined_parameter_is_worded_as_the_jacobian_came():
    """By differences the residuals change with it by less than they resolve; by an
    analytic Jacobian they do not depend on it."""
    t = np.linspace(0.0, 1.0, 20)
    y = 2.0 * t
    parameters = [FitParameter("k", "N/m", 1.0, 0.0, 5.0), FitParameter("d", "m", 1.0, 0.0, 5.0)]
    differenced = fit(lambda x: x[0] * t - y, parameters)
    analytic = fit(lambda x: x[0] * t - y, parameters,
                   jacobian=lambda x: np.column_stack([t, np.zeros_like(t)]))
    [by_differences] = [w for w in differenced.warnings if w.startswith("d is not determined")]
    [by_jacobian] = [w for w in analytic.warnings if w.startswith("d is not determined")]
    assert "change with it by less than the fit's finite differences resolve" in by_differences
    assert "the residuals do not depend on it" in by_jacobian


def test_a_failed_fit_says_how_many_parameter_sets_it_evaluated():
    calls = []
    t = np.linspace(0.0, 1.0, 10)

    def residuals(x):
        calls.append(float(x[0]))
        return x[0] * t - 5.0 * t if x[0] < 3.0 else np.full(t.size, np.nan)

    with pytest.raises(FitError) as failed:
        fit(residuals, [FitParameter("stiffness", "N/m", 1.0, 0.0, 10.0)])
    assert failed.value.evaluations == len(calls) > 1


def test_a_combination_is_worded_as_the_jacobian_came():
    """Only the product is determined: by differences, to within what they resolve; by an
    analytic Jacobian, exactly."""
    t = np.linspace(0.0, 1.0, 30)
    y = noisy(6.0 * t)
    differenced = fit(lambda x: (x[0] * x[1] * t - y) / SIGMA, product_parameters("k", "m"))
    analytic = fit(lambda x: (x[0] * x[1] * t - y) / SIGMA, product_parameters("k", "m"),
                   jacobian=lambda x: np.column_stack([x[1] * t, x[0] * t]) / SIGMA)
    assert differenced.warnings[0].endswith(
        "without changing the residuals by more than the fit's finite differences resolve; "
        "their standard errors are reported as nan.")
    assert analytic.warnings[0].endswith(
        "without changing the residuals; their standard errors are reported as nan.")


def test_a_batch_of_the_wrong_shape_is_named_before_any_row_is_known():
    parameters = [FitParameter("k", "N/m", 1.0, 0.0, 5.0)]
    with pytest.raises(FitError, match=r"shape \(2,\) for 2 parameter sets; expected \(2, m\)"):
        jacobian_at(lambda xs: np.zeros(len(xs)), parameters, [1.0])



def test_a_forward_fit_reports_the_statistics_of_central_differences():
    """A fit found with forward differences over 3e-3 takes its standard errors from central
    ones at the optimum: they agree with the analytic Jacobian's s²(JᵀJ)⁻¹ there to the
    central differences' O(h²); first-order ones would carry an error of order h and hide
    every direction weaker than about 3 % of the strongest."""
    forward = fit(decay_residuals, DECAY, relative_step=3e-3, differences="forward")
    jac = decay_jacobian(forward.estimate)
    r = decay_residuals(forward.estimate)
    se = np.sqrt(np.diag(r @ r / (T.size - 2) * np.linalg.inv(jac.T @ jac)))
    np.testing.assert_allclose(forward.standard_error, se, rtol=1e-4)
    assert forward.warnings == ()
