"""LS-SVM engines against independent references.

* the dual LS-SVM against scikit-learn's KernelRidge (a separate implementation) and
  against the full KKT system assembled here with scipy's cdist;
* the fixed-size LS-SVM against the dual LS-SVM, its Rényi selection against the entropy
  computed here from its definition;
* tuning against a cost whose minimum is known, NARX against simulated systems whose
  equations are written here, the NARX windows against rows written out by hand;
* metrics and whiteness bounds against hand-computed values.
"""

import math

import numpy as np
import pytest
from scipy.spatial.distance import cdist
from sklearn.kernel_ridge import KernelRidge
from threadpoolctl import threadpool_limits

from certkit.ident.fixed_size import FixedSizeLSSVM, select_prototypes
from certkit.ident.lssvm import LSSVMRegressor, kfold_cost, rbf_kernel, tune
from certkit.ident.narx import NARX, narx_regressors
from certkit.ident.validation import fit_percent, max_abs_error, nrmse, residual_analysis, rmse


@pytest.fixture(autouse=True, scope="module")
def one_blas_thread():
    """Small matrices: one BLAS thread is faster and does not collapse on a busy machine."""
    with threadpool_limits(limits=1):
        yield


def gram(x, z, sigma2):
    """K = exp(−‖x − z‖²/σ²) from explicit pairwise distances (not certkit's expansion)."""
    return np.exp(-cdist(np.atleast_2d(x), np.atleast_2d(z), "sqeuclidean") / sigma2)


@pytest.fixture
def regression_data():
    rng = np.random.default_rng(1)
    X = rng.uniform(-3.0, 3.0, (150, 2))
    y = np.sinc(X[:, 0]) + 0.3 * X[:, 1] + 2.0 + 0.05 * rng.standard_normal(150)
    return X, y, rng.uniform(-3.0, 3.0, (40, 2))


# --------------------------------------------------------------------------- kernel, dual
def test_rbf_kernel_has_no_factor_two():
    # ‖(0,0) − (3,4)‖² = 25, σ² = 5: exp(−5), LS-SVMlab convention (not exp(−25/10))
    assert rbf_kernel([[0.0, 0.0]], [[3.0, 4.0]], 5.0)[0, 0] == pytest.approx(math.exp(-5.0))


def test_dual_solution_satisfies_the_kkt_system(regression_data):
    X, y, _ = regression_data
    gamma, sigma2 = 10.0, 2.0
    model = LSSVMRegressor(gamma=gamma, sigma2=sigma2).fit(X, y)
    n = y.size
    system = np.zeros((n + 1, n + 1))
    system[0, 1:] = system[1:, 0] = 1.0
    system[1:, 1:] = gram(X, X, sigma2) + np.eye(n) / gamma
    unknowns = np.concatenate([[model.b_], model.alpha_])
    rhs = np.concatenate([[0.0], y])
    assert np.max(np.abs(system @ unknowns - rhs)) < 1e-10
    assert np.allclose(unknowns, np.linalg.solve(system, rhs), rtol=0, atol=1e-9)


def test_bias_free_lssvm_equals_kernel_ridge_on_centred_data(regression_data):
    # Without b the dual is (Ω + I/γ)α = y: KernelRidge with ridge 1/γ and
    # sklearn's gamma = 1/σ².  Compared: dual coefficients and predictions.
    X, y, X_test = regression_data
    gamma, sigma2 = 10.0, 2.0
    centred = y - y.mean()
    ours = LSSVMRegressor(gamma=gamma, sigma2=sigma2, bias=False).fit(X, centred)
    reference = KernelRidge(alpha=1 / gamma, kernel="rbf", gamma=1 / sigma2).fit(X, centred)
    assert ours.b_ == 0.0
    assert np.allclose(ours.alpha_, reference.dual_coef_, rtol=0, atol=1e-6)
    assert np.allclose(ours.predict(X_test), reference.predict(X_test), rtol=0, atol=1e-6)


def test_lssvm_with_bias_is_kernel_ridge_on_y_minus_b(regression_data):
    # With b the second block row reads (Ω + I/γ)α = y − b·1, so KernelRidge fitted to
    # y − b_ must return α exactly, and KernelRidge + b_ the same predictions.  The bias
    # is not the mean of y (Σα = 0 fixes it), so centring y alone would not match.
    X, y, X_test = regression_data
    gamma, sigma2 = 10.0, 2.0
    ours = LSSVMRegressor(gamma=gamma, sigma2=sigma2).fit(X, y)
    reference = KernelRidge(alpha=1 / gamma, kernel="rbf", gamma=1 / sigma2).fit(X, y - ours.b_)
    assert abs(ours.alpha_.sum()) < 1e-9
    assert abs(ours.b_ - y.mean()) > 1e-3
    assert np.allclose(ours.alpha_, reference.dual_coef_, rtol=0, atol=1e-6)
    assert np.allclose(ours.predict(X_test), reference.predict(X_test) + ours.b_,
                       rtol=0, atol=1e-6)


@pytest.mark.parametrize("kwargs, X, y, message", [
    ({}, np.zeros((5, 2)), np.zeros(4), "expected 5 samples, found 4"),
    ({}, np.zeros((0, 2)), np.zeros(0), "non-empty"),
    ({}, np.zeros((2, 2, 2)), np.zeros(2), "n_samples, n_features"),
    ({}, np.array([[0.0], [np.nan]]), np.zeros(2), "NaN"),
    ({}, np.zeros((2, 1)), np.array([0.0, np.inf]), "NaN or infinite"),
    ({"gamma": 0.0}, np.zeros((2, 1)), np.zeros(2), "gamma: expected a positive"),
    ({"sigma2": -1.0}, np.zeros((2, 1)), np.zeros(2), "sigma2: expected a positive"),
])
@pytest.mark.parametrize("estimator", [LSSVMRegressor, FixedSizeLSSVM])
def test_bad_data_and_hyper_parameters_are_refused(estimator, kwargs, X, y, message):
    with pytest.raises(ValueError, match=message):
        estimator(**kwargs).fit(X, y)


def test_predict_before_fit_and_wrong_width_are_refused(regression_data):
    X, y, _ = regression_data
    with pytest.raises(ValueError, match="not fitted"):
        LSSVMRegressor().predict(X)
    with pytest.raises(ValueError, match="3 features"):
        LSSVMRegressor().fit(X, y).predict(np.zeros((2, 3)))


# --------------------------------------------------------------------------- fixed size
def test_fixed_size_with_all_points_as_prototypes_is_the_dual_lssvm(regression_data):
    X, y, X_test = regression_data
    full = LSSVMRegressor(gamma=10.0, sigma2=2.0).fit(X, y)
    fixed = FixedSizeLSSVM(gamma=10.0, sigma2=2.0, prototypes=len(y)).fit(X, y)
    assert np.allclose(fixed.predict(X_test), full.predict(X_test), rtol=0, atol=1e-5)
    assert fixed.b_ == pytest.approx(full.b_, abs=1e-5)


def test_fixed_size_with_few_prototypes_stays_close_on_a_smooth_function():
    rng = np.random.default_rng(2)
    x = np.sort(rng.uniform(-4.0, 4.0, 1500))
    y = np.sin(x) + 0.5 * np.cos(2 * x) + 0.05 * rng.standard_normal(x.size)
    grid = np.linspace(-3.8, 3.8, 200)
    full = LSSVMRegressor(gamma=100.0, sigma2=0.5).fit(x, y).predict(grid)
    fixed = FixedSizeLSSVM(gamma=100.0, sigma2=0.5, prototypes=40).fit(x, y)
    assert fixed.support_.shape == (40, 1)
    assert np.max(np.abs(fixed.predict(grid) - full)) < 0.02   # signal amplitude ≈ 1.5


def test_renyi_selection_is_seeded_and_raises_the_entropy():
    rng = np.random.default_rng(3)
    X = np.concatenate([rng.normal(0.0, 0.2, (400, 2)), rng.uniform(-3, 3, (100, 2))])

    def entropy(points):          # quadratic Rényi entropy, Parzen estimate (definition)
        return -np.log(gram(points, points, 0.5).mean())

    first = select_prototypes(X, 30, 0.5, random_state=7)
    assert np.array_equal(first, select_prototypes(X, 30, 0.5, random_state=7))
    assert len(set(first.tolist())) == 30
    random_sets = [entropy(X[rng.choice(500, 30, replace=False)]) for _ in range(20)]
    assert entropy(X[first]) > max(random_sets)
    a = FixedSizeLSSVM(gamma=10.0, sigma2=1.0, prototypes=30, random_state=4).fit(X, X[:, 0])
    b = FixedSizeLSSVM(gamma=10.0, sigma2=1.0, prototypes=30, random_state=4).fit(X, X[:, 0])
    assert np.array_equal(a.prototype_indices_, b.prototype_indices_)


def test_fixed_size_accepts_given_prototypes(regression_data):
    X, y, _ = regression_data
    model = FixedSizeLSSVM(gamma=10.0, sigma2=2.0, prototypes=X[:20]).fit(X, y)
    assert model.prototype_indices_ is None
    assert np.array_equal(model.support_, X[:20])


# --------------------------------------------------------------------------- tuning
def test_tune_finds_the_known_minimum_of_a_cost():
    def bowl(gamma, sigma2):      # minimum at γ = 100, σ² = 10^0.5
        return (math.log10(gamma) - 2.0) ** 2 + 3.0 * (math.log10(sigma2) - 0.5) ** 2

    result = tune(bowl, gamma=(1e-2, 1e6), sigma2=(1e-2, 1e3), grid=5)
    assert math.log10(result.gamma) == pytest.approx(2.0, abs=0.05)
    assert math.log10(result.sigma2) == pytest.approx(0.5, abs=0.05)
    fixed = tune(bowl, gamma=10.0, sigma2=(1e-2, 1e3), grid=5)
    assert fixed.gamma == 10.0
    assert math.log10(fixed.sigma2) == pytest.approx(0.5, abs=0.05)


def test_tuning_by_cross_validation_beats_a_bad_start_and_is_deterministic():
    rng = np.random.default_rng(4)
    x = rng.uniform(-3.0, 3.0, 200)
    y = np.sinc(x) + 0.05 * rng.standard_normal(x.size)
    cost = kfold_cost(lambda g, s: LSSVMRegressor(gamma=g, sigma2=s), x, y, folds=5)
    bad = (1e-2, 1e2)                               # over-smoothed, under-fitted
    refined = tune(cost, start=bad, max_refine=40)
    assert refined.cost < cost(*bad) / 10
    first = tune(cost, grid=4, max_refine=20)
    second = tune(cost, grid=4, max_refine=20)
    assert first == second
    assert first.cost < cost(*bad) / 10
    assert first.cost == min(c for _, _, c in first.evaluations)


# --------------------------------------------------------------------------- NARX
def test_narx_rows_are_built_inside_each_experiment():
    u = [np.array([1.0, 2.0, 3.0, 4.0]), np.array([5.0, 6.0, 7.0])]
    y = [np.array([10.0, 20.0, 30.0, 40.0]), np.array([50.0, 60.0, 70.0])]
    X, target = narx_regressors(u, y, na=2, nb=1, delay=1)   # [y_{t−1}, y_{t−2}, u_{t−1}]
    assert np.array_equal(X, [[20, 10, 2], [30, 20, 3], [60, 50, 6]])
    assert np.array_equal(target, [30, 40, 70])
    X0, _ = narx_regressors(u[0], y[0], na=1, nb=2, delay=0)  # [y_{t−1}, u_t, u_{t−1}]
    assert np.array_equal(X0, [[10, 2, 1], [20, 3, 2], [30, 4, 3]])


def nonlinear_system(u, noise):
    """y_t = 0.5 y_{t−1} − 0.2 y_{t−2} + tanh(u_{t−1}) + 0.1 u_{t−2}² + e_t."""
    y = np.zeros_like(u)
    for t in range(2, u.size):
        y[t] = (0.5 * y[t - 1] - 0.2 * y[t - 2] + math.tanh(u[t - 1])
                + 0.1 * u[t - 2] ** 2 + noise[t])
    return y


@pytest.fixture(scope="module")
def experiments():
    rng = np.random.default_rng(5)
    us = [rng.uniform(-2.0, 2.0, n) for n in (300, 300, 400)]
    ys = [nonlinear_system(u, 0.01 * rng.standard_normal(u.size)) for u in us]
    return us, ys


def test_narx_windows_do_not_cross_experiments(experiments):
    us, ys = experiments
    separate = NARX(2, 2, delay=1, gamma=100.0, sigma2=5.0).fit(us[:2], ys[:2])
    joined = NARX(2, 2, delay=1, gamma=100.0, sigma2=5.0).fit(np.concatenate(us[:2]),
                                                        np.concatenate(ys[:2]))
    assert separate.n_rows_ == 300 + 300 - 2 * 2
    assert joined.n_rows_ == 600 - 2
    # every support row of the two-experiment model is a window of one experiment
    rows = separate.regressor_.support_
    restored = np.column_stack([rows[:, :2] * separate.y_std_ + separate.y_mean_,
                                rows[:, 2:] * separate.u_std_ + separate.u_mean_])
    by_hand = [[y[t - 1], y[t - 2], u[t - 1], u[t - 2]]
               for u, y in zip(us[:2], ys[:2]) for t in range(2, 300)]
    assert np.allclose(restored, by_hand, rtol=0, atol=1e-12)


def test_tuned_narx_simulates_held_out_data(experiments):
    us, ys = experiments
    model = NARX(2, 2, delay=1, tuning={"grid": 4, "max_refine": 15}).fit(us[:2], ys[:2])
    assert model.tuning_ is not None and model.gamma_ == model.tuning_.gamma
    u, y = us[2], ys[2]
    simulated = model.simulate(u, y[:10])
    one_step = model.predict(u, y)
    assert np.array_equal(simulated[:10], y[:10])
    free_run_error = nrmse(y[10:], simulated[10:])
    assert free_run_error < 0.05
    assert nrmse(y[10:], one_step[10:]) <= free_run_error
    # the fast simulator equals the plain recursion written out with predict
    reg, recursion = model.regressor_, (y[:10] - model.y_mean_) / model.y_std_
    scaled_u = (u - model.u_mean_) / model.u_std_
    for t in range(10, u.size):
        row = [recursion[t - 1], recursion[t - 2], scaled_u[t - 1], scaled_u[t - 2]]
        recursion = np.append(recursion, reg.predict(np.array([row]))[0])
    assert np.allclose(recursion * model.y_std_ + model.y_mean_, simulated,
                       rtol=0, atol=1e-9)


def test_fixed_size_narx_and_lists_of_experiments(experiments):
    us, ys = experiments
    model = NARX(2, 2, delay=1, gamma=1e3, sigma2=5.0, engine="fixed-size",
                 prototypes=80).fit(us[:2], ys[:2])
    assert model.regressor_.support_.shape == (80, 4)
    simulated = model.simulate([us[2], us[1]], [ys[2][:5], ys[1][:5]])
    assert isinstance(simulated, list) and len(simulated) == 2
    assert nrmse(ys[2][5:], simulated[0][5:]) < 0.1


def test_narx_refuses_short_windows_and_mismatched_experiments(experiments):
    us, ys = experiments
    model = NARX(3, 2, delay=1, gamma=10.0, sigma2=1.0).fit(us[0], ys[0])
    with pytest.raises(ValueError, match="between init_length = 3 and"):
        model.simulate(us[1], ys[1][:2])
    with pytest.raises(ValueError, match="found 2 and 1"):
        NARX(2, 2).fit(us[:2], ys[:1] + [])
    with pytest.raises(ValueError, match="engine"):
        NARX(engine="sparse").fit(us[0], ys[0])


# --------------------------------------------------------------------------- metrics
def test_metrics_by_hand():
    y, y_hat = np.array([1.0, 2.0, 3.0, 4.0]), np.array([1.0, 2.0, 3.0, 5.0])
    assert rmse(y, y_hat) == pytest.approx(0.5)                       # √(1/4)
    assert nrmse(y, y_hat) == pytest.approx(0.5 / math.sqrt(1.25))    # std = √1.25
    assert fit_percent(y, y_hat) == pytest.approx(100 * (1 - 1 / math.sqrt(5)))
    assert max_abs_error(y, y_hat) == 1.0


def test_white_noise_passes_and_coloured_residuals_fail():
    rng = np.random.default_rng(6)
    n = 5000
    white, u = rng.standard_normal(n), rng.standard_normal(n)
    result = residual_analysis(white, u)
    assert result.bound == pytest.approx(2.5758 / math.sqrt(n), rel=1e-4)
    assert result.lags.tolist() == list(range(1, 26))
    assert result.cross_lags.tolist() == list(range(-25, 26))
    assert result.autocorrelation_ok.mean() >= 0.95
    assert result.cross_correlation_ok.mean() >= 0.95

    ar1 = np.zeros(n)                       # e_t = 0.5 e_{t−1} + w_t: r(1) ≈ 0.5
    for t in range(1, n):
        ar1[t] = 0.5 * ar1[t - 1] + white[t]
    coloured = residual_analysis(ar1)
    assert not coloured.autocorrelation_ok[0] and not coloured.white
    assert coloured.autocorrelation[0] == pytest.approx(0.5, abs=0.05)

    leaking = white.copy()                  # residual still holds 0.8·u_{t−2}
    leaking[2:] += 0.8 * u[:-2]
    cross = residual_analysis(leaking, u)
    assert not cross.cross_correlation_ok[cross.cross_lags == 2][0]
    assert cross.cross_correlation_ok[cross.cross_lags == -2][0]


def test_refinement_may_start_from_a_grid_end_point():
    # a cost falling towards the upper σ² bound: its best grid point is the bound itself,
    # which after the log10 round trip can sit a rounding error outside the range

    def cost(gamma, sigma2):
        return 1.0 / sigma2 + (math.log10(gamma) - 2.0) ** 2

    scale = 0.7849569384544595  # found by search: 10**log10(10·scale) rounds above 10·scale
    assert math.log10(10 ** np.linspace(math.log10(1e-3 * scale), math.log10(10 * scale), 5)[-1]) \
        > math.log10(10 * scale)
    ranges = {"gamma": (1e0, 1e4), "sigma2": (1e-3 * scale, 10 * scale)}
    coarse = tune(cost, grid=5, refine=False, **ranges)
    assert coarse.sigma2 == pytest.approx(10 * scale)
    refined = tune(cost, grid=5, start=(coarse.gamma, coarse.sigma2), max_refine=10, **ranges)
    assert refined.cost <= coarse.cost
