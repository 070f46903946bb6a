"""The identification estimators as a notebook user meets them (issue 17, part 1).

Every expected number is worked out here, independently of the code under test: the
coefficients of the difference equations that generate the data, scipy's ``lfilter`` of the
true system, the exact dual LS-SVM against its fixed-size primal, invariances that must hold
by construction (units of u, forms of the same data), and cost functions written here whose
minimum is known.
"""

import math
import tracemalloc

import numpy as np
import pandas as pd
import pytest
from scipy.signal import lfilter
from sklearn.base import clone
from sklearn.frozen import FrozenEstimator
from sklearn.utils.estimator_checks import parametrize_with_checks
from threadpoolctl import threadpool_limits

from certkit.errors import CertkitInputError, DataInputError
from certkit.ident import (ARX, NARX, CostSurface, EnsembleModel, FreeRunCV,
                           HammersteinLSSVM, WienerLSSVM, nrmse, tune_free_run)


@pytest.fixture(autouse=True, scope="module")
def one_blas_thread():
    """Small matrices: one BLAS thread is faster and does not collapse on a busy machine."""
    with threadpool_limits(limits=1):
        yield


# --------------------------------------------------------------------- scikit-learn checks
#: Checks that do not apply to models of time series, each with the reason.
NOT_APPLICABLE = {
    "check_methods_sample_order_invariance":
        "rows are consecutive time steps: reordering them changes the record, so the "
        "free-run prediction changes (as it must)",
    "check_methods_subset_invariance":
        "a sample's prediction depends on the samples before it (the model's state), so "
        "predicting a subset of rows cannot give the same values",
    "check_fit1d":
        "a 1-D input is deliberately one experiment with one input channel, not an error",
    "check_fit2d_predict1d":
        "a 1-D input is one input channel, so a model fitted on 3 channels refuses it with "
        "certkit's channel-count message, not scikit-learn's 'Reshape your data'",
    "check_supervised_y_2d":
        "an (n, 1) output column is accepted silently as one output record (certkit reads "
        "columns as records), where scikit-learn expects a DataConversionWarning",
    "check_dtype_object":
        "non-numeric input raises certkit's DataInputError (a ValueError, like every bad "
        "input of certkit), where the check wants a TypeError",
}


def expected_failures(estimator):
    return NOT_APPLICABLE


@parametrize_with_checks(
    [ARX(2, 2), NARX(2, 2, gamma=10.0, sigma2=5.0),
     HammersteinLSSVM(2, 2, gamma=10.0, sigma2=1.0, normalisation="unit_norm"),
     HammersteinLSSVM(2, 2, gamma=10.0, sigma2=1.0, normalisation="unit_norm",
                      engine="fixed-size", prototypes=150),
     WienerLSSVM(2, 2, gamma=10.0, sigma2=1.0),
     WienerLSSVM(2, 2, gamma=10.0, sigma2=1.0, engine="fixed-size", prototypes=30),
     NARX(2, 2, gamma=10.0, sigma2=5.0, engine="auto"),
     # the checks' data are not a dynamic system: a cubic recursion fed its own outputs
     # diverges on some of them, so the bound that keeps a free run finite is set
     NARX(2, 2, gamma=10.0, sigma2=5.0, engine="fixed-size", prototypes=150, linear=True,
          cubic=2, cubic_terms="all", output_bound="range"),
     EnsembleModel([ARX(2, 2), NARX(2, 2, gamma=10.0, sigma2=5.0)])],
    expected_failed_checks=expected_failures)
def test_scikit_learn_checks(estimator, check):
    check(estimator)


# --------------------------------------------------------------------- ARX
def second_order(u, intercept=0.0):
    """y_t = 1.2 y_{t−1} − 0.5 y_{t−2} + 0.3 u_{t−1} + 0.2 u_{t−2} + c (written as a loop)."""
    y = np.zeros(u.size)
    for t in range(u.size):
        y[t] = intercept
        y[t] += 1.2 * y[t - 1] - 0.5 * y[t - 2] if t >= 2 else (1.2 * y[t - 1] if t else 0)
        y[t] += 0.3 * u[t - 1] if t >= 1 else 0.0
        y[t] += 0.2 * u[t - 2] if t >= 2 else 0.0
    return y


def test_arx_recovers_its_difference_equation_with_delay_and_intercept():
    u = np.random.default_rng(0).standard_normal(400)
    y = second_order(u, intercept=0.7)
    model = ARX(na=2, nb=2, delay=1).fit(u, y)
    assert model.a_ == pytest.approx([1.2, -0.5], abs=1e-10)
    assert model.b_ == pytest.approx([0.3, 0.2], abs=1e-10)
    assert model.intercept_ == pytest.approx(0.7, abs=1e-10)
    # steady state of the intercept: c / (1 − Σa) = 0.7 / 0.3
    assert model.static_gain_ == pytest.approx(0.5 / 0.3)
    without = ARX(na=2, nb=2, delay=1, fit_intercept=False).fit(u, y)
    assert without.intercept_ == 0.0 and abs(without.a_[0] - 1.2) > 1e-3


def test_arx_with_two_input_channels_recovers_both_polynomials():
    rng = np.random.default_rng(1)
    u = rng.standard_normal((600, 2))
    # y_t = 0.6 y_{t−1} + 1.0 u1_t − 0.4 u1_{t−1} + 0.5 u2_{t−2}  (u2 delayed by 2)
    y = lfilter([1.0, -0.4], [1.0, -0.6], u[:, 0]) + lfilter([0, 0, 0.5], [1.0, -0.6], u[:, 1])
    model = ARX(na=1, nb=[2, 1], delay=[0, 2], fit_intercept=False).fit(u, y)
    assert model.a_ == pytest.approx([0.6], abs=1e-10)
    assert model.b_[0] == pytest.approx([1.0, -0.4], abs=1e-10)
    assert model.b_[1] == pytest.approx([0.5, 0.0], abs=1e-10)      # zero-padded row
    assert model.static_gain_ == pytest.approx([0.6 / 0.4, 0.5 / 0.4])
    assert model.n_features_in_ == 2
    assert np.allclose(model.predict(u), y, atol=1e-9)                # free run from rest


def test_simulate_from_the_true_initial_outputs_reproduces_noise_free_data():
    u = np.random.default_rng(2).standard_normal(300)
    y = second_order(u, intercept=0.7)
    model = ARX(na=2, nb=2, delay=1).fit(u[:200], y[:200])
    # a record that does not start at rest: begin at sample 150, give its true first outputs
    part_u, part_y = u[150:], y[150:]
    simulated = model.simulate(part_u, y_init=part_y[:2])
    assert np.max(np.abs(simulated - part_y)) < 1e-9
    from_rest = model.simulate(part_u)
    assert np.max(np.abs(from_rest[:20] - part_y[:20])) > 0.1          # the start matters


def test_the_forms_of_one_record_give_identical_fits():
    rng = np.random.default_rng(3)
    u = rng.standard_normal(120)
    y = second_order(u) + 0.01 * rng.standard_normal(120)
    forms = [(u, y), (u[:, None], y[:, None]), (pd.Series(u), pd.Series(y)),
             (u.tolist(), y.tolist()), (pd.DataFrame({"load": u}), y),
             ([[v] for v in u], list(y))]
    for make in (lambda: ARX(2, 2, delay=1), lambda: NARX(2, 2, gamma=50.0, sigma2=4.0),
                 lambda: HammersteinLSSVM(2, 2, delay=1, gamma=1e3, sigma2=1.0)):
        reference = make().fit(u, y).predict(u)
        for form_u, form_y in forms:
            model = make().fit(form_u, form_y)
            assert model.n_features_in_ == 1
            assert np.array_equal(model.predict(form_u), reference), type(form_u)


def test_a_list_of_arrays_is_several_experiments_and_lags_stay_inside():
    rng = np.random.default_rng(4)
    us = [rng.standard_normal(80) for _ in range(2)]
    ys = [second_order(u) for u in us]
    model = ARX(2, 2, delay=1).fit(us, ys)           # each experiment from rest: exact
    assert model.a_ == pytest.approx([1.2, -0.5], abs=1e-10)
    joined = ARX(2, 2, delay=1).fit(np.concatenate(us), np.concatenate(ys))
    assert abs(joined.a_[0] - 1.2) > 1e-4            # the joint's rows are wrong equations
    simulated = model.simulate([pd.Series(u) for u in us])
    assert isinstance(simulated, list) and np.allclose(simulated[1], ys[1], atol=1e-9)


# --------------------------------------------------------------------- parameters
@pytest.mark.parametrize("estimator", [
    ARX(3, [1, 2], delay=[0, 1], fit_intercept=False),
    NARX(3, 1, delay=0, gamma=5.0, sigma2=2.0, engine="fixed-size", prototypes=40),
    HammersteinLSSVM(1, 3, gamma=2e3, sigma2=0.5, normalisation="b0", refine_linear=True,
                     delay=1, input_scale=2.0, engine="fixed-size", prototypes=30,
                     random_state=5),
    WienerLSSVM(2, 3, delay=1, gamma=10.0, sigma2=0.3, input_scale=1.0,
                tuning={"target": 0.1})])
def test_clone_and_get_params_round_trip(estimator):
    params = estimator.get_params()
    copy = clone(estimator)
    assert copy is not estimator and copy.get_params() == params
    assert type(estimator)(**params).get_params() == params
    changed = clone(estimator).set_params(na=4)
    assert changed.na == 4 and estimator.na == params["na"]


def test_a_given_linear_block_survives_clone_when_frozen():
    u = np.random.default_rng(5).standard_normal(300)
    block = ARX(2, 2, delay=1, fit_intercept=False).fit(u, second_order(u))
    y = np.tanh(second_order(u) * 0.6 + 0.2)
    wiener = WienerLSSVM(gamma=1e4, sigma2=0.5, linear_block=FrozenEstimator(block))
    fitted = clone(wiener).fit(u, y)
    assert fitted.raw_linear_ is block
    with pytest.raises(DataInputError, match="expected a fitted ARX"):
        clone(WienerLSSVM(gamma=1.0, sigma2=1.0, linear_block=block)).fit(u, y)


# --------------------------------------------------------------------- Hammerstein
def hammerstein_record(u, delay=0):
    """x = u + 0.5 u³; y_t = 1.2 y_{t−1} − 0.5 y_{t−2} + x_{t−d} + 0.5 x_{t−d−1}."""
    x = u + 0.5 * u ** 3
    forcing = np.convolve(x, [0.0] * delay + [1.0, 0.5])[:u.size]
    return lfilter([1.0], [1.0, -1.2, 0.5], forcing)


def test_hammerstein_delay_and_standardised_sigma2():
    u = np.random.default_rng(6).uniform(-1.0, 1.0, 400)
    y = hammerstein_record(u, delay=2)
    model = HammersteinLSSVM(2, 2, delay=2, gamma=1e6, sigma2=1.0).fit(u, y)
    assert model.a_ == pytest.approx([1.2, -0.5], rel=0.01)
    # unit static gain: b = (1, 0.5)·(1 − 1.2 + 0.5)/1.5
    assert model.b_ == pytest.approx(np.array([1.0, 0.5]) * 0.3 / 1.5, rel=0.01)
    # σ² is in standardised units: the same data in mV instead of V give the same model
    scaled = HammersteinLSSVM(2, 2, delay=2, gamma=1e6, sigma2=1.0).fit(1e3 * u, y)
    assert scaled.a_ == pytest.approx(model.a_, rel=1e-6)
    grid = np.linspace(-0.9, 0.9, 7)
    assert scaled.nonlinearity(1e3 * grid) == pytest.approx(model.nonlinearity(grid), abs=1e-6)
    assert scaled.input_scale_[0] == pytest.approx(1e3 * model.input_scale_[0])


def test_hammerstein_fixed_size_with_every_sample_a_prototype_is_the_exact_dual():
    u = np.random.default_rng(7).uniform(-1.0, 1.0, 200)
    y = hammerstein_record(u) + 0.01 * np.random.default_rng(8).standard_normal(200)
    exact = HammersteinLSSVM(2, 2, gamma=1e3, sigma2=0.5).fit(u, y)
    every = HammersteinLSSVM(2, 2, gamma=1e3, sigma2=0.5, engine="fixed-size",
                             prototypes=200).fit(u, y)
    few = HammersteinLSSVM(2, 2, gamma=1e3, sigma2=0.5, engine="fixed-size",
                           prototypes=30).fit(u, y)
    assert every.a_ == pytest.approx(exact.a_, abs=1e-6)
    assert every.b_ == pytest.approx(exact.b_, abs=1e-6)
    assert every.d_ == pytest.approx(exact.d_, abs=1e-6)
    reference = exact.simulate(u, y[:2])
    assert np.max(np.abs(every.simulate(u, y[:2]) - reference)) < 1e-5 * np.std(y)
    # 30 prototypes on a 1-D input: within 1 % of the exact dual's free run
    assert nrmse(reference[2:], few.simulate(u, y[:2])[2:]) < 0.01


def test_hammerstein_fixed_size_fits_50k_samples_in_bounded_memory():
    rng = np.random.default_rng(9)
    u = rng.uniform(-1.0, 1.0, 50_000)
    y = hammerstein_record(u) + 0.01 * rng.standard_normal(u.size)
    tracemalloc.start()
    model = HammersteinLSSVM(2, 2, gamma=1e4, sigma2=0.5, engine="fixed-size",
                             prototypes=50).fit(u, y)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    # the exact dual would need 50 000² doubles = 20 GB; the primal is O(N + (nb M)²)
    assert peak < 100 * 2 ** 20
    assert model.a_ == pytest.approx([1.2, -0.5], rel=0.01)


def test_hammerstein_with_two_input_channels():
    rng = np.random.default_rng(10)
    u = rng.uniform(-1.0, 1.0, (400, 2))
    x = u[:, 0] + 0.5 * u[:, 1] ** 2              # f(u1, u2), one static map of both
    y = lfilter([1.0, 0.5], [1.0, -1.2, 0.5], x)
    model = HammersteinLSSVM(2, 2, gamma=1e6, sigma2=2.0).fit(u, y)
    assert model.a_ == pytest.approx([1.2, -0.5], rel=0.01)
    held = rng.uniform(-1.0, 1.0, (300, 2))
    truth = lfilter([1.0, 0.5], [1.0, -1.2, 0.5], held[:, 0] + 0.5 * held[:, 1] ** 2)
    assert nrmse(truth[2:], model.simulate(held, truth[:2])[2:]) < 0.02


# --------------------------------------------------------------------- Wiener
def wiener_record(u):
    """z = G(q)u with G = (0.3 + 0.2 q⁻¹)/(1 − 1.2 q⁻¹ + 0.5 q⁻²) (static gain 5/3),
    y = tanh(0.6 z) + 0.1."""
    return np.tanh(0.6 * lfilter([0.3, 0.2], [1.0, -1.2, 0.5], u)) + 0.1


def test_wiener_from_recorded_data_in_one_call():
    rng = np.random.default_rng(11)
    u, held = rng.standard_normal(800), rng.standard_normal(400)
    model = WienerLSSVM(na=2, nb=2).fit(u, wiener_record(u))    # f tuned by static_map
    # the best linear approximation of a Wiener system has the poles of G (Bussgang)
    assert np.sort(np.abs(model.linear_.poles_)) == pytest.approx([math.sqrt(0.5)] * 2,
                                                                  rel=0.05)
    assert model.linear_.static_gain_ == pytest.approx(1.0)
    free_run = nrmse(wiener_record(held), model.predict(held))
    linear_only = ARX(2, 2).fit(u, wiener_record(u)).predict(held)
    assert free_run < 0.05 and free_run < 0.5 * nrmse(wiener_record(held), linear_only)
    with pytest.raises(DataInputError, match="no one-step-ahead predictor"):
        model.predict(held, wiener_record(held))


def test_wiener_with_two_input_channels_adds_them_in_one_linear_block():
    # z = G₁(q)u₁ + G₂(q)u₂ with one denominator (poles 0.6 ± 0.374i, |p| = √0.5), y = tanh(z/2)
    def record(u):
        return np.tanh(0.5 * (lfilter([0.3, 0.2], [1.0, -1.2, 0.5], u[:, 0])
                              + lfilter([0.0, 0.4], [1.0, -1.2, 0.5], u[:, 1])))

    rng = np.random.default_rng(20)
    u, held = rng.standard_normal((800, 2)), rng.standard_normal((400, 2))
    model = WienerLSSVM(na=2, nb=2).fit(u, record(u))
    assert np.abs(model.linear_.poles_) == pytest.approx([math.sqrt(0.5)] * 2, rel=0.05)
    linear_only = ARX(2, 2).fit(u, record(u)).predict(held)
    free_run = nrmse(record(held), model.predict(held))
    assert free_run < 0.05 and free_run < 0.5 * nrmse(record(held), linear_only)


def test_wiener_simulation_from_initial_outputs_beats_rest_on_a_record_in_motion():
    rng = np.random.default_rng(12)
    u = rng.standard_normal(1200)
    y = wiener_record(u)
    model = WienerLSSVM(na=2, nb=2).fit(u[:800], y[:800])
    part_u, part_y = u[900:], y[900:]                 # starts in motion, not at rest
    started = model.simulate(part_u, part_y[:2])
    rested = model.simulate(part_u)
    assert np.array_equal(started[:2], part_y[:2])
    early = slice(2, 12)
    assert nrmse(part_y[early], started[early]) < 0.5 * nrmse(part_y[early], rested[early])


# --------------------------------------------------------------------- bad input
@pytest.mark.parametrize("fit_args, message", [
    ((np.r_[np.zeros(19), np.nan], np.zeros(20)), "finite values, found NaN .*sample 19"),
    ((np.zeros(20), np.zeros(19)), "same number of samples, found 20 and 19"),
    ((["a"] * 20, np.zeros(20)), "expected numbers"),
    (([np.zeros(20)], np.zeros(20)), "both as one experiment"),
    (([np.zeros(20), np.zeros(20)], [np.zeros(20)]), "found 2 and 1"),
    ((np.zeros(2), np.zeros(2)), "found 2 sample"),
    ((np.zeros((20, 2, 2)), np.zeros(20)), r"found shape \(20, 2, 2\)"),
])
def test_bad_data_get_certkit_input_errors(fit_args, message):
    with pytest.raises(CertkitInputError, match=message) as raised:
        ARX(2, 2).fit(*fit_args)
    assert isinstance(raised.value, ValueError)


def test_bad_use_after_fit_gets_certkit_input_errors():
    u = np.random.default_rng(13).standard_normal((50, 2))
    model = NARX(2, 1, gamma=10.0, sigma2=3.0).fit(u, u[:, 0])
    with pytest.raises(DataInputError, match="X has 1 features, but NARX is expecting 2"):
        model.simulate(u[:, 0])
    with pytest.raises(DataInputError, match="between init_length = 2 and len"):
        model.simulate(u, y_init=[0.0])
    with pytest.raises(DataInputError, match="nb: expected one value per input channel"):
        NARX(2, [1, 2, 3], gamma=1.0, sigma2=1.0).fit(u, u[:, 0])
    with pytest.raises(DataInputError, match="delay: expected an integer >= 0, found -1"):
        ARX(2, 2, delay=-1).fit(u, u[:, 0])


# --------------------------------------------------------------------- tuning
def narx_system(u):
    """y_t = 0.5 y_{t−1} − 0.2 y_{t−2} + tanh(u_{t−1})."""
    y = np.zeros(u.size)
    for t in range(2, u.size):
        y[t] = 0.5 * y[t - 1] - 0.2 * y[t - 2] + math.tanh(u[t - 1])
    return y


def test_tune_free_run_returns_the_refitted_model_and_its_cost_surface():
    rng = np.random.default_rng(14)
    u = rng.uniform(-2.0, 2.0, 450)
    y = narx_system(u) + 0.01 * rng.standard_normal(u.size)
    model, surface = tune_free_run(NARX(2, 2), u[:300], y[:300], grid=3, refine=False,
                                   orders={"na": [1, 2]})
    assert isinstance(surface, CostSurface)
    frame = surface.to_frame()
    assert len(frame) == 2 * 3 * 3 and set(frame.na) == {1, 2}
    best = frame.loc[frame.cost.idxmin()]
    assert (model.na, model.gamma, model.sigma2) == (best.na, best.gamma, best.sigma2)
    assert model.na == 2                       # the true order: one lag of y cannot fit
    assert frame[frame.na == 1].cost.min() > 3 * frame[frame.na == 2].cost.min()
    gammas, sigma2s, costs = surface.grid(na=2)
    assert costs.shape == (3, 3) and np.nanmin(costs) == pytest.approx(best.cost)
    held = model.simulate(u[300:], y[300:302])
    assert nrmse(y[302:], held[2:]) < 0.1


def test_tune_free_run_searches_arx_orders_only():
    rng = np.random.default_rng(15)
    u = rng.standard_normal(300)
    y = second_order(u) + 0.01 * rng.standard_normal(300)
    model, surface = tune_free_run(ARX(delay=1), u, y, orders={"na": [1, 2], "nb": [2]})
    assert [row["na"] for row in surface.rows] == [1, 2]
    assert model.na == 2 and model.a_ == pytest.approx([1.2, -0.5], abs=0.02)


def test_the_cost_is_a_parameter_and_smoothing_prefers_a_broad_valley():
    # a cost written here: a broad valley at (γ, σ²) = (1e4, 1e1) and one lucky point at
    # (1e0, 1e-1), lower than the valley's floor but with bad neighbours.  Smoothed log10
    # costs (width 1 decade, by hand): about −1.21 at the valley, −1.12 at the lucky point
    def cost(estimator, pairs):
        g, s = math.log10(estimator.gamma), math.log10(estimator.sigma2)
        if abs(g) < 1e-9 and abs(s + 1) < 1e-9:
            return 0.03
        return 0.05 + 0.01 * ((g - 4) ** 2 + (s - 1) ** 2)

    u = np.random.default_rng(16).standard_normal(60)
    ranges = {"gamma": (1e0, 1e8), "sigma2": (1e-1, 1e3)}
    sharp, _ = tune_free_run(HammersteinLSSVM(1, 1), u, u, cost=cost, grid=5, refine=False,
                             **ranges)
    smooth, surface = tune_free_run(HammersteinLSSVM(1, 1), u, u, cost=cost, grid=5,
                                    smoothing=1.0, **ranges)
    assert (sharp.gamma, sharp.sigma2) == pytest.approx((1.0, 0.1))
    assert (smooth.gamma, smooth.sigma2) == pytest.approx((1e4, 1e1))
    assert surface.to_frame().smoothed_log10_cost.notna().all()


def test_free_run_cv_holds_out_whole_experiments_when_there_are_enough():
    rng = np.random.default_rng(17)
    us = [rng.standard_normal(100) for _ in range(3)]
    ys = [second_order(u) for u in us]
    pairs = [(u[:, None], y) for u, y in zip(us, ys)]
    # noise-free ARX data: a model of the true orders simulates every held-out drop exactly
    assert FreeRunCV(folds=3)(ARX(2, 2, delay=1), pairs) < 1e-20
    assert FreeRunCV(folds=3, mode="one-step")(ARX(1, 1, delay=1), pairs) > 1e-3
